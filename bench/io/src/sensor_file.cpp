#include "eitbench/bench/io/sensor_file.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <type_traits>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/forward_model.h"

namespace eitbench {
namespace {

constexpr const char* kFormat = "eitbench-sensor-1";

double positive(const nlohmann::json& j, const std::string& path, const char* field) {
  if (!j.contains(field) || !j[field].is_number())
    throw InputError(path, field, "missing, or not a number");
  const double v = j[field].get<double>();
  if (!(v > 0) || !std::isfinite(v)) throw InputError(path, field, "must be positive and finite");
  return v;
}

double finite(const nlohmann::json& j, const std::string& path, const char* field) {
  if (!j.contains(field) || !j[field].is_number())
    throw InputError(path, std::string("press_fit.") + field, "missing, or not a number");
  const double v = j[field].get<double>();
  if (!std::isfinite(v))
    throw InputError(path, std::string("press_fit.") + field, "must be finite");
  return v;
}

// An optional field of `j` (under `object`) as T, or `fallback` when absent; InputError naming it
// when it has another type.
template <typename T>
T optional_field(const nlohmann::json& j, const std::string& path, const std::string& object,
                 const char* field, T fallback) {
  if (!j.contains(field)) return fallback;
  const auto& v = j[field];
  const bool fits = std::is_same_v<T, bool>          ? v.is_boolean()
                    : std::is_same_v<T, int>         ? v.is_number_integer()
                    : std::is_same_v<T, std::string> ? v.is_string()
                                                     : v.is_number();
  if (!fits) throw InputError(path, object + field, "has the wrong type");
  return v.get<T>();
}

SensorPressFit read_press_fit(const nlohmann::json& j, const std::string& path) {
  if (!j.is_object()) throw InputError(path, "press_fit", "must be an object");
  SensorPressFit f;
  const std::string in = "press_fit.";
  f.presses = optional_field<std::string>(j, path, in, "presses", "");
  f.presses_hash = optional_field<std::string>(j, path, in, "presses_hash", "");
  f.rotate_degrees = finite(j, path, "rotate_degrees");
  f.scale = finite(j, path, "scale");
  f.touch_radius = finite(j, path, "touch_radius");
  f.contrast = finite(j, path, "contrast");
  f.gain = j.contains("gain") ? finite(j, path, "gain") : 1.0;
  for (const auto& [field, value] :
       {std::pair{"scale", f.scale}, {"touch_radius", f.touch_radius}, {"gain", f.gain}})
    if (!(value > 0)) throw InputError(path, std::string("press_fit.") + field, "must be positive");
  if (!j.contains("mirror") || !j["mirror"].is_boolean())
    throw InputError(path, "press_fit.mirror", "missing, or not true or false");
  f.mirror = j["mirror"].get<bool>();
  f.per_depth = optional_field(j, path, in, "per_depth", false);
  f.start_residual = optional_field(j, path, in, "start_residual", 0.0);
  f.relative_residual = optional_field(j, path, in, "relative_residual", 0.0);
  f.iterations = optional_field(j, path, in, "iterations", 0);
  f.converged = optional_field(j, path, in, "converged", false);
  return f;
}

// noise.FIELD: an array of at most 65,536 finite numbers, each positive unless `gains` (then any,
// and null for a channel the model puts at zero: no ratio, NaN); empty when absent.
Eigen::VectorXd noise_numbers(const nlohmann::json& j, const std::string& path,
                              const std::string& field, bool gains) {
  if (!j.contains(field)) return {};
  const auto& v = j[field];
  if (!v.is_array() || v.size() > 65536)
    throw InputError(path, "noise." + field, "not an array of at most 65,536 numbers");
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (std::size_t k = 0; k < v.size(); ++k) {
    const bool number = v[k].is_number() && std::isfinite(v[k].get<double>());
    if (gains && v[k].is_null()) {
      out[static_cast<Eigen::Index>(k)] = NAN;
    } else if (gains && !number) {
      throw InputError(path, "noise." + field, "must hold finite numbers (or null)");
    } else if (!gains && !(number && v[k].get<double>() > 0)) {
      throw InputError(path, "noise." + field, "must hold positive, finite numbers");
    } else {
      out[static_cast<Eigen::Index>(k)] = v[k].get<double>();
    }
  }
  return out;
}

SensorNoise read_noise(const nlohmann::json& j, const std::string& path) {
  if (!j.is_object()) throw InputError(path, "noise", "must be an object");
  SensorNoise n;
  const std::string in = "noise.";
  n.frames = optional_field<std::string>(j, path, in, "frames", "");
  n.references = optional_field(j, path, in, "references", 0);
  if (n.references < 0) throw InputError(path, "noise.references", "must not be negative");
  for (auto [field, value] : {std::pair{"noise", &n.noise},
                              {"drift", &n.drift},
                              {"signal", &n.signal},
                              {"gain_spread", &n.gain_spread}}) {
    *value = optional_field<double>(j, path, in, field, NAN);
    if (!(*value >= 0) || !std::isfinite(*value))
      throw InputError(path, in + field, "missing, negative or not finite");
  }
  if (!(n.noise > 0)) throw InputError(path, "noise.noise", "must be positive");
  n.inputs = noise_numbers(j, path, "inputs", false);
  n.gains = noise_numbers(j, path, "gains", true);
  return n;
}

}  // namespace

void write_sensor_file(const std::string& path, const SensorFile& s) {
  nlohmann::json j = {{"format", kFormat},
                      {"electrodes", s.electrodes},
                      {"background", s.background},
                      {"contact_impedances", std::vector<double>(s.contact_impedances.data(),
                                                                 s.contact_impedances.data() +
                                                                     s.contact_impedances.size())},
                      {"current", s.current},
                      {"calibration",
                       {{"reference", s.reference},
                        {"relative_residual", s.relative_residual},
                        {"iterations", s.iterations},
                        {"converged", s.converged},
                        {"fitted", s.fitted}}}};
  if (s.press_fit) {
    const SensorPressFit& f = *s.press_fit;
    j["press_fit"] = {{"presses", f.presses},
                      {"presses_hash", f.presses_hash},
                      {"rotate_degrees", f.rotate_degrees},
                      {"mirror", f.mirror},
                      {"scale", f.scale},
                      {"touch_radius", f.touch_radius},
                      {"contrast", f.contrast},
                      {"per_depth", f.per_depth},
                      {"gain", f.gain},
                      {"start_residual", f.start_residual},
                      {"relative_residual", f.relative_residual},
                      {"iterations", f.iterations},
                      {"converged", f.converged}};
  }
  if (s.noise) {
    const SensorNoise& n = *s.noise;
    j["noise"] = {
        {"frames", n.frames},
        {"references", n.references},
        {"noise", n.noise},
        {"inputs", std::vector<double>(n.inputs.data(), n.inputs.data() + n.inputs.size())},
        {"drift", n.drift},
        {"signal", n.signal},
        {"snr_db", n.snr_db()},
        {"gains", std::vector<double>(n.gains.data(), n.gains.data() + n.gains.size())},
        {"gain_spread", n.gain_spread}};
  }
  write_text_atomically(path, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
}

SensorFile read_sensor_file(const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(read_file_bytes(path, 1 << 20));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "", std::string("is not JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("format", "") != kFormat)
    throw InputError(path, "format",
                     std::string("is not an eitbench sensor file (") + kFormat + ")");
  SensorFile s;
  if (!j.contains("electrodes") || !j["electrodes"].is_number_integer())
    throw InputError(path, "electrodes", "missing, or not an integer");
  s.electrodes = j["electrodes"].get<int>();
  if (s.electrodes < 4 || s.electrodes > 256)
    throw InputError(path, "electrodes", "must lie in 4..256");
  s.background = positive(j, path, "background");
  const auto& z = j.contains("contact_impedances") ? j["contact_impedances"] : nlohmann::json();
  if (!z.is_array() || static_cast<int>(z.size()) != s.electrodes)
    throw InputError(path, "contact_impedances", "needs one number an electrode");
  s.contact_impedances.resize(s.electrodes);
  for (int e = 0; e < s.electrodes; ++e) {
    if (!z[e].is_number() || !(z[e].get<double>() > 0) || !std::isfinite(z[e].get<double>()))
      throw InputError(path, "contact_impedances", "must be positive and finite");
    s.contact_impedances[e] = z[e].get<double>();
  }
  if (!j.contains("current") || !j["current"].is_number() || j["current"].get<double>() == 0 ||
      !std::isfinite(j["current"].get<double>()))
    throw InputError(path, "current", "must be a finite, non-zero number");
  s.current = j["current"].get<double>();
  if (j.contains("calibration") && j["calibration"].is_object()) {
    const auto& c = j["calibration"];
    const std::string in = "calibration.";
    s.reference = optional_field<std::string>(c, path, in, "reference", "");
    s.relative_residual = optional_field(c, path, in, "relative_residual", 0.0);
    s.iterations = optional_field(c, path, in, "iterations", 0);
    s.converged = optional_field(c, path, in, "converged", false);
    s.fitted = optional_field(c, path, in, "fitted", true);
  }
  if (j.contains("press_fit")) s.press_fit = read_press_fit(j["press_fit"], path);
  if (j.contains("noise")) s.noise = read_noise(j["noise"], path);
  return s;
}

SensorFile read_sensor_file(const std::string& path, int electrodes, const std::string& whose) {
  SensorFile sensor = read_sensor_file(path);
  if (sensor.electrodes != electrodes)
    throw InputError(path, "electrodes",
                     "calibrates " + std::to_string(sensor.electrodes) + " electrodes; " + whose +
                         " " + std::to_string(electrodes));
  return sensor;
}

bool apply_fitted_sensor(const SensorFile& sensor, ForwardOptions& forward) {
  if (!sensor.fitted) return false;
  forward.contact_impedances = sensor.contact_impedances;
  forward.current = sensor.current;
  return true;
}

}  // namespace eitbench
