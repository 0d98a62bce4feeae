#include "eitbench/bench/data/simulate.h"

#include <fmt/core.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <optional>

#include "eitbench/augment/sensor_group.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/electrode_shift.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/forward_model.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/jacobian/random.h"

namespace eitbench {

PresetCounts preset_counts(const std::string& preset) {
  // The paper's EdEIT counts, and the same proportions scaled down.
  const double base[4] = {7035, 7298, 7500, 7500};
  double scale;
  if (preset == "paper")
    scale = 1.0;
  else if (preset == "standard")
    scale = 0.25;
  else if (preset == "quick")
    scale = 2000.0 / 21833.0;
  else if (preset == "tiny")
    scale = 60.0 / 21833.0;  // for tests: seconds, every code path
  else
    throw InputError("--preset", "", "unknown preset '" + preset + "' (quick, standard or paper)");
  PresetCounts counts{};
  for (int k = 0; k < 4; ++k)
    counts.circles[k] = std::max(3, static_cast<int>(std::lround(base[k] * scale)));
  counts.validation = static_cast<int>(std::lround(counts.circles[3] * 5000.0 / 7500.0));
  return counts;
}

void SimulationVariation::validate() const {
  if (touches_set() || radius_min != 0) {
    if (!(radius_min > 0 && radius_min <= radius_max && radius_max < 1))
      throw InputError("--touch-radius", "", "needs 0 < MIN <= MAX < 1 (x R)");
    if (!(contrast_min >= 0 && contrast_min <= contrast_max && contrast_max > 0 &&
          contrast_max < 1))
      throw InputError("--touch-contrast", "",
                       "needs 0 <= MIN <= MAX < 1 and MAX > 0 (with --touch-radius: touches of "
                       "contrast 0 change nothing)");
  } else if (contrast_max != 0 || contrast_min != 0) {
    throw InputError("--touch-contrast", "", "goes with --touch-radius");
  }
  if (!(electrode_shift_deg >= 0 && electrode_shift_deg <= 45))
    throw InputError("--randomise-electrodes", "", "must lie in [0, 45] degrees");
  if (!(impedance_spread >= 0 && impedance_spread <= 3))
    throw InputError("--randomise-impedance", "", "must lie in [0, 3] (a factor up to e^3)");
  if (!(gain_error >= 0 && gain_error < 0.5))
    throw InputError("--randomise-gain", "", "must lie in [0, 0.5)");
  if (snr_max_db != 0 && !(snr_min_db > 0 && snr_min_db <= snr_max_db && snr_max_db <= 200))
    throw InputError("--randomise-snr", "", "needs 0 < MIN <= MAX <= 200 (dB)");
  if (!(sensor_noise >= 0 && sensor_noise < 1))
    throw InputError("--sensor-noise", "noise", "must lie in [0, 1) (of the reference's RMS)");
  for (Eigen::Index c = 0; c < sensor_gains.size(); ++c)
    if (!std::isnan(sensor_gains(c)) && !(std::isfinite(sensor_gains(c)) && sensor_gains(c) > 0))
      throw InputError("--sensor-noise", "gains", "must be positive and finite (or null)");
}

std::string describe(const SimulationVariation& v) {
  std::string out;
  if (v.touches_set())
    out = fmt::format("touches {:g}-{:g} R, contrast {:g}-{:g}", v.radius_min, v.radius_max,
                      v.contrast_min, v.contrast_max);
  std::string r;
  auto add = [&r](const std::string& part) { r += (r.empty() ? "" : ", ") + part; };
  if (v.electrode_shift_deg > 0) add(fmt::format("electrodes +-{:g} deg", v.electrode_shift_deg));
  if (v.impedance_spread > 0)
    add(fmt::format("impedances x e^U(-{0:g}, {0:g})", v.impedance_spread));
  if (v.gain_error > 0) add(fmt::format("gains {:g} %", 100 * v.gain_error));
  if (v.snr_max_db > 0) add(fmt::format("SNR {:g}-{:g} dB", v.snr_min_db, v.snr_max_db));
  if (v.like_sensor()) {
    double sum = 0;  // the gains' fingerprint, so that a resumed run tells two sensors apart
    for (Eigen::Index c = 0; c < v.sensor_gains.size(); ++c)
      if (std::isfinite(v.sensor_gains(c))) sum += (c + 1) * v.sensor_gains(c);
    add(fmt::format("the sensor's noise {:.4g} % and {} gains (weighted sum {:.6g})",
                    100 * v.sensor_noise, v.sensor_gains.size(), sum));
  }
  if (!r.empty()) out += (out.empty() ? "" : "; ") + std::string("randomised: ") + r;
  return out;
}

std::string with_variation(const std::string& mesh, const SimulationVariation& v) {
  const std::string variation = describe(v);
  return variation.empty() ? mesh : mesh + "; " + variation;
}

namespace {

// k non-overlapping circles by rejection (docs/conventions.md): `propose` draws one candidate, or
// none when it falls outside the sensor; a fresh start in the (rare) case the last circle finds no
// room. A sensor too thin for k touches of these sizes is refused rather than tried for ever.
template <typename Propose>
std::vector<Circle> draw_circles(int k, RandomStream& rng, Propose propose) {
  for (int restart = 0; restart < 100; ++restart) {
    std::vector<Circle> circles;
    for (int attempt = 0; static_cast<int>(circles.size()) < k && attempt < 10000; ++attempt) {
      const std::optional<Circle> c = propose(rng);
      if (!c) continue;
      bool free = true;
      for (const Circle& o : circles) free &= std::hypot(c->x - o.x, c->y - o.y) >= c->r + o.r;
      if (free) circles.push_back(*c);
    }
    if (static_cast<int>(circles.size()) == k) return circles;
  }
  throw InputError("sensor mesh", "",
                   "no room for " + std::to_string(k) +
                       " separate touches of the drawn radii inside the sensor (R: half its "
                       "larger side): is it very thin, or --touch-radius too large?");
}

// A touch's radius and conductivity: the presets' draws, or the variation's ranges.
struct TouchDraw {
  const SimulationVariation& v;
  double background;
  double radius(RandomStream& g, double R) const {
    return v.touches_set() ? g.uniform(v.radius_min * R, v.radius_max * R)
                           : g.uniform(0.05 * R, 0.25 * R);
  }
  double sigma(RandomStream& g) const {
    return v.touches_set() ? background * (1 - g.uniform(v.contrast_min, v.contrast_max))
                           : g.uniform(0.0001, 0.05);
  }
};

// Fully inside the disk of radius R: centres uniform over the disk of radius R - r.
std::vector<Circle> draw_circles(int k, double R, const TouchDraw& touch, RandomStream& rng) {
  return draw_circles(k, rng, [R, &touch](RandomStream& g) -> std::optional<Circle> {
    const double r = touch.radius(g, R);
    const double rho = (R - r) * std::sqrt(g.uniform()), phi = 2 * M_PI * g.uniform();
    const double sigma = touch.sigma(g);
    return Circle{rho * std::cos(phi), rho * std::sin(phi), r, sigma};
  });
}

// On a sensor of any shape: centres uniform over the grid's box, kept when inside the mesh and at
// least r from its boundary; radii as on the disk, in units of the grid's R.
std::vector<Circle> draw_circles(int k, const MeshDomain& domain, const PixelGrid& grid,
                                 const TouchDraw& touch, RandomStream& rng) {
  const double R = grid.radius();
  return draw_circles(k, rng, [&](RandomStream& g) -> std::optional<Circle> {
    const double r = touch.radius(g, R);
    const double x = g.uniform(-R, R), y = g.uniform(-R, R);  // in this order, always
    const Eigen::Vector2d at = grid.box_centre() + Eigen::Vector2d(x, y);
    const double sigma = touch.sigma(g);
    if (!domain.contains(at) || domain.boundary_distance(at) < r) return std::nullopt;
    return Circle{at.x(), at.y(), r, sigma};
  });
}

// One sample's change on its own draw of the sensor: electrodes shifted along the rim and contact
// impedances spread about the nominal ones (its own model, and its own empty frame to differ
// from), channel gains, then noise at a drawn SNR. Draws after the sample's circles, from its
// stream, so thread counts do not matter; a part left at zero draws nothing.
Eigen::VectorXd randomised_change(const ForwardModel& nominal, const Eigen::VectorXd& reference,
                                  const ForwardOptions& forward, const std::vector<Circle>& circles,
                                  const Eigen::VectorXd& sigma, double background,
                                  const SimulationVariation& v, RandomStream& rng) {
  const Mesh& mesh = nominal.mesh();
  Eigen::VectorXd change;
  if (v.electrode_shift_deg > 0 || v.impedance_spread > 0) {  // a model of its own
    std::optional<Mesh> shifted;
    if (v.electrode_shift_deg > 0) {
      std::vector<double> shifts(mesh.num_electrodes());
      for (auto& s : shifts)
        s = rng.uniform(-v.electrode_shift_deg, v.electrode_shift_deg) * M_PI / 180;
      shifted = shift_electrodes(mesh, shifts);
    }
    const Mesh& own_mesh = shifted ? *shifted : mesh;
    ForwardOptions own = forward;
    if (v.impedance_spread > 0) {
      own.contact_impedances.resize(mesh.num_electrodes());
      for (auto& z : own.contact_impedances)
        z = forward.contact_impedance *
            std::exp(rng.uniform(-v.impedance_spread, v.impedance_spread));
    }
    // Impedances alone: the nominal model's checks, pattern and analysis serve (the same bits).
    const ForwardModel model = shifted ? ForwardModel(own_mesh, own)
                                       : nominal.with_contact_impedances(own.contact_impedances);
    const Eigen::VectorXd own_sigma =
        shifted ? conductivity_from_circles(own_mesh, circles, background) : sigma;
    change = model.measured(own_sigma) -
             model.measured(Eigen::VectorXd::Constant(mesh.num_triangles(), background));
  } else {
    change = nominal.measured(sigma) - reference;
  }
  if (v.gain_error > 0)
    for (auto& c : change) c *= 1 + v.gain_error * rng.normal();
  if (v.snr_max_db > 0) {
    const double snr = rng.uniform(v.snr_min_db, v.snr_max_db);
    const double sd = std::sqrt(change.squaredNorm() / static_cast<double>(change.size()) /
                                std::pow(10.0, snr / 10));
    for (auto& c : change) c += sd * rng.normal();
  }
  if (v.like_sensor()) {
    const double sd = v.sensor_noise * reference.norm() / std::sqrt(double(reference.size()));
    for (Eigen::Index c = 0; c < change.size(); ++c) {
      const bool gained =
          v.sensor_gains.size() == change.size() && std::isfinite(v.sensor_gains(c));
      change(c) = (gained ? v.sensor_gains(c) : 1.0) * change(c) + sd * rng.normal();
    }
  }
  return change;
}

// The meshes and grid a simulation works on: the disk's, or a sensor mesh's.
struct SimulationGeometry {
  Mesh sensor;      // where touches are drawn (the reconstruction mesh for a sensor mesh)
  Mesh simulation;  // where frames are made
  PixelGrid grid;
  std::string description;
};

SimulationGeometry simulation_geometry(const SimulationOptions& o) {
  if (o.sensor_mesh) {
    const Mesh& mesh = *o.sensor_mesh;
    return {mesh, refine_mesh(mesh), PixelGrid::covering(mesh, o.image_size),
            (o.sensor_source.empty() ? std::string("sensor mesh") : o.sensor_source) +
                ", refined once"};
  }
  DiskMeshOptions disk;
  disk.electrodes = o.electrodes;
  disk.density = o.density;
  disk.electrode_coverage = o.electrode_coverage;
  Mesh mesh = generate_disk_mesh(disk);
  return {mesh, mesh, PixelGrid(o.image_size, disk.radius),
          "disk L=" + std::to_string(o.electrodes) + " " + to_string(o.density)};
}

// The shift's bound: two neighbours may differ by twice it, and shift_electrodes takes at most
// half the narrowest gap between them.
void check_electrode_shift(const SimulationOptions& o, const Mesh& mesh) {
  const double d = o.variation.electrode_shift_deg;
  if (d == 0) return;
  if (o.sensor_mesh)
    throw InputError("--randomise-electrodes", "",
                     "moves the disk's electrodes; a sensor mesh's stay where the mesh has them");
  const double limit = max_neighbour_shift(mesh) / 2 * 180 / M_PI;
  if (d > limit)
    throw InputError("--randomise-electrodes", "",
                     fmt::format("{:g} degrees is more than this disk allows ({:.3g}: a quarter "
                                 "of the gap between electrodes)",
                                 d, limit));
}

}  // namespace

std::pair<int, int> shard_rows(const SimulationOptions& o, int n) {
  if (!(o.shard_count >= 1 && o.shard_index >= 0 && o.shard_index < o.shard_count))
    throw InputError("--shard", "", "needs K/N with 0 <= K < N");
  const auto bound = [&](int k) {
    return static_cast<int>(static_cast<long long>(n) * k / o.shard_count);
  };
  if (bound(o.shard_index + 1) == bound(o.shard_index))
    throw InputError("--shard", "",
                     fmt::format("shard {} of {} holds none of the set's {} samples: use fewer "
                                 "shards",
                                 o.shard_index, o.shard_count, n));
  return {bound(o.shard_index), bound(o.shard_index + 1)};
}

Dataset simulate_dataset(const SimulationOptions& o, const ProgressFn& progress) {
  const PresetCounts counts = preset_counts(o.preset);
  o.variation.validate();
  if (!(o.background > 0)) throw InputError("--background", "", "must be positive");
  const SimulationGeometry geometry = simulation_geometry(o);
  const Mesh& mesh = geometry.simulation;
  check_electrode_shift(o, mesh);
  ForwardOptions forward;
  forward.current = o.current;
  forward.contact_impedance = o.contact_impedance;
  forward.protocol = o.protocol;
  const ForwardModel model(mesh, forward);
  const PixelGrid& grid = geometry.grid;
  const auto domain = o.sensor_mesh ? std::make_unique<MeshDomain>(geometry.sensor) : nullptr;
  const MeasurementProtocol& protocol = model.measurement_protocol();
  const Eigen::Index gains = o.variation.sensor_gains.size();
  if (gains > 0 && gains != protocol.size())
    throw InputError("--sensor-noise", "gains",
                     fmt::format("has {} channels' gains; the {} protocol has {}: measure them on "
                                 "frames read on it",
                                 gains, protocol.name(), protocol.size()));

  Dataset data;
  data.electrodes = mesh.num_electrodes();
  data.radius = grid.radius();
  data.background = o.background;
  data.contact_impedance = o.contact_impedance;
  data.current = o.current;
  data.electrode_coverage = o.electrode_coverage;
  data.image_size = o.image_size;
  data.seed = o.seed;
  data.preset = o.preset;
  data.simulation_mesh = with_variation(geometry.description, o.variation);
  if (o.sensor_mesh) {
    data.sensor_mesh = mesh_text(*o.sensor_mesh);
    data.sensor_group = find_sensor_group(*o.sensor_mesh, {}, o.sensor_source).name();
  }
  data.simulation_triangles = mesh.num_triangles();
  data.program = program_version();
  set_protocol(data, protocol);
  data.reference = model.measured(Eigen::VectorXd::Constant(mesh.num_triangles(), o.background));

  int n = 0;
  for (int c : counts.circles) n += c;
  std::vector<int> circle_count(n);
  std::vector<Split> split;
  for (int k = 0, i = 0; k < 4; ++k)
    for (int j = 0; j < counts.circles[k]; ++j, ++i) {
      circle_count[i] = k + 1;
      const bool four = k == 3;
      split.push_back(!four                   ? Split::train
                      : j < counts.validation ? Split::validation
                                              : Split::test);
    }
  const auto [first, last] = shard_rows(o, n);
  const int rows = last - first;
  data.split.assign(split.begin() + first, split.begin() + last);
  if (o.shard_count > 1) data.shard = {o.shard_index, o.shard_count, first, n};
  data.frames.resize(rows, protocol.size());
  data.differences.resize(rows, protocol.input_size());
  data.labels.resize(rows, grid.num_pixels());
  data.circles.resize(rows);

  const TouchDraw touch{o.variation, o.background};
  std::atomic<int> done{0};
  tbb::task_arena arena(o.threads > 0 ? o.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(0, rows, [&](int row) {
      const int i = first + row;  // the sample's index in the whole set
      RandomStream rng(o.seed, static_cast<std::uint64_t>(i));  // sample i's own stream
      auto& circles = data.circles[row];
      circles = o.sensor_mesh ? draw_circles(circle_count[i], *domain, grid, touch, rng)
                              : draw_circles(circle_count[i], grid.radius(), touch, rng);
      const Eigen::VectorXd sigma = conductivity_from_circles(mesh, circles, o.background);
      if (o.variation.randomised()) {  // the frame the nominal sensor would give that change
        const Eigen::VectorXd change = randomised_change(model, data.reference, forward, circles,
                                                         sigma, o.background, o.variation, rng);
        data.frames.row(row) = (data.reference + change).transpose();
        data.differences.row(row) = protocol.to_inputs(change).transpose();
      } else {
        const Eigen::VectorXd frame = model.measured(sigma);
        data.frames.row(row) = frame.transpose();
        data.differences.row(row) = protocol.to_inputs(frame - data.reference).transpose();
      }
      // Labels are float32 in the file: rounded here too, so that a set in memory and the same
      // set read back are identical (a training checkpoint hashes them).
      data.labels.row(row) =
          circles_image(grid, circles, o.background).cast<float>().cast<double>().transpose();
      const int finished = ++done;
      if (progress) progress(finished, rows);
    });
  });
  return data;
}

}  // namespace eitbench
