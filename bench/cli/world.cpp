#include "world.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <initializer_list>
#include <stdexcept>
#include <thread>

#ifdef EITBENCH_HAVE_MPI
// The C API only: Open MPI's and MPICH's headers otherwise pull in their removed C++ bindings.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace eitbench::cli {
namespace {

World joined;
bool met = false;  // every rank has been through on_every_rank's collective

#ifdef EITBENCH_HAVE_MPI
// Open MPI, MPICH and Slurm's PMI each say so in the environment of the processes they start.
// Without one, MPI_Init would start a singleton, slow and noisy in a container, for nothing.
bool under_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

void finalize() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}
#endif

}  // namespace

World join_world([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#ifdef EITBENCH_HAVE_MPI
  if (under_launcher()) {
    int provided = 0;  // TBB and LibTorch start threads; only this one calls MPI
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &joined.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &joined.size);
    std::atexit(finalize);
  }
#endif
  return joined;
}

World world() {
  return joined;
}

bool all_ranks(bool ok) {
#ifdef EITBENCH_HAVE_MPI
  if (joined.parallel()) {
    // Non-blocking, polled gently: a rank that finished first would otherwise spin a core in a
    // blocking reduction while the others still work on theirs.
    int mine = ok ? 1 : 0, every = 0, done = 0;
    MPI_Request request;
    MPI_Iallreduce(&mine, &every, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD, &request);
    for (MPI_Test(&request, &done, MPI_STATUS_IGNORE); !done;
         MPI_Test(&request, &done, MPI_STATUS_IGNORE))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return every == 1;
  }
#endif
  return ok;
}

void on_every_rank(const std::function<void()>& work, const std::string& after_failure) {
  std::exception_ptr failure;
  try {
    work();
  } catch (...) {
    failure = std::current_exception();
  }
  const bool every_rank = all_ranks(!failure);
  met = true;  // no rank waits for another any more: errors from here end this rank alone
  if (failure) std::rethrow_exception(failure);
  if (!every_rank)
    throw std::runtime_error("rank " + std::to_string(joined.rank) +
                             ": another rank failed (its message is printed beside this one); " +
                             after_failure);
}

void abort_world([[maybe_unused]] int code) {
#ifdef EITBENCH_HAVE_MPI
  if (joined.parallel() && !met) {
    std::fflush(stdout), std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
  }
#endif
}

bool built_with_mpi() {
#ifdef EITBENCH_HAVE_MPI
  return true;
#else
  return false;
#endif
}

}  // namespace eitbench::cli
