#pragma once
// The processes this one runs beside (docs/scaling.md). Under an MPI launcher (mpirun, srun) the
// tool joins the MPI world and a command shards its work by rank; started on its own, it is rank 0
// of a world of one and never touches MPI. A build without MPI is always a world of one.
#include <functional>
#include <string>

namespace eitbench::cli {

struct World {
  int rank = 0, size = 1;
  bool parallel() const { return size > 1; }
};

// Joins the MPI world when a launcher started this process (its environment says so), finalised
// at exit; else a world of one. Call once, from main, before parsing.
World join_world(int& argc, char**& argv);
// The world join_world found (a world of one before it).
World world();
// True on every rank when `ok` is true on every rank: a collective, so every rank must reach it,
// whatever happened to it before.
bool all_ranks(bool ok);
// Runs this rank's `work`, then meets every other rank (all_ranks): rethrows this rank's own
// failure; throws "another rank failed" (with `after_failure`, what the user can do) when only
// another's work failed; returns when every rank's work finished.
void on_every_rank(const std::function<void()>& work, const std::string& after_failure);
// Ends every rank of a parallel world at once (MPI_Abort) after this one's error was printed, so
// that a rank that failed before the collective of on_every_rank does not leave the others
// waiting in it for ever; nothing in a world of one, or once every rank has been through it.
void abort_world(int code);
// Whether this build can join an MPI world.
bool built_with_mpi();

}  // namespace eitbench::cli
