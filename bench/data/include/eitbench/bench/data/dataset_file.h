#pragma once
// A data set's HDF5 file (layout in dataset.h): written atomically or streamed block by block, read
// in a child process (libhdf5 is not safe on corrupt files) and checked field by field.
#include <memory>
#include <string>

#include "eitbench/bench/data/dataset.h"

namespace eitbench {

// Writes atomically (temporary, then rename); chunked and compressed.
void write_dataset(const std::string& path, const Dataset& data);

// Writes a data set block by block, for sets larger than memory: the attributes and the
// reference come from `header`, the samples from each append(). Nothing appears at `path` until
// commit(); a writer destroyed before that removes its temporary file.
class DatasetWriter {
 public:
  DatasetWriter(const std::string& path, const Dataset& header, bool labels, bool circles);
  ~DatasetWriter();
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;

  void append(const Dataset& block);  // rows of frames, differences, split, labels, circles
  void commit();
  long long size() const { return rows_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_, temp_;
  long long rows_ = 0;
  bool committed_ = false;
};
// Reads and checks shapes, values and attributes; InputError names the file and the data set. A
// shard (Dataset::shard) is refused: it is part of a set.
Dataset read_dataset(const std::string& path);
// The same, a shard accepted (merge, info).
Dataset read_dataset_or_shard(const std::string& path);
// True when the path is a regular file with HDF5's signature (whatever its name); false for
// FIFOs, devices and folders, which it does not open.
bool is_hdf5_file(const std::string& path);

}  // namespace eitbench
