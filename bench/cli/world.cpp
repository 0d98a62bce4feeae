#include "world.h"

#include <cstdlib>
#include <exception>
#include <initializer_list>
#include <stdexcept>

#ifdef EITBENCH_HAVE_MPI
// The C API only: Open MPI's and MPICH's headers otherwise pull in their removed C++ bindings.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace eitbench::cli {
namespace {

World joined;

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
    MPI_Init(&argc, &argv);
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
    int mine = ok ? 1 : 0, every = 0;
    MPI_Allreduce(&mine, &every, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
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
  if (failure) std::rethrow_exception(failure);
  if (!every_rank)
    throw std::runtime_error("rank " + std::to_string(joined.rank) +
                             ": another rank failed (its message is printed beside this one); " +
                             after_failure);
}

bool built_with_mpi() {
#ifdef EITBENCH_HAVE_MPI
  return true;
#else
  return false;
#endif
}

}  // namespace eitbench::cli
