#include "options.h"

#include <cmath>
#include <cstdlib>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "eitbench/bench/io/sensor_file.h"

namespace eitbench::cli {
namespace {

CLI::Validator number_check(bool allow_zero) {
  return CLI::Validator(
      [allow_zero](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(v) || v < 0 ||
            (!allow_zero && v == 0))
          return "'" + text + "' must be a " +
                 (allow_zero ? "finite number, zero or more" : "positive, finite number");
        return "";
      },
      allow_zero ? "NONNEGATIVE" : "POSITIVE");
}

}  // namespace

const CLI::Validator kPositive = number_check(false);
const CLI::Validator kNonNegative = number_check(true);

void add_mesh_options(CLI::App& app, MeshSource& s) {
  auto* mesh = app.add_option("--mesh", s.file,
                              "Gmsh mesh (.msh 2.2 or 4.1, ASCII) with electrode_0.. groups");
  auto* electrodes =
      app.add_option("--electrodes", s.disk.electrodes, "electrodes L of a generated mesh")
          ->capture_default_str()
          ->check(CLI::Range(4, 256));
  auto* density = app.add_option("--density", s.density, "coarse | medium | fine (generated mesh)")
                      ->capture_default_str()
                      ->check(CLI::IsMember({"coarse", "medium", "fine"}));
  auto* coverage = app.add_option("--electrode-coverage", s.disk.electrode_coverage,
                                  "fraction of the rim under electrodes (each is coverage/L of it)")
                       ->capture_default_str()
                       ->check(CLI::Range(0.001, 0.999));
  auto* radius = app.add_option("--radius", s.disk.radius, "disk radius R")
                     ->capture_default_str()
                     ->check(kPositive);
  for (auto* o : {electrodes, density, coverage, radius}) mesh->excludes(o);
}

void add_shape_options(CLI::App& app, MeshSource& s) {
  auto* mesh = app.get_option("--mesh");
  auto* shape = app.add_option("--shape", s.shape,
                               "generate this sensor: disk | rectangle | ellipse (default: the "
                               "D_L-symmetric disk of --radius)")
                    ->check(CLI::IsMember({"disk", "rectangle", "ellipse"}));
  auto* width = app.add_option("--width", s.other.width,
                               "--shape: the rectangle's width or the ellipse's axis along x")
                    ->capture_default_str()
                    ->check(kPositive);
  auto* height = app.add_option("--height", s.other.height,
                                "--shape: the rectangle's height or the ellipse's axis along y")
                     ->capture_default_str()
                     ->check(kPositive);
  auto* positions = app.add_option("--electrode-positions", s.other.electrode_positions,
                                   "--shape: electrode centres as fractions of the perimeter, "
                                   "counter-clockwise from the +x "
                                   "axis, \"f0,f1,...\" (default: (e + 1/2) / L; on a disk e / L)")
                        ->delimiter(',');
  for (auto* o : {shape, width, height, positions}) mesh->excludes(o);
  for (auto* o : {width, height, positions}) o->needs(shape);
  app.get_option("--radius")->excludes(width)->excludes(height);
}

Mesh load_mesh(MeshSource& s) {
  if (!s.file.empty()) return read_msh_file(s.file);
  s.disk.density = parse_density(s.density);
  if (s.shape.empty()) return generate_disk_mesh(s.disk);
  ShapeMeshOptions& o = s.other;
  o.shape = parse_shape(s.shape);
  o.electrodes = s.disk.electrodes;
  o.density = s.disk.density;
  o.electrode_coverage = s.disk.electrode_coverage;
  if (o.shape == SensorShape::disk) o.width = o.height = 2 * s.disk.radius;
  return generate_shape_mesh(o);
}

void add_conductivity_options(CLI::App& app, ConductivitySource& s) {
  auto* uniform =
      app.add_option("--conductivity", s.uniform, "uniform conductivity S (S/m)")->check(kPositive);
  auto* file =
      app.add_option("--element-conductivity", s.file, "CSV with one conductivity per triangle");
  auto* circles =
      app.add_option("--circles", s.circles, "circular inclusions \"x,y,r,s;...\" on --background");
  app.add_option("--background", s.background, "background conductivity for --circles (S/m)")
      ->capture_default_str()
      ->check(kPositive);
  uniform->excludes(file)->excludes(circles);
  file->excludes(circles);
}

Eigen::VectorXd load_conductivity(const CLI::App& app, const ConductivitySource& s,
                                  const Mesh& mesh) {
  const int T = mesh.num_triangles();
  if (app.count("--element-conductivity")) {
    const std::vector<double> v = read_numbers(s.file);
    if (static_cast<int>(v.size()) != T)
      throw InputError(s.file, "values",
                       "has " + std::to_string(v.size()) + " conductivities, the mesh has " +
                           std::to_string(T) + " triangles");
    for (int t = 0; t < T; ++t)
      if (!(v[t] > 0))
        throw InputError(s.file, "value " + std::to_string(t + 1), "conductivity must be positive");
    return Eigen::Map<const Eigen::VectorXd>(v.data(), T);
  }
  if (app.count("--circles")) {
    const auto circles = parse_circles(s.circles, "--circles");
    return conductivity_from_circles(mesh, circles, s.background);
  }
  if (app.count("--conductivity")) return Eigen::VectorXd::Constant(T, s.uniform);
  throw InputError("conductivity", "",
                   "give one of --conductivity, --element-conductivity or --circles");
}

void add_model_options(CLI::App& app, ModelSetup& s) {
  auto* z = app.add_option("--contact-impedance", s.forward.contact_impedance,
                           "contact impedance z_c of every electrode")
                ->capture_default_str()
                ->check(kPositive);
  auto* sensor = app.add_option("--sensor", s.sensor,
                                "a calibrated sensor file (eitbench calibrate): its contact "
                                "impedances, one an electrode, and its current");
  sensor->excludes(z);
  app.add_option("--current", s.forward.current, "drive current I (finite, non-zero)")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (end == text.c_str() || *end != '\0' || !std::isfinite(v) || v == 0)
              return "'" + text + "' must be a finite, non-zero number";
            return "";
          },
          "NONZERO"));
  app.add_option("--order", s.order, "measurement order: rotating | ascending")
      ->capture_default_str()
      ->check(CLI::IsMember({"rotating", "ascending"}));
  app.add_option(
         "--values", s.values,
         "all L(L-3) values (208 | full) or the L(L-3)/2 reciprocity-reduced ones (104 | "
         "reduced); forward also writes every adjacent pair as an L x L map (256 | map), the "
         "reference calibrate needs")
      ->capture_default_str();
}

void add_protocol_options(CLI::App& app, ProtocolChoice& c) {
  app.add_option("--protocol", c.spec,
                 "measurement protocol: adjacent | adjacent-ascending | opposite (drive e -> "
                 "e+L/2, OpenEIT's 192 for 16 electrodes) | skip-K (drive e -> e+K+1) | FILE.csv "
                 "(a header, then drive+,drive-,meas+,meas- a line, electrodes 0-based)")
      ->capture_default_str();
  app.add_flag("--magnitude", c.magnitude,
               "frames are magnitudes |v| (OpenEIT and similar boards): the model's frames and "
               "Jacobian are those of |v|, the sign taken from the homogeneous solution");
}

std::shared_ptr<const MeasurementProtocol> load_protocol(const ProtocolChoice& c, int electrodes) {
  return std::make_shared<const MeasurementProtocol>(
      make_protocol(c.spec, electrodes).with_magnitude(c.magnitude));
}

std::shared_ptr<const MeasurementProtocol> chosen_protocol(const ProtocolChoice& c,
                                                           int electrodes) {
  if (c.spec == "adjacent" && !c.magnitude) return nullptr;
  return load_protocol(c, electrodes);
}

void check_protocol_of(const ProtocolChoice& c, const MeasurementProtocol& data,
                       const std::string& path) {
  const auto chosen = chosen_protocol(c, data.electrodes());
  if (!chosen || chosen->same_channels(data)) return;
  throw InputError(c.spec == "adjacent" ? "--magnitude" : "--protocol", "",
                   "the data set " + path + " is read on the " + data.name() + " protocol (" +
                       std::to_string(data.size()) + " channels" +
                       (data.magnitude() ? ", magnitudes" : "") + "), not on " + chosen->name() +
                       " (" + std::to_string(chosen->size()) + " channels" +
                       (chosen->magnitude() ? ", magnitudes" : "") +
                       "): leave the flags out to use the set's own");
}

std::optional<SensorFile> load_sensor(const std::string& path, int electrodes) {
  if (path.empty()) return std::nullopt;
  return read_sensor_file(path, electrodes, "the mesh has");
}

void apply_sensor(ModelSetup& s, const Mesh& mesh) {
  const auto sensor = load_sensor(s.sensor, mesh.num_electrodes());
  if (sensor) apply_fitted_sensor(*sensor, s.forward);
}

bool reduced_values(const ModelSetup& s, int L) {
  const int full = L * (L - 3), reduced = full / 2;
  if (s.values == "full" || s.values == std::to_string(full)) return false;
  if (s.values == "reduced" || s.values == std::to_string(reduced)) return true;
  throw InputError("--values", "",
                   "'" + s.values + "' does not fit " + std::to_string(L) + " electrodes: use " +
                       std::to_string(full) + " (full) or " + std::to_string(reduced) +
                       " (reduced)");
}

namespace {
// "MIN,MAX" into two numbers.
void add_range(CLI::App& app, const std::string& flag, double& lo, double& hi,
               const std::string& help) {
  app.add_option_function<std::vector<double>>(
         flag, [&lo, &hi](const std::vector<double>& v) { lo = v[0], hi = v[1]; }, help)
      ->delimiter(',')
      ->expected(2)
      ->type_name("MIN,MAX");
}
}  // namespace

void add_variation_options(CLI::App& app, SimulationVariation& v) {
  add_range(app, "--touch-radius", v.radius_min, v.radius_max,
            "each touch's radius drawn uniformly in [MIN, MAX] (x R; default: 0.05,0.25), e.g. "
            "the sensor fit's press radius");
  add_range(app, "--touch-contrast", v.contrast_min, v.contrast_max,
            "with --touch-radius: each touch's contrast c (sigma = sigma_0 (1 - c)) uniform in "
            "[MIN, MAX] (default: sigma uniform in [0.0001, 0.05] S/m)");
  app.add_option("--randomise-electrodes", v.electrode_shift_deg,
                 "domain randomisation: each sample's electrodes turned along the rim by U(-DEG, "
                 "DEG) degrees (the disk; 0: off)")
      ->check(kNonNegative)
      ->type_name("DEG");
  app.add_option("--randomise-impedance", v.impedance_spread,
                 "domain randomisation: each sample's contact impedances, each electrode's x "
                 "e^U(-S, S) (0: off)")
      ->check(kNonNegative);
  app.add_option("--randomise-gain", v.gain_error,
                 "domain randomisation: each sample's channel gains 1 + N(0, G) (0: off)")
      ->check(kNonNegative);
  add_range(app, "--randomise-snr", v.snr_min_db, v.snr_max_db,
            "domain randomisation: each sample's change with noise at an SNR uniform in [MIN, "
            "MAX] dB");
  app.add_option_function<std::string>(
         "--sensor-noise",
         [&v](const std::string& path) {
           try {
             const std::optional<SensorNoise> noise = read_sensor_file(path).noise;
             if (!noise)
               throw InputError(path, "noise",
                                "is absent: measure it with calibrate --noise SET --out FILE");
             v.sensor_gains = noise->gains, v.sensor_noise = noise->noise;
           } catch (const InputError& e) {
             throw CLI::ValidationError("--sensor-noise", e.what());
           }
         },
         "a sensor file with the real sensor's noise (calibrate --noise): every sample's change "
         "times its measured channel gains, plus its measured noise (docs/real-presses.md)")
      ->type_name("FILE");
}

void add_shard_option(CLI::App& app, int& index, int& count) {
  app.add_option_function<std::string>(
         "--shard",
         [&index, &count](const std::string& text) {
           const auto slash = text.find('/');
           try {
             std::size_t k_end = 0, n_end = 0;
             if (slash == std::string::npos) throw std::invalid_argument(text);
             index = std::stoi(text.substr(0, slash), &k_end);
             count = std::stoi(text.substr(slash + 1), &n_end);
             if (k_end != slash || n_end != text.size() - slash - 1)
               throw std::invalid_argument(text);
           } catch (const std::logic_error&) {
             throw CLI::ValidationError("--shard", "'" + text + "' is not K/N (e.g. 0/4)");
           }
           if (!(count >= 1 && count <= 100000 && index >= 0 && index < count))
             throw CLI::ValidationError("--shard", "'" + text + "' needs 0 <= K < N <= 100000");
         },
         "this process's part of the work: shard K of N (0-based), each written on its own; "
         "`eitbench merge` joins them into what one process writes (docs/scaling.md)")
      ->type_name("K/N");
}

std::pair<int, int> parse_range(const std::string& text, int n, const char* flag) {
  if (text.empty()) return {0, n};
  const auto colon = text.find(':');
  auto number = [&](const std::string& s, int fallback) {
    if (s.empty()) return fallback;
    char* end = nullptr;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (*end != '\0') throw InputError(flag, "", "'" + text + "' is not a range A:B");
    return static_cast<int>(v);
  };
  if (colon == std::string::npos) throw InputError(flag, "", "'" + text + "' is not a range A:B");
  const int a = number(text.substr(0, colon), 0), b = number(text.substr(colon + 1), n);
  if (a < 0 || b > n || a >= b)
    throw InputError(flag, "",
                     "range " + text + " is empty or outside the " + std::to_string(n) + " frames");
  return {a, b};
}

}  // namespace eitbench::cli
