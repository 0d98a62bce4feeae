// Every reconstructor behind one class, and the symmetry group's augmentation.
#include <memory>
#include <optional>

#include "bindings.h"
#include "eitbench/augment/augmented_set.h"
#include "eitbench/bench/methods/metrics.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/jacobian.h"
#include "eitbench/solvers/shape.h"

namespace eitbench::python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A method with what it reconstructs on: the linear problem (model-based) and the pixel grid.
struct Method {
  std::shared_ptr<const LinearProblem> problem;  // null for dnn
  std::unique_ptr<Reconstructor> method;
  PixelGrid grid{64, 1.0};
};

std::shared_ptr<Method> make_method(const std::string& name, std::shared_ptr<Mesh> mesh,
                                    double background, std::optional<double> lambda,
                                    const std::string& choose, const std::string& model,
                                    const std::string& neighbours, double tolerance, double robust,
                                    double contact_impedance, double current, int image_size,
                                    double noser_exponent, double smooth_length) {
  auto out = std::make_shared<Method>();
  if (name == "dnn") {
    if (model.empty()) throw InputError("model", "", "method dnn needs a model file");
    LearnedModel learned = read_model_file(model);
    out->grid = PixelGrid(learned.info().network.image_size, 1.0);
    out->method = make_learned_reconstructor(std::move(learned));
    return out;
  }
  if (!mesh) mesh = std::make_shared<Mesh>(generate_disk_mesh({}));
  ForwardOptions forward;
  forward.contact_impedance = contact_impedance, forward.current = current;
  const auto fm = std::make_shared<const ForwardModel>(*mesh, forward, "mesh");
  double radius = 0;
  for (Eigen::Index k = 0; k < mesh->nodes.rows(); ++k)
    radius = std::max(radius, mesh->nodes.row(k).norm());
  out->grid = PixelGrid(image_size, radius);
  out->problem =
      std::make_shared<const LinearProblem>(make_linear_problem(fm, background, out->grid));
  MethodOptions o;
  o.choose = lambda ? "fixed" : choose.empty() ? find_method(name).default_choice : choose;
  o.lambda = lambda.value_or(0.0);
  o.neighbours = neighbours, o.tolerance = tolerance, o.robust = robust;
  o.noser_exponent = noser_exponent, o.smooth_length = smooth_length;
  out->method = make_reconstructor(name, out->problem, o);
  return out;
}

}  // namespace

void bind_methods(py::module_& m) {
  m.attr("methods") = method_names();
  py::class_<Method, std::shared_ptr<Method>>(
      m, "Reconstructor",
      "One reconstruction method, as `eitbench reconstruct --method` builds it: frames (the "
      "reduced difference voltages, one a row) to images on the label scale")
      .def(py::init(&make_method), py::arg("method"), py::arg("mesh") = nullptr,
           py::arg("background") = 0.05, py::arg("lambda_") = py::none(), py::arg("choose") = "",
           py::arg("model") = "", py::arg("neighbours") = "pixels", py::arg("tolerance") = 0.0,
           py::arg("robust") = 0.0, py::arg("contact_impedance") = 0.01, py::arg("current") = 1.0,
           py::arg("image_size") = 64, py::arg("noser_exponent") = MethodOptions().noser_exponent,
           py::arg("smooth_length") = MethodOptions().smooth_length,
           "method: one of eitbench.methods; mesh: the reconstruction mesh (default: the medium "
           "disk); lambda_: a fixed hyperparameter, or choose = gcv | lcurve | validation (then "
           "fit() chooses it); model: the model file of dnn; noser_exponent: noser's p in "
           "diag(A^T A)^p; smooth_length: where smooth's prior covariance falls to 1 %, in the "
           "sensor's radius")
      .def_property_readonly("name", [](const Method& r) { return r.method->name(); })
      .def_property_readonly("settings", [](const Method& r) { return r.method->settings(); })
      .def(
          "fit",
          [](Method& r, const Array& frames, const Array& labels) {
            const SampleMatrix f = rows_of(frames, "frames");
            const SampleMatrix l = image_rows(labels, "labels");
            if (l.cols() != r.grid.num_pixels())
              throw InputError("labels", "",
                               "need " + std::to_string(r.grid.num_pixels()) + " pixels a label");
            const PixelGrid grid = r.grid;
            py::gil_scoped_release release;
            r.method->fit(f, l, [grid](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
              return correlation(x, y, grid);
            });
          },
          py::arg("frames"), py::arg("labels"),
          "Chooses the hyperparameter on labelled frames by CC (choose = validation, gcv, lcurve)")
      .def(
          "reconstruct",
          [](const Method& r, const Array& frames) -> py::object {
            const SampleMatrix f = rows_of(frames, "frames");
            SampleMatrix images;
            {
              py::gil_scoped_release release;
              images = r.method->reconstruct_all(f);
            }
            py::array_t<double> out = as_images(images, r.grid.size());
            if (frames.ndim() == 1) return out[py::int_(0)];
            return std::move(out);
          },
          py::arg("frames"), "Images (N x n x n, or n x n for one frame); 0 outside the disk")
      .def(
          "touches",
          [](const Method& r, const Eigen::Ref<const Eigen::VectorXd>& frame) {
            if (!r.method->finds_circles())
              throw InputError("method", "", r.method->name() + " gives images, not circles");
            Eigen::VectorXd image;
            std::vector<std::array<double, 4>> out;
            for (const Circle& c : r.method->touches(frame, image))
              out.push_back({c.x, c.y, c.r, c.conductivity});
            return out;
          },
          py::arg("frame"), "shape, shape-linear: the circles found, [x, y, r, sigma] each")
      .def(
          "fits_by_count",
          [](const Method& r, const Eigen::Ref<const Eigen::VectorXd>& frame) {
            const auto* shape = dynamic_cast<const ShapeReconstructor*>(r.method.get());
            if (!shape) throw InputError("method", "", r.method->name() + " is not a shape fit");
            std::vector<std::pair<double, std::vector<std::array<double, 4>>>> out;
            for (const ShapeFit& f : shape->fits_by_count(frame)) {
              out.push_back({f.rss, {}});
              for (const Circle& c : f.circles)
                out.back().second.push_back({c.x, c.y, c.r, c.conductivity});
            }
            return out;
          },
          py::arg("frame"),
          "shape, shape-linear: the linear fit with each number of circles K = 0, 1, ..., as "
          "(misfit, circles); the method chooses K among them by its BIC")
      .def(
          "fit_from",
          [](const Method& r, const Eigen::Ref<const Eigen::VectorXd>& frame,
             const std::vector<std::array<double, 4>>& start, const std::string& forward) {
            const auto* shape = dynamic_cast<const ShapeReconstructor*>(r.method.get());
            if (!shape) throw InputError("method", "", r.method->name() + " is not a shape fit");
            std::vector<Circle> circles;
            for (const auto& c : start) circles.push_back({c[0], c[1], c[2], c[3]});
            const ShapeFit f = shape->fit_circles(frame, circles, parse_shape_forward(forward));
            std::vector<std::array<double, 4>> out;
            for (const Circle& c : f.circles) out.push_back({c.x, c.y, c.r, c.conductivity});
            return std::make_pair(f.rss, out);
          },
          py::arg("frame"), py::arg("start"), py::arg("forward") = "full",
          "shape, shape-linear: the fit of exactly len(start) circles from start ([x, y, r, sigma] "
          "each) on the forward model (full or linear), as (misfit, circles)")
      .def_property_readonly(
          "pixel_jacobian",
          [](const Method& r) {
            if (!r.problem) throw InputError("method", "", "dnn has no Jacobian");
            return r.problem->A;
          },
          "J_pix: reduced measurements x in-disk pixels (see pixel_indices)")
      .def_property_readonly("pixel_indices", [](const Method& r) {
        if (!r.problem) throw InputError("method", "", "dnn has no Jacobian");
        return r.problem->pixels;
      });

  m.def(
      "augment",
      [](const Array& frames, std::optional<Array> labels, const std::string& group, int electrodes,
         double radius, const std::string& order) {
        AugmentSetup setup;
        setup.group = parse_group(group, "group");
        setup.electrodes = electrodes, setup.radius = radius;
        LabelledFrames set;
        set.frames = rows_of(frames, "frames");
        setup.layout = frame_layout(set.frames.cols(), electrodes, parse_order(order), "frames");
        if (labels) {
          set.labels = image_rows(*labels, "labels");
          const double n = std::sqrt(static_cast<double>(set.labels.cols()));
          setup.image_size = static_cast<int>(std::lround(n));
        } else {
          set.labels.resize(set.frames.rows(), 0);
        }
        LabelledFrames out;
        {
          py::gil_scoped_release release;
          out = expand_by_group(set, setup);
        }
        if (!labels) return py::make_tuple(out.frames, py::none());
        return py::make_tuple(out.frames, as_images(out.labels, setup.image_size));
      },
      py::arg("frames"), py::arg("labels") = py::none(), py::arg("group") = "d16",
      py::arg("electrodes") = 16, py::arg("radius") = 1.0, py::arg("order") = "rotating",
      "Frames (reduced, or full L(L-3) in `order`) and labels moved by every element of the group "
      "(none, rotations, mirror, d16, "
      "paper): |G| x N rows, sample-major (row i |G| + k is sample i under element k)");
}

}  // namespace eitbench::python
