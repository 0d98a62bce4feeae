#pragma once
// How much memory a file from outside may make eitbench allocate. One rule serves every reader
// (Gmsh, CSV, NPY/NPZ, MAT v5 and v7.3, the HDF5 data set), and every check runs on the sizes a
// file declares, before anything is allocated:
//
//  1. A cap on what one file decodes into, summed over its arrays: 2 GiB unless the environment
//     variable EITBENCH_READ_LIMIT sets another (bytes, or a number with KiB, MiB or GiB).
//  2. Plain storage (CSV, NPY, uncompressed MAT v5, Gmsh): every declared value must be backed by
//     bytes present in the file, so memory stays within a fixed multiple of the file's size.
//  3. Compressed storage (NPZ deflate, MAT v5 miCOMPRESSED, HDF5 chunks): a declared size may be
//     at most kMaxInflation times the bytes stored for it. Deflate cannot do better, so only a
//     lie, or HDF5 storage that was never written (fill values), goes past it.
//
// A refusal is an InputError naming the file, the field, the declared size and the limit.
#include <cstdint>
#include <string>

namespace eitbench {

// Deflate's largest ratio: a 258-byte match coded in two bits.
constexpr double kMaxInflation = 1032;

// The cap of rule 1, read from EITBENCH_READ_LIMIT at the first call. An unreadable value is an
// InputError naming the variable.
std::uint64_t read_limit_bytes();
// For tests: the cap from now on (0: read the environment again).
void set_read_limit_bytes(std::uint64_t bytes);

// "3.0 GB", "512 MiB": a size in a message.
std::string byte_size_text(double bytes);

// The running total of one file's decoded arrays against the cap.
class ReadBudget {
 public:
  explicit ReadBudget(std::string source);

  // `bytes` of memory that `field` declares (`declared` says how: "20 x 4096 x 4096 float32");
  // InputError when the file's total would pass the cap.
  void take(const std::string& field, double bytes, const std::string& declared = "");
  // The same for compressed storage, where `stored` bytes on disk hold `decoded` bytes: rule 3,
  // then take(field, in_memory). Stored sizes under 64 KiB of output are not checked for ratio.
  void take_compressed(const std::string& field, double decoded, double stored, double in_memory,
                       const std::string& declared = "");

  double used() const { return used_; }
  double left() const;
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  double limit_;
  double used_ = 0;
};

}  // namespace eitbench
