#pragma once
// The Python package's bindings (pybind11), one file an area: the sensor's physics, the methods,
// the data. NumPy arrays in and out; float64 C-contiguous inputs are read in place.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench::python {

namespace py = pybind11;

// Frames as the libraries take them: a 2-D array (one frame a row) read in place when it is
// float64 and C-contiguous, a 1-D array as one row.
SampleMatrix rows_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                     const char* what);
// Images as rows of n^2 pixels, from N x n x n (read in place) or N x n^2.
SampleMatrix image_rows(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                        const char* what);
// An N x n^2 image matrix as N x n x n.
py::array_t<double> as_images(const SampleMatrix& images, int n);

void bind_physics(py::module_& m);
void bind_methods(py::module_& m);
void bind_data(py::module_& m);

}  // namespace eitbench::python
