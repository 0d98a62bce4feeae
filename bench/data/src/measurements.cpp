#include "eitbench/bench/data/measurements.h"

#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>

#include "eitbench/augment/impedance_map.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "eitbench/bench/io/matlab.h"
#include "eitbench/bench/io/numpy.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"
#include "foreign_arrays.h"

namespace eitbench {

Measurements read_measurements(const std::string& path, const ImportOptions& o) {
  const int L = o.electrodes;
  if (L < 4 || L > 256) throw InputError("--electrodes", "", "need 4 <= L <= 256");
  const bool other = o.protocol && !is_adjacent(*o.protocol);
  // adjacent-ascending names the order of L(L-3)-value frames, as --order does.
  const MeasurementOrder order =
      o.protocol && !other &&
              o.protocol->same_channels(adjacent_protocol(L, MeasurementOrder::ascending))
          ? MeasurementOrder::ascending
      : o.protocol && !other ? MeasurementOrder::rotating
                             : o.order;
  if (o.protocol && o.protocol->electrodes() != L)
    throw InputError("--protocol", "",
                     "is for " + std::to_string(o.protocol->electrodes()) + " electrodes, not " +
                         std::to_string(L));
  const std::size_t full = L * (L - 3), reduced = full / 2, square = L * L;
  const std::size_t channels = other ? static_cast<std::size_t>(o.protocol->size()) : 0;
  auto fits = [&](std::size_t n) {
    return other ? n == channels : n == full || n == reduced || n == square;
  };
  std::string format;
  bool columns_first = false;
  const auto arrays =
      detail::read_arrays(path, fits, other ? channels : square, format, columns_first);
  const detail::NamedArray& a = detail::choose(arrays, o.variable, path);
  const std::string field = a.name.empty() ? "frames" : a.name;
  if (a.shape.size() > 2)
    throw InputError(path, field,
                     "has " + std::to_string(a.shape.size()) + " dimensions; frames need 1 or 2");
  std::size_t rows = a.shape.size() == 2 ? a.shape[0] : 1,
              cols = a.shape.empty() ? 0 : a.shape.back();
  bool transpose = false;  // frames are columns
  if (a.shape.size() == 2) {
    if (fits(cols) && fits(rows))
      transpose = columns_first;
    else if (!fits(cols) && fits(rows))
      transpose = true;
  }
  const std::size_t n = transpose ? cols : rows, length = transpose ? rows : cols;
  if (!fits(length) && other)
    throw InputError(path, field,
                     "frames of " + std::to_string(length) + " values do not fit the " +
                         o.protocol->name() + " protocol's " + std::to_string(channels) +
                         " channels");
  if (!fits(length))
    throw InputError(path, field,
                     "frames of " + std::to_string(length) + " values do not fit " +
                         std::to_string(L) + " electrodes (" + std::to_string(full) + ", " +
                         std::to_string(reduced) + " reduced, or " + std::to_string(square) +
                         " as an L x L map); frames of another protocol need --protocol");
  if (n == 0) throw InputError(path, field, "holds no frames");
  for (std::size_t i = 0; i < a.values.size(); ++i)
    if (!std::isfinite(a.values[i]))
      throw InputError(path, field, "value " + std::to_string(i) + " is NaN or infinite");
  auto value = [&](std::size_t frame, std::size_t k) {
    return transpose ? a.values[k * cols + frame] : a.values[frame * cols + k];
  };

  if (other) {  // the protocol's channels, in its order, as they are
    Measurements m;
    m.frames.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(length));
    for (std::size_t f = 0; f < n; ++f)
      for (std::size_t k = 0; k < length; ++k) m.frames(f, k) = value(f, k);
    m.reduced_input = true;  // no reciprocity to measure in general
    m.description = format + (a.name.empty() ? "" : " (variable '" + a.name + "')") + ", " +
                    std::to_string(n) + " frames, " + o.protocol->name() + " protocol (" +
                    std::to_string(length) + " channels)" +
                    (transpose ? ", one frame a column" : "");
    return m;
  }
  const Protocol protocol(L);
  Measurements m;
  m.frames.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(full));
  if (o.keep_maps && length == square)
    m.maps.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(square));
  std::string layout;
  double reciprocity = 0;
  for (std::size_t f = 0; f < n; ++f) {
    Eigen::VectorXd raw(length);
    for (std::size_t k = 0; k < length; ++k) raw[k] = value(f, k);
    Eigen::VectorXd rotating;
    if (length == square) {
      layout = "L x L map";
      if (m.maps.size()) m.maps.row(f) = raw.transpose();
      rotating.resize(full);
      const auto& pairs = protocol.pairs(MeasurementOrder::rotating);
      for (std::size_t i = 0; i < full; ++i)
        rotating[i] = raw[pairs[i].drive * L + pairs[i].measure];
    } else if (length == reduced) {
      layout = "reduced (" + std::to_string(reduced) + " values)";
      rotating = protocol.expand(raw, MeasurementOrder::rotating);
      m.reduced_input = true;
    } else {
      layout = to_string(order) + " order";
      rotating = protocol.reorder(raw, order, MeasurementOrder::rotating);
    }
    reciprocity += protocol.reciprocity_error(rotating, MeasurementOrder::rotating);
    m.frames.row(f) = rotating.transpose();
  }
  m.reciprocity_error = reciprocity / n;
  m.description = format + (a.name.empty() ? "" : " (variable '" + a.name + "')") + ", " +
                  std::to_string(n) + " frames, " + layout +
                  (transpose ? ", one frame a column" : "");
  return m;
}

Dataset import_measurements(const std::string& path, const std::string& reference_path,
                            const ImportOptions& o, const std::string& reference_variable) {
  return import_measurements(read_measurements(path, o), reference_path, o, reference_variable);
}

Dataset import_measurements(const Measurements& m, const std::string& reference_path,
                            const ImportOptions& o, const std::string& reference_variable) {
  const int L = o.electrodes;
  Dataset d;
  d.electrodes = L;
  d.preset = "imported";
  d.simulation_mesh = m.description;
  d.program = program_version();
  d.frames = m.frames;
  // The adjacent protocol's frames are in rotating order whatever layout they came in.
  const MeasurementProtocol protocol =
      o.protocol && !is_adjacent(*o.protocol)
          ? *o.protocol
          : adjacent_protocol(L).with_magnitude(o.protocol && o.protocol->magnitude());
  set_protocol(d, protocol);
  const Eigen::Index n = m.frames.rows();
  SampleMatrix references = SampleMatrix::Zero(1, m.frames.cols());
  if (!reference_path.empty()) {
    ImportOptions ro = o;
    ro.variable = reference_variable;
    const Measurements r = read_measurements(reference_path, ro);
    const std::string field = ro.variable.empty() ? "frames" : ro.variable;
    if (o.paired_reference && r.frames.rows() != n)
      throw InputError(reference_path, field,
                       "holds " + std::to_string(r.frames.rows()) +
                           " frames; paired references "
                           "need one per frame (" +
                           std::to_string(n) + ")");
    references = o.paired_reference ? r.frames : SampleMatrix(r.frames.colwise().mean());
    // An empty sensor has voltages: a zero reference would pass every frame off as a difference.
    if (references.cwiseAbs().maxCoeff() == 0)
      throw InputError(reference_path, field,
                       "is all zero: a reference is the untouched sensor's frame, with its "
                       "voltages (without a reference, the frames are taken as differences)");
    if (o.relative)
      for (Eigen::Index i = 0; i < references.rows(); ++i)
        for (Eigen::Index k = 0; k < references.cols(); ++k)
          if (references(i, k) == 0)
            throw InputError(reference_path, field,
                             "frame " + std::to_string(i) + ", channel " + std::to_string(k) +
                                 " is zero: relative differences divide by it");
  } else if (o.relative || o.paired_reference) {
    throw InputError(o.relative ? "--relative" : "--paired-reference", "",
                     "needs --reference (the untouched sensor's frames)");
  }
  d.reference = references.colwise().mean().transpose();
  if (o.paired_reference) d.references = references;
  d.differences.resize(n, protocol.input_size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::VectorXd ref = references.row(references.rows() == 1 ? 0 : i).transpose();
    Eigen::VectorXd change = m.frames.row(i).transpose() - ref;
    // Relative: the change as a fraction of its own reference, in the mean reference's units, so
    // that every method (which compares differences with the model's v - v0) and the group's
    // signs apply unchanged, while a reference's own gain divides out.
    if (o.relative) change = change.cwiseQuotient(ref).cwiseProduct(d.reference);
    d.differences.row(i) = protocol.to_inputs(change).transpose();
  }
  d.split.assign(static_cast<std::size_t>(m.frames.rows()), Split::test);
  return d;
}

int frames_without_change(const Dataset& data) {
  int count = 0;
  for (Eigen::Index i = 0; i < data.differences.rows(); ++i)
    count += data.differences.row(i).cwiseAbs().maxCoeff() == 0;
  return count;
}

ReferenceCalibration calibrate_to_model(const Eigen::VectorXd& measured_reference,
                                        const Eigen::VectorXd& model_reference) {
  if (measured_reference.size() != model_reference.size())
    throw std::invalid_argument("calibrate_to_model: the references differ in length");
  const double mm = measured_reference.squaredNorm(), rr = model_reference.squaredNorm();
  if (mm == 0 || rr == 0) return {};
  const double dot = model_reference.dot(measured_reference);
  return {dot / mm, dot / std::sqrt(mm * rr)};
}

}  // namespace eitbench
