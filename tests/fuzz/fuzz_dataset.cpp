// Data sets are HDF5 files, read by path through libhdf5: the input goes to a file first. The
// reader runs libhdf5 in a child process (child_read.h); its limit here stays under the smoke
// driver's 10 s, so that a libhdf5 hang is the InputError it becomes for users, not a finding.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/child_read.h"
#include "fuzz_target.h"

namespace {
// The scratch file is removed when the fuzzer exits, so that runs leave nothing in /tmp.
struct Scratch {
  std::string path = "/tmp/eitbench_fuzz_dataset_" + std::to_string(::getpid()) + ".h5";
  Scratch() { eitbench::detail::set_child_read_base_limit(3); }
  ~Scratch() { std::remove(path.c_str()); }
};

const std::string& scratch_path() {
  static const Scratch scratch;
  return scratch.path;
}
}  // namespace

EITBENCH_FUZZ_TARGET({
  std::ofstream(scratch_path(), std::ios::binary | std::ios::trunc) << bytes;
  eitbench::read_dataset(scratch_path());
})
