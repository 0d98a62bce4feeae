// The data set's HDF5 file (layout in dataset.h and the README).
#include <H5Cpp.h>
#include <fmt/core.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "child_read.h"
#include "eitbench/bench/dataset.h"
#include "eitbench/bench/io.h"
#include "eitbench/jacobian/error.h"
#include "hdf5_attributes.h"
#include "wire.h"

namespace eitbench {
namespace {

constexpr int kFormatVersion = 1;
constexpr int kMaxCircles = 4;
// Deflate level 1: augmenting the quick set (64,687 samples) took 6.6 s for 76 MB, level 4 took
// 9.7 s for 65 MB. HDF5 compresses on one thread, so this is the file writer's bottleneck.
constexpr int kDeflateLevel = 1;
constexpr double kMaxBytes = 16e9;  // refuse data sets whose declared size could not be held

template <typename T>
const H5::PredType& h5_type();
template <>
const H5::PredType& h5_type<double>() {
  return H5::PredType::NATIVE_DOUBLE;
}
template <>
const H5::PredType& h5_type<float>() {
  return H5::PredType::NATIVE_FLOAT;
}
template <>
const H5::PredType& h5_type<int>() {
  return H5::PredType::NATIVE_INT;
}

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

 private:
  H5::DataSet set_;
  const H5::PredType& type_;
  std::vector<hsize_t> sample_;
  hsize_t rows_ = 0;
};

using detail::write_attribute;

class Reader {
 public:
  Reader(const std::string& path) : path_(path) {
    H5::Exception::dontPrint();
    if (!is_hdf5_file(path)) throw InputError(path, "", "not an HDF5 file (or unreadable)");
    try {
      file_ = H5::H5File(path, H5F_ACC_RDONLY);
    } catch (const H5::Exception& e) {
      throw InputError(path, "", "cannot open the HDF5 file: " + e.getDetailMsg());
    }
  }

  bool has(const std::string& name) const {
    return H5Lexists(file_.getId(), name.c_str(), H5P_DEFAULT) > 0;
  }

  // The data set `name` as T, checked to have `dims` (0 in dims: any size, reported back).
  template <typename T>
  std::vector<T> array(const std::string& name, std::vector<hsize_t>& dims) const {
    if (!has(name)) throw InputError(path_, name, "the data set is missing");
    try {
      H5::DataSet set = file_.openDataSet(name);
      H5::DataSpace space = set.getSpace();
      const int rank = space.getSimpleExtentNdims();
      std::vector<hsize_t> actual(rank);
      space.getSimpleExtentDims(actual.data());
      if (rank != static_cast<int>(dims.size())) fail(name, rank, dims.size(), actual);
      double elements = 1;
      for (int k = 0; k < rank; ++k) {
        if (dims[k] != 0 && dims[k] != actual[k]) fail(name, rank, dims.size(), actual);
        dims[k] = actual[k];
        elements *= static_cast<double>(actual[k]);
      }
      if (elements * sizeof(T) > kMaxBytes)
        throw InputError(path_, name, "declares " + shape(actual) + ", too large to read");
      const H5T_class_t cls = set.getTypeClass();
      if (cls != H5T_FLOAT && cls != H5T_INTEGER) throw InputError(path_, name, "is not numeric");
      std::vector<T> out(static_cast<std::size_t>(elements));
      if (!out.empty()) set.read(out.data(), h5_type<T>());
      return out;
    } catch (const H5::Exception& e) {
      throw InputError(path_, name, "cannot read: " + e.getDetailMsg());
    }
  }

  // A numeric attribute in [low, high], or `fallback` when it is absent and not `required`.
  double number(const std::string& name, double fallback, double low, double high,
                bool required = false) const {
    try {
      if (!file_.attrExists(name)) {
        if (required) throw InputError(path_, name, "the attribute is missing");
        return fallback;
      }
      const H5::Attribute a = scalar_attribute(name);
      if (a.getTypeClass() != H5T_FLOAT && a.getTypeClass() != H5T_INTEGER)
        throw InputError(path_, name, "is not a number");
      double v = 0;
      a.read(H5::PredType::NATIVE_DOUBLE, &v);
      if (!std::isfinite(v)) throw InputError(path_, name, "is NaN or infinite");
      if (v < low || v > high)
        throw InputError(path_, name, fmt::format("is {:g}, outside {:g} .. {:g}", v, low, high));
      return v;
    } catch (const H5::Exception& e) {
      throw InputError(path_, name, "cannot read: " + e.getDetailMsg());
    }
  }

  // A text attribute; "" when it is absent or not text (the texts are descriptions).
  std::string text(const std::string& name) const {
    try {
      if (!file_.attrExists(name)) return "";
      const H5::Attribute a = scalar_attribute(name);
      if (a.getTypeClass() != H5T_STRING) return "";
      std::string v;
      a.read(a.getStrType(), v);
      return v;
    } catch (const H5::Exception& e) {
      throw InputError(path_, name, "cannot read: " + e.getDetailMsg());
    }
  }

  std::uint64_t seed() const {
    try {
      if (!file_.attrExists("seed")) return 0;
      const H5::Attribute a = scalar_attribute("seed");
      if (a.getTypeClass() == H5T_STRING) return std::strtoull(text("seed").c_str(), nullptr, 10);
      if (a.getTypeClass() != H5T_INTEGER) throw InputError(path_, "seed", "is not an integer");
      std::uint64_t v = 0;
      a.read(H5::PredType::NATIVE_UINT64, &v);
      return v;
    } catch (const H5::Exception& e) {
      throw InputError(path_, "seed", "cannot read: " + e.getDetailMsg());
    }
  }

  const std::string& path() const { return path_; }

 private:
  static std::string shape(const std::vector<hsize_t>& dims) {
    std::string s;
    for (std::size_t k = 0; k < dims.size(); ++k) s += (k ? " x " : "") + std::to_string(dims[k]);
    return s.empty() ? "a scalar" : s;
  }
  // The attribute, checked to hold one value: reading an array into one would overrun it.
  H5::Attribute scalar_attribute(const std::string& name) const {
    H5::Attribute a = file_.openAttribute(name);
    if (a.getSpace().getSimpleExtentNpoints() != 1)
      throw InputError(path_, name, "must be a single value");
    return a;
  }
  [[noreturn]] void fail(const std::string& name, int, std::size_t,
                         const std::vector<hsize_t>& actual) const {
    throw InputError(path_, name,
                     "has shape " + shape(actual) + ", which does not fit the file's other data");
  }
  std::string path_;
  H5::H5File file_;
};

void check_finite(const Reader& r, const std::string& name, const double* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i]))
      throw InputError(r.path(), name, "value " + std::to_string(i) + " is NaN or infinite");
}

}  // namespace

std::string to_string(Split split) {
  switch (split) {
    case Split::train:
      return "train";
    case Split::validation:
      return "validation";
    case Split::test:
      return "test";
  }
  return "?";
}

std::vector<int> Dataset::indices(Split which) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < split.size(); ++i)
    if (split[i] == which) out.push_back(static_cast<int>(i));
  return out;
}

bool is_hdf5_file(const std::string& path) {
  H5E_BEGIN_TRY {
    return H5Fis_hdf5(path.c_str()) > 0;
  }
  H5E_END_TRY;
  return false;
}

struct DatasetWriter::Impl {
  H5::H5File file;
  std::unique_ptr<GrowingArray> differences, frames, split, labels, circles, circle_count;
  Eigen::Index frame_size = 0, difference_size = 0, pixels = 0;
};

DatasetWriter::DatasetWriter(const std::string& path, const Dataset& d, bool labels, bool circles)
    : impl_(std::make_unique<Impl>()), path_(path) {
  temp_ = temporary_path_for(path);
  try {
    H5::Exception::dontPrint();
    Impl& w = *impl_;
    w.file = H5::H5File(temp_, H5F_ACC_TRUNC);
    const int L = d.electrodes;
    w.frame_size = L * (L - 3);
    w.difference_size = w.frame_size / 2;
    w.pixels = static_cast<Eigen::Index>(d.image_size) * d.image_size;
    if (d.reference.size() != w.frame_size)
      throw InputError(path, "reference", "does not fit the electrode count");
    const hsize_t reference_size = static_cast<hsize_t>(w.frame_size);
    w.file
        .createDataSet("reference", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &reference_size))
        .write(d.reference.data(), H5::PredType::NATIVE_DOUBLE);
    w.differences = std::make_unique<GrowingArray>(
        w.file, "differences", H5::PredType::NATIVE_DOUBLE,
        std::vector<hsize_t>{static_cast<hsize_t>(w.difference_size)});
    w.frames =
        std::make_unique<GrowingArray>(w.file, "frames", H5::PredType::NATIVE_DOUBLE,
                                       std::vector<hsize_t>{static_cast<hsize_t>(w.frame_size)});
    w.split = std::make_unique<GrowingArray>(w.file, "split", H5::PredType::NATIVE_INT,
                                             std::vector<hsize_t>{});
    const hsize_t side = static_cast<hsize_t>(d.image_size);
    if (labels)
      w.labels = std::make_unique<GrowingArray>(w.file, "labels", H5::PredType::NATIVE_FLOAT,
                                                std::vector<hsize_t>{side, side});
    if (circles) {
      w.circles = std::make_unique<GrowingArray>(
          w.file, "circles", H5::PredType::NATIVE_DOUBLE,
          std::vector<hsize_t>{static_cast<hsize_t>(kMaxCircles), 4});
      w.circle_count = std::make_unique<GrowingArray>(
          w.file, "circle_count", H5::PredType::NATIVE_INT, std::vector<hsize_t>{});
    }
    H5::H5File& file = w.file;
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
    write_attribute(file, "protocol", "adjacent drive, adjacent measurement (SPEC section 1)");
    write_attribute(file, "frame_order", "rotating");
    write_attribute(file, "difference_layout",
                    "reduced: v(d,m), d < m, m - d >= 2, (d,m) != (0,L-1), row-major");
    write_attribute(file, "program", d.program);
    write_attribute(file, "augmentation", d.augmentation);
    write_attribute(file, "format_version", static_cast<long long>(kFormatVersion));
  } catch (const H5::Exception& e) {
    impl_.reset();
    std::remove(temp_.c_str());
    throw InputError(path, "", "cannot create the HDF5 file: " + e.getDetailMsg());
  } catch (...) {
    impl_.reset();
    std::remove(temp_.c_str());
    throw;
  }
}

DatasetWriter::~DatasetWriter() {
  if (committed_) return;
  impl_.reset();  // closes the file
  std::remove(temp_.c_str());
}

void DatasetWriter::append(const Dataset& b) {
  Impl& w = *impl_;
  const hsize_t n = static_cast<hsize_t>(b.size());
  if (b.differences.cols() != w.difference_size || b.frames.cols() != w.frame_size ||
      b.frames.rows() != b.differences.rows() || b.split.size() != n ||
      (w.labels && b.labels.cols() != w.pixels) || (w.circles && b.circles.size() != n))
    throw std::invalid_argument("DatasetWriter::append: the block's shapes do not match the file");
  try {
    w.differences->append(b.differences.data(), n);
    w.frames->append(b.frames.data(), n);
    std::vector<int> split(n);
    for (hsize_t i = 0; i < n; ++i) split[i] = static_cast<int>(b.split[i]);
    w.split->append(split.data(), n);
    if (w.labels) {
      const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> labels =
          b.labels.cast<float>();
      w.labels->append(labels.data(), n);
    }
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
      w.circles->append(table.data(), n);
      w.circle_count->append(count.data(), n);
    }
  } catch (const H5::Exception& e) {
    throw InputError(path_, "", "HDF5 write failed (disk full?): " + e.getDetailMsg());
  }
  rows_ += static_cast<long long>(n);
}

void DatasetWriter::commit() {
  try {
    impl_->file.close();
  } catch (const H5::Exception& e) {
    throw InputError(path_, "", "HDF5 write failed: " + e.getDetailMsg());
  }
  impl_.reset();
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    std::remove(temp_.c_str());
    throw InputError(path_, "", "cannot move the finished file into place");
  }
  committed_ = true;
}

void write_dataset(const std::string& path, const Dataset& d) {
  DatasetWriter writer(path, d, d.has_labels(), !d.circles.empty());
  writer.append(d);
  writer.commit();
}

namespace {

Dataset read_dataset_checked(const std::string& path) {
  const Reader r(path);
  Dataset d;
  constexpr double kHuge = 1e300;
  const double electrodes = r.number("electrodes", 0, 4, 256, true);
  if (electrodes != std::floor(electrodes))
    throw InputError(path, "electrodes", "must be a whole number from 4 to 256");
  d.electrodes = static_cast<int>(electrodes);
  const int L = d.electrodes;
  const hsize_t full = static_cast<hsize_t>(L * (L - 3)), reduced = full / 2;
  d.radius = r.number("radius", 1.0, 0, kHuge);
  d.background = r.number("background_conductivity", 0.05, 0, kHuge);
  d.contact_impedance = r.number("contact_impedance", 0.01, -kHuge, kHuge);
  d.current = r.number("current", 1.0, -kHuge, kHuge);
  d.electrode_coverage = r.number("electrode_coverage", 0.5, -kHuge, kHuge);
  d.image_size = static_cast<int>(r.number("image_size", 64, 1, 4096));
  if (!(d.radius > 0) || !(d.background > 0))
    throw InputError(path, "attributes", "radius and background_conductivity must be positive");
  d.seed = r.seed();
  d.preset = r.text("preset");
  d.simulation_mesh = r.text("simulation_mesh");
  d.simulation_triangles = static_cast<int>(r.number("simulation_triangles", 0, 0, 1e9));
  d.program = r.text("program");
  d.augmentation = r.text("augmentation").empty() ? "none" : r.text("augmentation");

  std::vector<hsize_t> dims{0, reduced};
  const std::vector<double> differences = r.array<double>("differences", dims);
  const hsize_t n = dims[0];
  if (n == 0) throw InputError(path, "differences", "the data set is empty");
  check_finite(r, "differences", differences.data(), differences.size());
  d.differences = Eigen::Map<const SampleMatrix>(differences.data(), static_cast<Eigen::Index>(n),
                                                 static_cast<Eigen::Index>(reduced));
  dims = {n, full};
  const std::vector<double> frames = r.array<double>("frames", dims);
  check_finite(r, "frames", frames.data(), frames.size());
  d.frames = Eigen::Map<const SampleMatrix>(frames.data(), static_cast<Eigen::Index>(n),
                                            static_cast<Eigen::Index>(full));
  dims = {full};
  const std::vector<double> reference = r.array<double>("reference", dims);
  check_finite(r, "reference", reference.data(), reference.size());
  d.reference =
      Eigen::Map<const Eigen::VectorXd>(reference.data(), static_cast<Eigen::Index>(full));
  dims = {n};
  for (int s : r.array<int>("split", dims)) {
    if (s < 0 || s > 2)
      throw InputError(path, "split", "values must be 0 (train), 1 (validation) or 2 (test)");
    d.split.push_back(static_cast<Split>(s));
  }
  if (r.has("labels")) {
    const hsize_t side = static_cast<hsize_t>(d.image_size);
    dims = {n, side, side};
    const std::vector<float> labels = r.array<float>("labels", dims);
    d.labels =
        Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            labels.data(), static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(side * side))
            .cast<double>();
    if (!d.labels.allFinite()) throw InputError(path, "labels", "NaN or infinite values");
  }
  if (r.has("circles")) {
    dims = {n, static_cast<hsize_t>(kMaxCircles), 4};
    const std::vector<double> table = r.array<double>("circles", dims);
    dims = {n};
    const std::vector<int> count = r.array<int>("circle_count", dims);
    d.circles.resize(n);
    for (hsize_t i = 0; i < n; ++i) {
      if (count[i] < 0 || count[i] > kMaxCircles)
        throw InputError(path, "circle_count", "values must lie in 0..4");
      for (int k = 0; k < count[i]; ++k) {
        const double* c = &table[(i * kMaxCircles + k) * 4];
        if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !(c[2] > 0) || !(c[3] > 0))
          throw InputError(
              path, "circles",
              "sample " + std::to_string(i) + ", circle " + std::to_string(k) + " is invalid");
        d.circles[i].push_back({c[0], c[1], c[2], c[3]});
      }
    }
  }
  return d;
}

// A data set as the child that read it hands it over (child_read.h).
std::string to_wire(const Dataset& d) {
  detail::WireWriter w;
  w.pod(d.electrodes), w.pod(d.radius), w.pod(d.background), w.pod(d.contact_impedance);
  w.pod(d.current), w.pod(d.electrode_coverage), w.pod(d.image_size), w.pod(d.seed);
  w.text(d.preset), w.text(d.simulation_mesh), w.pod(d.simulation_triangles);
  w.text(d.program), w.text(d.augmentation);
  w.matrix(d.reference), w.matrix(d.frames), w.matrix(d.differences), w.matrix(d.labels);
  w.pod<std::uint64_t>(d.circles.size());
  for (const auto& list : d.circles) w.vector(list);
  w.vector(d.split);
  return w.take();
}

Dataset from_wire(const std::string& bytes) {
  detail::WireReader r(bytes);
  Dataset d;
  d.electrodes = r.pod<int>(), d.radius = r.pod<double>(), d.background = r.pod<double>();
  d.contact_impedance = r.pod<double>(), d.current = r.pod<double>();
  d.electrode_coverage = r.pod<double>(), d.image_size = r.pod<int>();
  d.seed = r.pod<std::uint64_t>();
  d.preset = r.text(), d.simulation_mesh = r.text(), d.simulation_triangles = r.pod<int>();
  d.program = r.text(), d.augmentation = r.text();
  d.reference = r.matrix<Eigen::VectorXd>();
  d.frames = r.matrix<SampleMatrix>(), d.differences = r.matrix<SampleMatrix>();
  d.labels = r.matrix<SampleMatrix>();
  d.circles.resize(r.pod<std::uint64_t>());
  for (auto& list : d.circles) list = r.vector<Circle>();
  d.split = r.vector<Split>();
  return d;
}

}  // namespace

Dataset read_dataset(const std::string& path) {
  // libhdf5 may crash or hang on a corrupt file: it reads the file in a child (child_read.h).
  return from_wire(detail::read_in_child(path, [&path] {
    try {
      return to_wire(read_dataset_checked(path));
    } catch (const H5::Exception& e) {  // anything the readers above do not name more precisely
      throw InputError(path, "", "cannot read the HDF5 file: " + e.getDetailMsg());
    }
  }));
}

}  // namespace eitbench
