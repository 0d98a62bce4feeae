#include "eitbench/bench/data/press_touches.h"

#include <fmt/core.h>

#include <cmath>

#include "eitbench/jacobian/error.h"
#include "foreign_arrays.h"

namespace eitbench {
namespace {

void check_options(const TouchFileOptions& o) {
  if (!(o.scale > 0) || !std::isfinite(o.scale))
    throw InputError("--touch-scale", "", "must be positive and finite");
  if (o.size != "depth" && o.size != "radius")
    throw InputError("--touch-size", "", "'" + o.size + "' is not depth or radius");
  if (!std::isfinite(o.rotate_degrees))
    throw InputError("--touch-rotate", "", "must be a finite angle in degrees");
}

// The file's point in the mesh's frame: scaled, mirrored, turned.
void to_mesh_frame(PressTouch& t, const TouchFileOptions& o) {
  const double y = o.mirror ? -t.y : t.y;
  const double a = o.rotate_degrees * 3.14159265358979323846 / 180;
  const double c = std::cos(a), s = std::sin(a);
  t = {c * t.x - s * y, s * t.x + c * y, t.size};
}

// The rows x columns of a 2-D array; a MATLAB or NumPy vector of one touch is 1 x width.
std::pair<std::size_t, std::size_t> rows_and_columns(const detail::NamedArray& a,
                                                     const std::string& path,
                                                     const std::string& field) {
  if (a.shape.size() == 2) return {a.shape[0], a.shape[1]};
  if (a.shape.size() == 1) return {1, a.shape[0]};
  throw InputError(path, field, "must be a matrix, a touch a row (x, y[, size])");
}

}  // namespace

PressTruth read_touch_file(const TouchFileOptions& o, long long frames, double radius) {
  check_options(o);
  std::string format;
  bool columns_first = false;
  const auto arrays = detail::read_arrays(
      o.path, [](std::size_t width) { return width == 2 || width == 3; }, 3, format, columns_first);
  const detail::NamedArray& a =
      detail::choose(arrays, o.variable, o.path, {"touches", "positions", "xy"});
  const std::string field = a.name.empty() ? "touches" : a.name;
  const auto [rows, columns] = rows_and_columns(a, o.path, field);
  if (columns != 2 && columns != 3)
    throw InputError(
        o.path, field,
        fmt::format("has {} columns; a touch a row is x, y or x, y, {}", columns, o.size));
  if (static_cast<long long>(rows) != frames)
    throw InputError(
        o.path, field,
        fmt::format("has {} rows; the frames are {} (one touch a frame, in order)", rows, frames));
  PressTruth out;
  out.size = columns == 3 ? o.size : "";
  out.touches.resize(rows);
  for (std::size_t i = 0; i < rows; ++i) {
    const double* v = &a.values[i * columns];
    PressTouch t{v[0] * o.scale, v[1] * o.scale, columns == 3 ? v[2] * o.scale : NAN};
    const std::string row = fmt::format("row {}", i + 1);
    if (!std::isfinite(t.x) || !std::isfinite(t.y))
      throw InputError(o.path, field, row + ": the position is not a finite number");
    if (columns == 3 && !(t.size > 0 && std::isfinite(t.size)))
      throw InputError(o.path, field, row + ": the " + o.size + " must be positive");
    to_mesh_frame(t, o);
    if (std::hypot(t.x, t.y) > radius * (1 + 1e-9))
      throw InputError(o.path, field,
                       fmt::format("{}: ({:g}, {:g}) x {:g} lies outside the sensor (radius {:g}): "
                                   "is --touch-scale right?",
                                   row, v[0], v[1], o.scale, radius));
    out.touches[i].push_back(t);
  }
  return out;
}

}  // namespace eitbench

namespace eitbench {

void check_press_set(const std::string& path, const Dataset& data,
                     const MeasurementProtocol& protocol) {
  if (data.touches.empty())
    throw InputError(path, "touches", "is not a press set (import --touches makes one)");
  for (std::size_t i = 0; i < data.touches.size(); ++i)
    if (data.touches[i].size() != 1)
      throw InputError(path, "touches",
                       fmt::format("frame {} has {} touches; presses are scored one a frame", i,
                                   data.touches[i].size()));
  const MeasurementProtocol own = measurement_protocol(data);
  if (!own.same_channels(protocol) || data.magnitude != protocol.magnitude())
    throw InputError(path, "protocol",
                     "is read on the " + own.name() + (data.magnitude ? " (magnitudes)" : "") +
                         " protocol, the scored presses on " + protocol.name() +
                         (protocol.magnitude() ? " (magnitudes)" : "") +
                         ": presses tune and score on one board");
}

}  // namespace eitbench
