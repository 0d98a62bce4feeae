// The data set's HDF5 file, written whole or streamed block by block (layout in dataset.h).
#include <H5Cpp.h>
#include <fmt/core.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "dataset_hdf5.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/child_write.h"
#include "eitbench/bench/io/hdf5_attributes.h"
#include "eitbench/bench/io/output_path.h"
#include "eitbench/bench/io/wire.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

using detail::h5_type;
using detail::kDatasetFormatVersion;
using detail::kMaxCircles;
// Deflate level 1: augmenting the quick set (64,687 samples) took 6.6 s for 76 MB, level 4 took
// 9.7 s for 65 MB. HDF5 compresses on one thread, so this is the file writer's bottleneck.
constexpr int kDeflateLevel = 1;

// An extendible C-order array whose first dimension grows as samples are appended; chunked by
// whole samples, shuffled and compressed.
class GrowingArray {
 public:
  GrowingArray(H5::H5File& file, const std::string& name, const H5::PredType& type,
               std::vector<hsize_t> sample_dims)
      : type_(type), sample_(std::move(sample_dims)) {
    std::vector<hsize_t> dims{0}, max{H5S_UNLIMITED}, chunk{1};
    hsize_t per_sample = 1;
    for (hsize_t d : sample_)
      dims.push_back(d), max.push_back(d), chunk.push_back(d), per_sample *= d;
    chunk[0] = std::max<hsize_t>(1, (1u << 18) / std::max<hsize_t>(1, per_sample));
    H5::DSetCreatPropList props;
    props.setChunk(static_cast<int>(chunk.size()), chunk.data());
    props.setShuffle();
    props.setDeflate(kDeflateLevel);
    set_ = file.createDataSet(
        name, type, H5::DataSpace(static_cast<int>(dims.size()), dims.data(), max.data()), props);
  }
  void append(const void* data, hsize_t rows) {
    if (rows == 0) return;
    std::vector<hsize_t> size{rows_ + rows}, start{rows_}, count{rows};
    for (hsize_t d : sample_) size.push_back(d), start.push_back(0), count.push_back(d);
    set_.extend(size.data());
    H5::DataSpace file_space = set_.getSpace();
    file_space.selectHyperslab(H5S_SELECT_SET, count.data(), start.data());
    const H5::DataSpace memory(static_cast<int>(count.size()), count.data());
    set_.write(data, type_, memory, file_space);
    rows_ += rows;
  }
  void close() { set_.close(); }  // throws where the flush fails, unlike the destructor

 private:
  H5::DataSet set_;
  const H5::PredType& type_;
  std::vector<hsize_t> sample_;
  hsize_t rows_ = 0;
};

using detail::write_attribute;
using FloatRows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The file as the writing child holds it (child_write.h): this process never opens it.
struct OpenFile {
  H5::H5File file;
  std::unique_ptr<GrowingArray> differences, frames, split, labels, circles, circle_count;
};

// A press set's touches, whole: they come with the set, never in streamed blocks.
void write_touches(H5::H5File& file, const Dataset& d) {
  using detail::kMaxCircles;
  const hsize_t n = d.touches.size();
  std::vector<double> table(n * kMaxCircles * 3, std::numeric_limits<double>::quiet_NaN());
  std::vector<int> count(n);
  for (hsize_t i = 0; i < n; ++i) {
    count[i] = static_cast<int>(std::min<std::size_t>(d.touches[i].size(), kMaxCircles));
    for (int k = 0; k < count[i]; ++k) {
      const PressTouch& t = d.touches[i][static_cast<std::size_t>(k)];
      double* row = &table[(i * kMaxCircles + k) * 3];
      row[0] = t.x, row[1] = t.y, row[2] = t.size;
    }
  }
  const hsize_t dims[3] = {n, static_cast<hsize_t>(kMaxCircles), 3};
  detail::write_closed(
      file.createDataSet("touches", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(3, dims)),
      table.data(), H5::PredType::NATIVE_DOUBLE);
  detail::write_closed(
      file.createDataSet("touch_count", H5::PredType::NATIVE_INT, H5::DataSpace(1, &n)),
      count.data(), H5::PredType::NATIVE_INT);
}

void create_arrays(OpenFile& w, const Dataset& d, bool labels, bool circles) {
  const MeasurementProtocol protocol = measurement_protocol(d);
  const hsize_t frame_size = static_cast<hsize_t>(protocol.size());
  std::vector<int> channels;
  for (const Channel& c : protocol.channels())
    channels.insert(channels.end(), {c.drive_plus, c.drive_minus, c.meas_plus, c.meas_minus});
  const hsize_t channel_dims[2] = {frame_size, 4};
  detail::write_closed(w.file.createDataSet("protocol_channels", H5::PredType::NATIVE_INT,
                                            H5::DataSpace(2, channel_dims)),
                       channels.data(), H5::PredType::NATIVE_INT);
  detail::write_closed(
      w.file.createDataSet("reference", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &frame_size)),
      d.reference.data(), H5::PredType::NATIVE_DOUBLE);
  if (!d.touches.empty()) write_touches(w.file, d);
  if (d.references.rows() > 0) {
    const hsize_t dims[2] = {static_cast<hsize_t>(d.references.rows()), frame_size};
    detail::write_closed(
        w.file.createDataSet("references", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(2, dims)),
        d.references.data(), H5::PredType::NATIVE_DOUBLE);
  }
  if (!d.sensor_mesh.empty()) {
    const hsize_t bytes = d.sensor_mesh.size();
    detail::write_closed(
        w.file.createDataSet("sensor_mesh", H5::PredType::NATIVE_UCHAR, H5::DataSpace(1, &bytes)),
        d.sensor_mesh.data(), H5::PredType::NATIVE_UCHAR);
  }
  w.differences = std::make_unique<GrowingArray>(
      w.file, "differences", H5::PredType::NATIVE_DOUBLE,
      std::vector<hsize_t>{static_cast<hsize_t>(protocol.input_size())});
  w.frames = std::make_unique<GrowingArray>(w.file, "frames", H5::PredType::NATIVE_DOUBLE,
                                            std::vector<hsize_t>{frame_size});
  w.split = std::make_unique<GrowingArray>(w.file, "split", H5::PredType::NATIVE_INT,
                                           std::vector<hsize_t>{});
  const hsize_t side = static_cast<hsize_t>(d.image_size);
  if (labels)
    w.labels = std::make_unique<GrowingArray>(w.file, "labels", H5::PredType::NATIVE_FLOAT,
                                              std::vector<hsize_t>{side, side});
  if (circles) {
    w.circles =
        std::make_unique<GrowingArray>(w.file, "circles", H5::PredType::NATIVE_DOUBLE,
                                       std::vector<hsize_t>{static_cast<hsize_t>(kMaxCircles), 4});
    w.circle_count = std::make_unique<GrowingArray>(
        w.file, "circle_count", H5::PredType::NATIVE_INT, std::vector<hsize_t>{});
  }
}

void write_attributes(H5::H5File& file, const Dataset& d) {
  write_attribute(file, "electrodes", static_cast<long long>(d.electrodes));
  write_attribute(file, "radius", d.radius);
  write_attribute(file, "background_conductivity", d.background);
  write_attribute(file, "contact_impedance", d.contact_impedance);
  write_attribute(file, "current", d.current);
  write_attribute(file, "electrode_coverage", d.electrode_coverage);
  write_attribute(file, "image_size", static_cast<long long>(d.image_size));
  write_attribute(file, "seed", d.seed);
  write_attribute(file, "preset", d.preset);
  write_attribute(file, "simulation_mesh", d.simulation_mesh);
  write_attribute(file, "simulation_triangles", static_cast<long long>(d.simulation_triangles));
  const MeasurementProtocol protocol = measurement_protocol(d);
  write_attribute(file, "protocol", protocol.name());
  write_attribute(file, "magnitude", static_cast<long long>(protocol.magnitude()));
  write_attribute(file, "frame_order", "the rows of /protocol_channels");
  write_attribute(file, "difference_layout",
                  protocol.reciprocal()
                      ? "reciprocity-reduced: the first channel of each reciprocal pair, in order"
                      : "every channel (the protocol is not reciprocal)");
  write_attribute(file, "program", d.program);
  write_attribute(file, "augmentation", d.augmentation);
  if (!d.sensor_mesh.empty()) write_attribute(file, "sensor_group", d.sensor_group);
  if (!d.touches.empty()) write_attribute(file, "touch_size", d.touch_size);
  if (!d.shard.whole()) {
    write_attribute(file, "shard_index", static_cast<long long>(d.shard.index));
    write_attribute(file, "shard_count", static_cast<long long>(d.shard.count));
    write_attribute(file, "shard_first", d.shard.first);
    write_attribute(file, "shard_total", d.shard.total);
  }
  write_attribute(file, "format_version", static_cast<long long>(kDatasetFormatVersion));
}

// A block as the child receives it: rows, then each array in the file's own element type.
void append_block(OpenFile& w, const std::string& bytes) {
  detail::WireReader r(bytes);
  const hsize_t n = r.pod<std::uint64_t>();
  w.differences->append(r.matrix<SampleMatrix>().data(), n);
  w.frames->append(r.matrix<SampleMatrix>().data(), n);
  w.split->append(r.vector<int>().data(), n);
  if (w.labels) w.labels->append(r.matrix<FloatRows>().data(), n);
  if (w.circles) {
    w.circles->append(r.vector<double>().data(), n);
    w.circle_count->append(r.vector<int>().data(), n);
  }
}

// Every array first: a file closes (and is flushed) only when nothing in it is open.
void close(OpenFile& w) {
  for (auto* a : {&w.differences, &w.frames, &w.split, &w.labels, &w.circles, &w.circle_count})
    if (*a) (*a)->close();
  w.file.close();
}

// Runs a step of the child's work, turning libhdf5's exceptions into the writer's message.
template <typename F>
void in_hdf5(const std::string& path, const std::string& what, F&& step) {
  try {
    step();
  } catch (const H5::Exception& e) {
    throw InputError(path, "", what + ": " + e.getDetailMsg());
  }
}

}  // namespace

struct DatasetWriter::Impl {
  std::unique_ptr<detail::ChildWriter> child;
  Eigen::Index frame_size = 0, difference_size = 0, pixels = 0;
  bool labels = false, circles = false;
};

DatasetWriter::DatasetWriter(const std::string& path, const Dataset& d, bool labels, bool circles)
    : impl_(std::make_unique<Impl>()), path_(path) {
  Impl& w = *impl_;
  const MeasurementProtocol protocol = measurement_protocol(d);
  w.frame_size = protocol.size();
  w.difference_size = protocol.input_size();
  w.pixels = static_cast<Eigen::Index>(d.image_size) * d.image_size;
  w.labels = labels, w.circles = circles;
  if (d.reference.size() != w.frame_size)
    throw InputError(path, "reference", "does not fit the " + protocol.name() + " protocol");
  if (!d.touches.empty() && d.touches.size() != static_cast<std::size_t>(d.size()))
    throw std::invalid_argument(
        "DatasetWriter: a press set's touches come whole, one list a frame");
  if (d.references.rows() > 0 &&
      (d.references.rows() != d.size() || d.references.cols() != w.frame_size))
    throw std::invalid_argument("DatasetWriter: paired references come whole, one frame a frame");
  temp_ = temporary_path_for(path);
  auto file = std::make_shared<OpenFile>();  // filled in the child, which has its own copy
  const std::string temp = temp_;
  w.child = std::make_unique<detail::ChildWriter>(
      path,
      [&d, file, temp, path, labels, circles] {  // runs in the child, at once: `d` is alive
        H5::Exception::dontPrint();
        in_hdf5(path, "cannot create the HDF5 file", [&] {
          file->file = H5::H5File(temp, H5F_ACC_TRUNC);
          create_arrays(*file, d, labels, circles);
          write_attributes(file->file, d);
        });
      },
      [=](const std::string& block) {
        in_hdf5(path, "HDF5 write failed (disk full?)", [&] { append_block(*file, block); });
      },
      [=] { in_hdf5(path, "HDF5 write failed", [&] { close(*file); }); });
}

DatasetWriter::~DatasetWriter() {
  if (committed_) return;
  impl_.reset();  // the child abandons the file
  std::remove(temp_.c_str());
}

void DatasetWriter::append(const Dataset& b) {
  Impl& w = *impl_;
  const hsize_t n = static_cast<hsize_t>(b.size());
  if (b.differences.cols() != w.difference_size || b.frames.cols() != w.frame_size ||
      b.frames.rows() != b.differences.rows() || b.split.size() != n ||
      (w.labels && b.labels.cols() != w.pixels) || (w.circles && b.circles.size() != n))
    throw std::invalid_argument("DatasetWriter::append: the block's shapes do not match the file");
  detail::WireWriter out;
  out.pod<std::uint64_t>(n);
  out.matrix(b.differences), out.matrix(b.frames);
  std::vector<int> split(n);
  for (hsize_t i = 0; i < n; ++i) split[i] = static_cast<int>(b.split[i]);
  out.vector(split);
  if (w.labels) out.matrix(FloatRows(b.labels.cast<float>()));
  if (w.circles) {
    std::vector<double> table(n * kMaxCircles * 4, std::numeric_limits<double>::quiet_NaN());
    std::vector<int> count(n);
    for (hsize_t i = 0; i < n; ++i) {
      count[i] = static_cast<int>(std::min<std::size_t>(b.circles[i].size(), kMaxCircles));
      for (int k = 0; k < count[i]; ++k) {
        const Circle& c = b.circles[i][k];
        double* row = &table[(i * kMaxCircles + k) * 4];
        row[0] = c.x, row[1] = c.y, row[2] = c.r, row[3] = c.conductivity;
      }
    }
    out.vector(table), out.vector(count);
  }
  try {
    w.child->send(out.take());
  } catch (const InputError&) {
    std::remove(temp_.c_str());
    throw;
  }
  rows_ += static_cast<long long>(n);
}

void DatasetWriter::commit() {
  try {
    impl_->child->finish();
  } catch (const InputError&) {
    std::remove(temp_.c_str());
    throw;
  }
  impl_.reset();
  if (std::rename(temp_.c_str(), output_target(path_).c_str()) != 0) {
    std::remove(temp_.c_str());
    throw InputError(path_, "", "cannot move the finished file into place");
  }
  committed_ = true;
}

void write_dataset(const std::string& path, const Dataset& d) {
  DatasetWriter writer(path, d, d.has_labels(), !d.circles.empty());
  constexpr Eigen::Index kBlock = 1024;  // bounds the copy each block makes on its way
  for (Eigen::Index at = 0; at < d.size(); at += kBlock) {
    const Eigen::Index n = std::min<Eigen::Index>(kBlock, d.size() - at);
    Dataset b;
    b.differences = d.differences.middleRows(at, n);
    b.frames = d.frames.middleRows(at, n);
    if (d.has_labels()) b.labels = d.labels.middleRows(at, n);
    b.split.assign(d.split.begin() + at, d.split.begin() + at + n);
    if (!d.circles.empty()) b.circles.assign(d.circles.begin() + at, d.circles.begin() + at + n);
    writer.append(b);
  }
  writer.commit();
}
}  // namespace eitbench
