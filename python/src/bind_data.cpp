// Data sets (read and written as `simulate` and `import` do) and learned models.
#include <cmath>

#include "bindings.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/learned.h"

namespace eitbench::python {
namespace {

constexpr int kMaxCircles = 4;  // the file's /circles holds up to 4 a sample

// A press set's known touches: touches N x 4 x 3 ([x, y, size], NaN-padded), touch_count and
// touch_size, as the file holds them.
void add_touches(const Dataset& d, py::dict& out) {
  py::array_t<double> touches(
      {static_cast<py::ssize_t>(d.size()), py::ssize_t{kMaxCircles}, py::ssize_t{3}});
  std::fill(touches.mutable_data(), touches.mutable_data() + touches.size(), NAN);
  std::vector<int> count;
  auto t = touches.mutable_unchecked<3>();
  for (int i = 0; i < d.size(); ++i) {
    const auto& list = d.touches[static_cast<std::size_t>(i)];
    count.push_back(static_cast<int>(list.size()));
    for (std::size_t k = 0; k < list.size() && k < kMaxCircles; ++k) {
      const auto j = static_cast<py::ssize_t>(k);
      t(i, j, 0) = list[k].x, t(i, j, 1) = list[k].y, t(i, j, 2) = list[k].size;
    }
  }
  out["touches"] = touches;
  out["touch_count"] = py::array_t<int>(static_cast<py::ssize_t>(count.size()), count.data());
  out["touch_size"] = d.touch_size;
}

py::dict to_dict(const Dataset& d) {
  py::dict out;
  out["differences"] = d.differences;
  out["frames"] = d.frames;
  out["reference"] = d.reference;
  if (d.has_labels()) out["labels"] = as_images(d.labels, d.image_size);
  std::vector<int> split;
  for (Split s : d.split) split.push_back(static_cast<int>(s));
  out["split"] = py::array_t<int>(static_cast<py::ssize_t>(split.size()), split.data());
  if (!d.circles.empty()) {
    py::array_t<double> circles(
        {static_cast<py::ssize_t>(d.size()), py::ssize_t{kMaxCircles}, py::ssize_t{4}});
    std::fill(circles.mutable_data(), circles.mutable_data() + circles.size(), NAN);
    std::vector<int> count;
    auto c = circles.mutable_unchecked<3>();
    for (int i = 0; i < d.size(); ++i) {
      const auto& list = d.circles[static_cast<std::size_t>(i)];
      count.push_back(static_cast<int>(list.size()));
      for (std::size_t k = 0; k < list.size() && k < kMaxCircles; ++k) {
        const auto j = static_cast<py::ssize_t>(k);
        c(i, j, 0) = list[k].x, c(i, j, 1) = list[k].y, c(i, j, 2) = list[k].r;
        c(i, j, 3) = list[k].conductivity;
      }
    }
    out["circles"] = circles;
    out["circle_count"] = py::array_t<int>(static_cast<py::ssize_t>(count.size()), count.data());
  }
  if (!d.touches.empty()) add_touches(d, out);
  out["electrodes"] = d.electrodes, out["radius"] = d.radius;
  out["background_conductivity"] = d.background, out["contact_impedance"] = d.contact_impedance;
  out["current"] = d.current, out["electrode_coverage"] = d.electrode_coverage;
  out["image_size"] = d.image_size, out["seed"] = d.seed, out["preset"] = d.preset;
  out["simulation_mesh"] = d.simulation_mesh, out["program"] = d.program;
  out["augmentation"] = d.augmentation;
  if (!d.sensor_mesh.empty())  // a sensor of another shape: its mesh (Gmsh text) and group
    out["sensor_mesh"] = d.sensor_mesh, out["sensor_group"] = d.sensor_group;
  // The protocol (docs/protocols.md): its name, channels (C x 4) and magnitude flag.
  const MeasurementProtocol protocol = measurement_protocol(d);
  std::vector<int> channels;
  for (const Channel& c : protocol.channels())
    channels.insert(channels.end(), {c.drive_plus, c.drive_minus, c.meas_plus, c.meas_minus});
  out["protocol"] = protocol.name(), out["magnitude"] = protocol.magnitude();
  out["protocol_channels"] = py::array_t<int>(
      {static_cast<py::ssize_t>(protocol.size()), py::ssize_t{4}}, channels.data());
  return out;
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

template <typename T>
T get(const py::dict& d, const char* key, T fallback) {
  return d.contains(key) ? d[key].cast<T>() : fallback;
}

Dataset from_dict(const py::dict& x) {
  Dataset d;
  if (!x.contains("differences") || !x.contains("frames") || !x.contains("reference"))
    throw InputError("dataset", "", "needs differences, frames and reference");
  d.differences = rows_of(x["differences"].cast<py::array>(), "differences");
  d.frames = rows_of(x["frames"].cast<py::array>(), "frames");
  d.reference = x["reference"].cast<Eigen::VectorXd>();
  d.electrodes = get(x, "electrodes", d.electrodes);
  d.radius = get(x, "radius", d.radius);
  d.background = get(x, "background_conductivity", d.background);
  d.contact_impedance = get(x, "contact_impedance", d.contact_impedance);
  d.current = get(x, "current", d.current);
  d.electrode_coverage = get(x, "electrode_coverage", d.electrode_coverage);
  d.image_size = get(x, "image_size", d.image_size);
  d.seed = get<std::uint64_t>(x, "seed", 0);
  d.preset = get<std::string>(x, "preset", "imported");
  d.simulation_mesh = get<std::string>(x, "simulation_mesh", "python");
  d.program = get<std::string>(x, "program", "eitbench (Python)");
  d.augmentation = get<std::string>(x, "augmentation", "none");
  d.sensor_mesh = get<std::string>(x, "sensor_mesh", "");
  d.sensor_group = get<std::string>(x, "sensor_group", "");
  d.magnitude = get<bool>(x, "magnitude", false);
  if (x.contains("protocol_channels")) {  // checked when the set is written or used
    const auto c =
        x["protocol_channels"].cast<py::array_t<int, py::array::c_style | py::array::forcecast>>();
    if (c.ndim() != 2 || c.shape(1) != 4)
      throw InputError("dataset", "protocol_channels",
                       "must be C x 4 (drive+, drive-, meas+, meas-)");
    for (py::ssize_t i = 0; i < c.shape(0); ++i)
      d.protocol_channels.push_back({c.at(i, 0), c.at(i, 1), c.at(i, 2), c.at(i, 3)});
    d.protocol = get<std::string>(x, "protocol", "unnamed");
  }
  const int n = d.size();
  d.split.assign(static_cast<std::size_t>(n), Split::test);
  if (x.contains("split")) {
    const auto s = x["split"].cast<std::vector<int>>();
    if (static_cast<int>(s.size()) != n)
      throw InputError("dataset", "split", "needs one value a sample");
    for (int i = 0; i < n; ++i) {
      if (s[i] < 0 || s[i] > 2) throw InputError("dataset", "split", "values are 0, 1 or 2");
      d.split[static_cast<std::size_t>(i)] = static_cast<Split>(s[i]);
    }
  }
  if (x.contains("labels")) {
    const auto labels =
        x["labels"].cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
    if (labels.ndim() != 3 || labels.shape(0) != n)
      throw InputError("dataset", "labels", "must be N x n x n, one image a sample");
    d.labels = Eigen::Map<const SampleMatrix>(labels.data(), n, labels.shape(1) * labels.shape(2));
  } else {
    d.labels.resize(n, 0);
  }
  if (x.contains("circles")) {
    const auto c =
        x["circles"].cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
    if (c.ndim() != 3 || c.shape(0) != n || c.shape(2) != 4)
      throw InputError("dataset", "circles", "must be N x K x 4 ([x, y, r, sigma], NaN-padded)");
    const auto v = c.unchecked<3>();
    d.circles.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      for (py::ssize_t k = 0; k < c.shape(1); ++k)
        if (!std::isnan(v(i, k, 0)))
          d.circles[static_cast<std::size_t>(i)].push_back(
              {v(i, k, 0), v(i, k, 1), v(i, k, 2), v(i, k, 3)});
  }
  if (x.contains("touches")) {  // a press set's; checked when the set is written and read
    const auto t =
        x["touches"].cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
    if (t.ndim() != 3 || t.shape(0) != n || t.shape(2) != 3)
      throw InputError("dataset", "touches", "must be N x K x 3 ([x, y, size], NaN-padded)");
    const auto v = t.unchecked<3>();
    d.touches.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      for (py::ssize_t k = 0; k < t.shape(1); ++k)
        if (!std::isnan(v(i, k, 0)))
          d.touches[static_cast<std::size_t>(i)].push_back({v(i, k, 0), v(i, k, 1), v(i, k, 2)});
    d.touch_size = get<std::string>(x, "touch_size", "");
  }
  return d;
}

}  // namespace

void bind_data(py::module_& m) {
  m.def(
      "read_dataset", [](const std::string& path) { return to_dict(read_dataset(path)); },
      py::arg("path"),
      "An eitbench data set (HDF5) as a dict of NumPy arrays (differences, frames, reference, "
      "labels N x n x n, split, circles N x 4 x 4 NaN-padded, circle_count; a press set's touches "
      "N x 4 x 3, touch_count, touch_size) and its attributes");
  m.def(
      "write_dataset",
      [](const std::string& path, const py::dict& data) { write_dataset(path, from_dict(data)); },
      py::arg("path"), py::arg("data"),
      "Writes a dict in read_dataset's layout as an eitbench data set (whole or not at all)");

  py::class_<LearnedModel>(m, "LearnedModel", "A trained model (eitbench train --out)")
      .def_property_readonly("augment", [](const LearnedModel& l) { return l.info().augment; })
      .def_property_readonly("parameters", &LearnedModel::parameters)
      .def_property_readonly("image_size",
                             [](const LearnedModel& l) { return l.info().network.image_size; })
      .def(
          "reconstruct",
          [](const LearnedModel& l,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& frames) {
            const SampleMatrix f = rows_of(frames, "frames");
            SampleMatrix images;
            {
              py::gil_scoped_release release;
              images = l.reconstruct(f);
            }
            return as_images(images, l.info().network.image_size);
          },
          py::arg("frames"), "Images N x n x n from frames (reduced differences, one a row)");
  m.def("load_model", &read_model_file, py::arg("path"), "A model file of eitbench train");
  m.def("save_model", &write_model_file, py::arg("path"), py::arg("model"),
        "Writes a model file (as eitbench train --out), whole or not at all");
  m.def(
      "train",
      [](const Array& frames, const Array& labels, const Array& val_frames, const Array& val_labels,
         const std::string& augment, int epochs, long long steps, int patience, int batch,
         double learning_rate, std::uint64_t seed, const std::string& size, double radius,
         int electrodes, bool quiet) {
        LabelledFrames train, validation;
        train.frames = rows_of(frames, "frames");
        train.labels = image_rows(labels, "labels");
        validation.frames = rows_of(val_frames, "val_frames");
        validation.labels = image_rows(val_labels, "val_labels");
        const int n = static_cast<int>(std::lround(std::sqrt(double(train.labels.cols()))));
        const ModelSize model_size = parse_model_size(size, "size");
        NetworkOptions network =
            NetworkOptions::preset(model_size, static_cast<int>(train.frames.cols()), n);
        network.radius = radius;
        TrainingOptions o;  // the command line's defaults (eitbench train)
        o.augment = parse_group(augment, "augment");
        o.patience = patience, o.seed = seed;
        o.batch_size = batch > 0 ? batch : (model_size == ModelSize::paper ? 512 : 128);
        o.learning_rate =
            learning_rate > 0 ? learning_rate : (model_size == ModelSize::paper ? 1e-3 : 1e-2);
        if (steps > 0)
          o.steps = steps;
        else
          o.epochs = epochs > 0 ? epochs : (model_size == ModelSize::paper ? 300 : 100);
        AugmentSetup sensor;
        sensor.electrodes = electrodes, sensor.image_size = n, sensor.radius = radius;
        py::gil_scoped_release release;
        Trainer trainer(network, o, std::move(train), validation, sensor);
        while (!trainer.done()) {
          const TrainingRecord r = trainer.run_round();
          if (!quiet) {
            py::gil_scoped_acquire hold;
            py::print("step", r.steps, "validation MSE", r.validation_loss);
          }
        }
        return trainer.best_model();
      },
      py::arg("frames"), py::arg("labels"), py::arg("val_frames"), py::arg("val_labels"),
      py::arg("augment") = "none", py::arg("epochs") = 0, py::arg("steps") = 0,
      py::arg("patience") = 5, py::arg("batch") = 0, py::arg("learning_rate") = 0.0,
      py::arg("seed") = 1, py::arg("size") = "small", py::arg("radius") = 1.0,
      py::arg("electrodes") = 16, py::arg("quiet") = true,
      "Trains the learned reconstructor as eitbench train does (early stopping on validation, "
      "patience 5; budget: epochs or steps, default 100 epochs) and returns the best model");
}

}  // namespace eitbench::python
