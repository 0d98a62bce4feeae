// The eitbench Python module: errors as Python exceptions with the tool's messages.
#include "bindings.h"

#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::python {

SampleMatrix rows_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                     const char* what) {
  if (a.ndim() != 1 && a.ndim() != 2)
    throw InputError(
        what, "",
        "must be a 1-D frame or a 2-D array (one a row), not " + std::to_string(a.ndim()) + "-D");
  const Eigen::Index rows = a.ndim() == 1 ? 1 : a.shape(0), cols = a.shape(a.ndim() - 1);
  return Eigen::Map<const SampleMatrix>(a.data(), rows, cols);
}

SampleMatrix image_rows(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                        const char* what) {
  if (a.ndim() == 3)
    return Eigen::Map<const SampleMatrix>(a.data(), a.shape(0), a.shape(1) * a.shape(2));
  return rows_of(a, what);
}

py::array_t<double> as_images(const SampleMatrix& images, int n) {
  py::array_t<double> out(
      {static_cast<py::ssize_t>(images.rows()), py::ssize_t{n}, py::ssize_t{n}});
  std::copy(images.data(), images.data() + images.size(), out.mutable_data());
  return out;
}

}  // namespace eitbench::python

PYBIND11_MODULE(eitbench, m) {
  using namespace eitbench::python;
  m.doc() =
      "eitbench: electrical impedance tomography for tactile sensing. Meshes, the forward model "
      "and its Jacobian, the symmetry group's augmentation, every reconstructor, data sets and "
      "learned models, on NumPy arrays.";
  m.attr("__version__") = eitbench::program_version();
  // InputError (bad data or options, named with its source and field) is a ValueError.
  static py::exception<eitbench::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const eitbench::InputError& e) {
      input_error(e.what());
    }
  });
  bind_physics(m);
  bind_methods(m);
  bind_data(m);
}
