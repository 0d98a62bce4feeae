// The data set's HDF5 file, read in a child process and checked field by field.
#include <H5Cpp.h>
#include <fmt/core.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "dataset_hdf5.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/child_read.h"
#include "eitbench/bench/io/hdf5_attributes.h"
#include "eitbench/bench/io/wire.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"
#include "eitbench/jacobian/msh_io.h"
#include "eitbench/jacobian/read_budget.h"

namespace eitbench {
namespace {

using detail::h5_type;
using detail::kDatasetFormatVersion;
using detail::kMaxCircles;

class Reader {
 public:
  Reader(const std::string& path) : path_(path) {
    H5::Exception::dontPrint();
    require_input_file(path);
    if (!is_hdf5_file(path)) throw InputError(path, "", "not an HDF5 file (or unreadable)");
    try {
      file_ = H5::H5File(path, H5F_ACC_RDONLY);
    } catch (const H5::Exception& e) {
      throw InputError(path, "", "cannot open the HDF5 file: " + e.getDetailMsg());
    }
  }

  // The data set `name` holds integers (checked before its values are trusted as indices).
  bool integer(const std::string& name) const {
    return file_.openDataSet(name).getTypeClass() == H5T_INTEGER;
  }

  bool has(const std::string& name) const {
    return H5Lexists(file_.getId(), name.c_str(), H5P_DEFAULT) > 0;
  }

  // The data set `name`, checked to have `dims` (0 in dims: any size, reported back) and to fit
  // the memory rule (read_budget.h) as `in_memory_size` bytes a value, before anything is read.
  H5::DataSet checked_set(const std::string& name, std::vector<hsize_t>& dims,
                          std::size_t in_memory_size) {
    if (!has(name)) throw InputError(path_, name, "the data set is missing");
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
    const H5T_class_t cls = set.getTypeClass();
    if (cls != H5T_FLOAT && cls != H5T_INTEGER) throw InputError(path_, name, "is not numeric");
    // Declared against stored bytes: chunks never written (fill values) store nothing.
    budget_.take_compressed(name, elements * set.getDataType().getSize(),
                            static_cast<double>(set.getStorageSize()), elements * in_memory_size,
                            shape(actual) + " values");
    return set;
  }

  // The data set `name` as T (see checked_set).
  template <typename T>
  std::vector<T> array(const std::string& name, std::vector<hsize_t>& dims) {
    try {
      const H5::DataSet set = checked_set(name, dims, sizeof(T));
      std::vector<T> out(static_cast<std::size_t>(count(dims)));
      if (!out.empty()) set.read(out.data(), h5_type<T>());
      return out;
    } catch (const H5::Exception& e) {
      throw InputError(path_, name, "cannot read: " + e.getDetailMsg());
    }
  }

  // The data set `name` as rows of `matrix`, read in place (labels: the largest array).
  void rows(const std::string& name, std::vector<hsize_t>& dims, SampleMatrix& matrix) {
    try {
      const H5::DataSet set = checked_set(name, dims, sizeof(double));
      const double n = count(dims);
      matrix.resize(static_cast<Eigen::Index>(dims[0]),
                    static_cast<Eigen::Index>(dims[0] ? n / static_cast<double>(dims[0]) : 0));
      if (matrix.size()) set.read(matrix.data(), H5::PredType::NATIVE_DOUBLE);
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
  static double count(const std::vector<hsize_t>& dims) {
    double n = 1;
    for (hsize_t d : dims) n *= static_cast<double>(d);
    return n;
  }
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
  ReadBudget budget_{path_};
};

// The most channels a stored protocol may list: about 8,000 times a 16-electrode board's, and a
// bound on what building it (an index of every channel) takes.
constexpr hsize_t kMaxChannels = hsize_t{1} << 20;

void check_finite(const Reader& r, const std::string& name, const double* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i]))
      throw InputError(r.path(), name, "value " + std::to_string(i) + " is NaN or infinite");
}

// A press set's touches: at most 4 a frame, each centre a finite point inside the disk (a sensor
// mesh's set is checked against its mesh where it is used), each size positive or NaN.
void read_touches(Reader& r, const std::string& path, hsize_t n, Dataset& d) {
  std::vector<hsize_t> dims{n, static_cast<hsize_t>(kMaxCircles), 3};
  const std::vector<double> table = r.array<double>("touches", dims);
  dims = {n};
  const std::vector<int> count = r.array<int>("touch_count", dims);
  d.touch_size = r.text("touch_size");
  if (d.touch_size != "" && d.touch_size != "radius" && d.touch_size != "depth")
    throw InputError(path, "touch_size",
                     "'" + d.touch_size + "' is not radius, depth or empty (unknown)");
  d.touches.resize(n);
  for (hsize_t i = 0; i < n; ++i) {
    if (count[i] < 0 || count[i] > kMaxCircles)
      throw InputError(path, "touch_count", "values must lie in 0..4");
    for (int k = 0; k < count[i]; ++k) {
      const double* t = &table[(i * kMaxCircles + k) * 3];
      const std::string where = "frame " + std::to_string(i) + ", touch " + std::to_string(k);
      if (!std::isfinite(t[0]) || !std::isfinite(t[1]))
        throw InputError(path, "touches", where + ": the centre is not a finite number");
      if (d.sensor_mesh.empty() && std::hypot(t[0], t[1]) > d.radius * (1 + 1e-9))
        throw InputError(path, "touches", where + " lies outside the sensor's radius");
      if (!std::isnan(t[2]) && !(t[2] > 0 && std::isfinite(t[2])))
        throw InputError(path, "touches", where + ": the size must be positive, or NaN (unknown)");
      d.touches[i].push_back({t[0], t[1], t[2]});
    }
  }
}

// A shard's place in its whole set; absent attributes: the whole set.
Shard read_shard(const Reader& r, const std::string& path, hsize_t n) {
  Shard s;
  const double count = r.number("shard_count", 1, 1, 1e6);
  if (count == 1) return s;
  const double index = r.number("shard_index", 0, 0, count - 1, true);
  const double first = r.number("shard_first", 0, 0, 1e12, true);
  const double total = r.number("shard_total", 0, 1, 1e12, true);
  for (const auto& [name, v] : {std::pair{"shard_count", count},
                                {"shard_index", index},
                                {"shard_first", first},
                                {"shard_total", total}})
    if (v != std::floor(v)) throw InputError(path, name, "must be a whole number");
  if (first + static_cast<double>(n) > total)
    throw InputError(
        path, "shard_total",
        fmt::format("is {:g}, but the shard's {} rows from row {:g} run past it", total, n, first));
  s.count = static_cast<int>(count), s.index = static_cast<int>(index);
  s.first = static_cast<long long>(first), s.total = static_cast<long long>(total);
  return s;
}

Dataset read_dataset_checked(const std::string& path) {
  Reader r(path);
  Dataset d;
  constexpr double kHuge = 1e300;
  const double electrodes = r.number("electrodes", 0, 4, 256, true);
  if (electrodes != std::floor(electrodes))
    throw InputError(path, "electrodes", "must be a whole number from 4 to 256");
  d.electrodes = static_cast<int>(electrodes);
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
  if (r.has("sensor_mesh")) {
    std::vector<hsize_t> bytes{0};
    const std::vector<unsigned char> text = r.array<unsigned char>("sensor_mesh", bytes);
    d.sensor_mesh.assign(text.begin(), text.end());
    // Checked here, in the child, as any mesh file is: the parent parses it again safely.
    std::istringstream in(d.sensor_mesh);
    const Mesh mesh = read_msh(in, path + ": sensor_mesh");
    if (mesh.num_electrodes() != d.electrodes)
      throw InputError(path, "sensor_mesh",
                       "has " + std::to_string(mesh.num_electrodes()) + " electrodes; the file " +
                           std::to_string(d.electrodes));
    // The radius is the grid's R everywhere the set is used: it must be the mesh's.
    const Eigen::Vector2d extent =
        mesh.nodes.colwise().maxCoeff() - mesh.nodes.colwise().minCoeff();
    if (!(std::abs(0.5 * extent.maxCoeff() - d.radius) <= 1e-9 * d.radius))
      throw InputError(path, "radius",
                       fmt::format("is {:g}, but sensor_mesh's bounding box is {:g} x {:g} (the "
                                   "radius must be half its larger side)",
                                   d.radius, extent.x(), extent.y()));
    d.sensor_group = r.text("sensor_group");
  }
  const double magnitude = r.number("magnitude", 0, 0, 1);
  if (magnitude != 0 && magnitude != 1) throw InputError(path, "magnitude", "must be 0 or 1");
  d.magnitude = magnitude == 1;
  if (r.has("protocol_channels")) {  // checked by the protocol itself: range, pairs, repeats
    std::vector<hsize_t> shape{0, 4};
    const std::vector<int> c = r.array<int>("protocol_channels", shape);
    if (shape[0] == 0 || shape[0] > kMaxChannels)
      throw InputError(path, "protocol_channels",
                       "has " + std::to_string(shape[0]) + " channels; a protocol has 1 to " +
                           std::to_string(kMaxChannels));
    if (!r.integer("protocol_channels"))
      throw InputError(path, "protocol_channels", "must hold integers (electrode indices)");
    for (std::size_t k = 0; k + 3 < c.size(); k += 4)
      d.protocol_channels.push_back({c[k], c[k + 1], c[k + 2], c[k + 3]});
    d.protocol = r.text("protocol").empty() ? "unnamed" : r.text("protocol");
  }
  const MeasurementProtocol protocol = [&] {
    try {
      return measurement_protocol(d);
    } catch (const InputError& e) {
      throw InputError(path, "protocol_channels", e.field() + ": " + e.message());
    }
  }();
  if (d.protocol_channels.empty()) d.protocol = protocol.name();
  const hsize_t full = static_cast<hsize_t>(protocol.size()),
                reduced = static_cast<hsize_t>(protocol.input_size());

  std::vector<hsize_t> dims{0, reduced};
  const std::vector<double> differences = r.array<double>("differences", dims);
  const hsize_t n = dims[0];
  if (n == 0) throw InputError(path, "differences", "the data set is empty");
  d.shard = read_shard(r, path, n);
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
    r.rows("labels", dims, d.labels);
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
  if (r.has("touches")) read_touches(r, path, n, d);
  if (r.has("references")) {
    dims = {n, full};
    const std::vector<double> refs = r.array<double>("references", dims);
    check_finite(r, "references", refs.data(), refs.size());
    d.references = Eigen::Map<const SampleMatrix>(refs.data(), static_cast<Eigen::Index>(n),
                                                  static_cast<Eigen::Index>(full));
  }
  return d;
}

// A data set as the child that read it hands it over (child_read.h).
std::string to_wire(const Dataset& d) {
  detail::WireWriter w;
  w.pod(d.electrodes), w.pod(d.radius), w.pod(d.background), w.pod(d.contact_impedance);
  w.pod(d.current), w.pod(d.electrode_coverage), w.pod(d.image_size), w.pod(d.seed);
  w.text(d.preset), w.text(d.simulation_mesh), w.pod(d.simulation_triangles);
  w.text(d.program), w.text(d.augmentation), w.text(d.sensor_mesh), w.text(d.sensor_group);
  w.text(d.protocol), w.vector(d.protocol_channels), w.pod(d.magnitude);
  w.matrix(d.reference), w.matrix(d.frames), w.matrix(d.differences), w.matrix(d.labels);
  w.pod<std::uint64_t>(d.circles.size());
  for (const auto& list : d.circles) w.vector(list);
  w.pod<std::uint64_t>(d.touches.size());
  for (const auto& list : d.touches) w.vector(list);
  w.text(d.touch_size);
  w.matrix(d.references);
  w.vector(d.split);
  w.pod(d.shard);
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
  d.sensor_mesh = r.text(), d.sensor_group = r.text();
  d.protocol = r.text(), d.protocol_channels = r.vector<Channel>(), d.magnitude = r.pod<bool>();
  d.reference = r.matrix<Eigen::VectorXd>();
  d.frames = r.matrix<SampleMatrix>(), d.differences = r.matrix<SampleMatrix>();
  d.labels = r.matrix<SampleMatrix>();
  d.circles.resize(r.pod<std::uint64_t>());
  for (auto& list : d.circles) list = r.vector<Circle>();
  d.touches.resize(r.pod<std::uint64_t>());
  for (auto& list : d.touches) list = r.vector<PressTouch>();
  d.touch_size = r.text();
  d.references = r.matrix<SampleMatrix>();
  d.split = r.vector<Split>();
  d.shard = r.pod<Shard>();
  return d;
}

}  // namespace

bool is_hdf5_file(const std::string& path) {
  // A FIFO or a device would block the signature read, or drain it: only regular files are
  // looked into, and the reader that follows names what the path is (input_file.h).
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return false;
  H5E_BEGIN_TRY {
    return H5Fis_hdf5(path.c_str()) > 0;
  }
  H5E_END_TRY;
  return false;
}

Dataset read_dataset(const std::string& path) {
  Dataset d = read_dataset_or_shard(path);
  if (!d.shard.whole())
    throw InputError(path, "shard_index",
                     fmt::format("the file is shard {} of {} (rows {} to {} of {}): join the "
                                 "shards with `eitbench merge` first",
                                 d.shard.index, d.shard.count, d.shard.first,
                                 d.shard.first + d.size() - 1, d.shard.total));
  return d;
}

Dataset read_dataset_or_shard(const std::string& path) {
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
