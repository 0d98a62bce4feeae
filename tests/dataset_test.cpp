// The simulated data set (docs/conventions.md) and its HDF5 file.
#include <H5Cpp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "eitbench/augment.h"
#include "eitbench/bench/data/augment_file.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/dataset_shards.h"
#include "eitbench/bench/data/noise.h"
#include "eitbench/bench/data/simulate.h"
#include "eitbench/bench/data/training_data.h"
#include "eitbench/jacobian.h"
#include "eitbench/jacobian/error.h"
#include "test_support.h"

namespace eitbench {
namespace {
namespace fs = std::filesystem;

std::string dataset_path(const std::string& name) {
  return (fs::temp_directory_path() / ("eitbench_ds_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// The tiny preset's options: seconds to simulate, every code path.
SimulationOptions tiny_options(std::uint64_t seed, MeshDensity density) {
  SimulationOptions o;
  o.preset = "tiny";
  o.seed = seed;
  o.density = density;
  return o;
}

const Dataset& tiny_set() {
  static const Dataset data = [] {
    return simulate_dataset(tiny_options(11, MeshDensity::medium));
  }();
  return data;
}

TEST(Presets, PaperCountsAreEdEITs) {
  const PresetCounts paper = preset_counts("paper");
  EXPECT_EQ(paper.circles[0], 7035);
  EXPECT_EQ(paper.circles[1], 7298);
  EXPECT_EQ(paper.circles[2], 7500);
  EXPECT_EQ(paper.circles[3], 7500);
  EXPECT_EQ(paper.circles[0] + paper.circles[1] + paper.circles[2], 21833);
  EXPECT_EQ(paper.validation, 5000);
  const PresetCounts quick = preset_counts("quick");
  const int train = quick.circles[0] + quick.circles[1] + quick.circles[2];
  EXPECT_NEAR(train, 2000, 5);
  EXPECT_NEAR(quick.validation / double(quick.circles[3]), 2.0 / 3.0, 0.01);
  EXPECT_THROW(preset_counts("huge"), InputError);
}

TEST(Simulate, SplitsFollowTheCircleCounts) {
  const Dataset& d = tiny_set();
  const PresetCounts counts = preset_counts("tiny");
  ASSERT_EQ(d.size(),
            counts.circles[0] + counts.circles[1] + counts.circles[2] + counts.circles[3]);
  for (int i = 0; i < d.size(); ++i) {
    const bool four = d.circles[i].size() == 4;
    EXPECT_EQ(d.split[i] == Split::train, !four) << i;
  }
  EXPECT_EQ(static_cast<int>(d.indices(Split::validation).size()), counts.validation);
}

// The data-efficiency sweep's subsets: a simulated set stores its training frames by touch count
// (one touch first), so a subset must be drawn, not taken from the front, or every small size
// trains on one-touch frames alone.
TEST(TrainingSubset, DrawnNestedAndFromEveryTouchCount) {
  const std::vector<int> train = tiny_set().indices(Split::train);
  const auto twenty = subset_rows(train, 20, 1), forty = subset_rows(train, 40, 1);
  ASSERT_EQ(twenty.size(), 20u);
  EXPECT_TRUE(std::is_sorted(twenty.begin(), twenty.end()));
  EXPECT_EQ(std::adjacent_find(twenty.begin(), twenty.end()), twenty.end());  // no repeats
  EXPECT_TRUE(std::includes(forty.begin(), forty.end(), twenty.begin(), twenty.end()));
  EXPECT_TRUE(std::includes(train.begin(), train.end(), forty.begin(), forty.end()));
  EXPECT_EQ(subset_rows(train, 20, 1), twenty);  // the same seed, the same subset
  EXPECT_NE(subset_rows(train, 20, 2), twenty);
  EXPECT_EQ(subset_rows(train, 0, 1), train);
  EXPECT_EQ(subset_rows(train, 1000, 1), train);
  std::set<std::size_t> touches;
  for (int row : twenty) touches.insert(tiny_set().circles[row].size());
  EXPECT_EQ(touches, (std::set<std::size_t>{1, 2, 3}));
  // labelled_frames takes those rows.
  const LabelledFrames frames = labelled_frames(tiny_set(), Split::train, 20, 1);
  ASSERT_EQ(frames.frames.rows(), 20);
  for (int k = 0; k < 20; ++k)
    EXPECT_EQ(frames.frames.row(k), tiny_set().differences.row(twenty[k]));
}

TEST(Simulate, CirclesAreInsideAndApart) {
  const Dataset& d = tiny_set();
  for (const auto& circles : d.circles)
    for (std::size_t a = 0; a < circles.size(); ++a) {
      const Circle& c = circles[a];
      EXPECT_LE(std::hypot(c.x, c.y) + c.r, d.radius + 1e-12);
      EXPECT_GE(c.r, 0.05 * d.radius);
      EXPECT_LE(c.r, 0.25 * d.radius);
      EXPECT_GE(c.conductivity, 0.0001);
      EXPECT_LE(c.conductivity, 0.05);
      for (std::size_t b = a + 1; b < circles.size(); ++b)
        EXPECT_GE(std::hypot(c.x - circles[b].x, c.y - circles[b].y), c.r + circles[b].r);
    }
}

TEST(Simulate, LabelsConserveTheTouch) {
  // sum of intensities x pixel area = sum of pi r^2 (sigma_0 - sigma) / sigma_0, within 1 %.
  const Dataset& d = tiny_set();
  const double pixel_area = std::pow(2 * d.radius / d.image_size, 2);
  for (int i = 0; i < d.size(); ++i) {
    double expected = 0;
    for (const Circle& c : d.circles[i])
      expected += M_PI * c.r * c.r * (d.background - c.conductivity) / d.background;
    EXPECT_NEAR(d.labels.row(i).sum() * pixel_area, expected, 0.01 * expected) << i;
    EXPECT_GE(d.labels.row(i).minCoeff(), 0.0);
    EXPECT_LT(d.labels.row(i).maxCoeff(), 1.0);
  }
}

TEST(Simulate, FramesAreForwardSolutionsAndDifferencesFollow) {
  const Dataset& d = tiny_set();
  const Mesh mesh = generate_disk_mesh({16, MeshDensity::medium});
  const ForwardModel model(mesh);
  const Protocol& p = model.protocol();
  for (int i : {0, d.size() / 2, d.size() - 1}) {
    const Eigen::VectorXd v =
        model.frame(conductivity_from_circles(mesh, d.circles[i], d.background));
    EXPECT_LT((v - d.frames.row(i).transpose()).norm(), 1e-12 * v.norm());
    const Eigen::VectorXd dv = p.reduce(v - d.reference, MeasurementOrder::rotating);
    EXPECT_LT((dv - d.differences.row(i).transpose()).norm(), 1e-12 * v.norm());
  }
  EXPECT_LT(
      (d.reference - model.frame(Eigen::VectorXd::Constant(mesh.num_triangles(), d.background)))
          .norm(),
      1e-13);
}

TEST(Simulate, IsDeterministicWhateverTheThreadCount) {
  SimulationOptions o = tiny_options(11, MeshDensity::medium);
  o.threads = 1;
  const Dataset one = simulate_dataset(o);
  const Dataset& many = tiny_set();  // all cores
  EXPECT_EQ(one.frames, many.frames);
  EXPECT_EQ(one.labels, many.labels);
  // And through the file: the same seed gives the same data sets.
  const std::string a = dataset_path("a.h5"), b = dataset_path("b.h5");
  write_dataset(a, one);
  write_dataset(b, many);
  const Dataset ra = read_dataset(a), rb = read_dataset(b);
  EXPECT_EQ(ra.differences, rb.differences);
  EXPECT_EQ(ra.labels, rb.labels);
  o.seed = 12;
  EXPECT_NE(simulate_dataset(o).differences, one.differences);
  fs::remove(a);
  fs::remove(b);
}

// The variation (docs/real-presses.md): touches drawn in the asked ranges, each sample's sensor
// randomised from its own stream (the same on any thread count), its change consistent with its
// frame, and the touches the same as without randomisation (drawn first); bad ranges refused.
TEST(Simulate, VariationDrawsItsRangesAndRandomisesEachSample) {
  SimulationOptions o = tiny_options(11, MeshDensity::coarse);
  o.variation.radius_min = 0.2, o.variation.radius_max = 0.3;
  o.variation.contrast_min = 0.05, o.variation.contrast_max = 0.25;
  const Dataset plain = simulate_dataset(o);
  for (const auto& list : plain.circles)
    for (const Circle& c : list) {
      EXPECT_GE(c.r, 0.2 - 1e-12);
      EXPECT_LE(c.r, 0.3 + 1e-12);
      EXPECT_GE(c.conductivity, plain.background * (1 - 0.25) - 1e-15);
      EXPECT_LE(c.conductivity, plain.background * (1 - 0.05) + 1e-15);
    }
  EXPECT_NE(plain.simulation_mesh.find("touches 0.2-0.3 R, contrast 0.05-0.25"), std::string::npos);

  o.variation.impedance_spread = 0.7, o.variation.gain_error = 0.03;
  o.variation.snr_min_db = 30, o.variation.snr_max_db = 40;
  o.threads = 1;
  const Dataset one = simulate_dataset(o);
  o.threads = 2;
  const Dataset two = simulate_dataset(o);
  EXPECT_EQ(one.differences, two.differences);
  EXPECT_EQ(one.labels, plain.labels);  // the same touches
  const ForwardModel model(generate_disk_mesh({16, MeshDensity::coarse}));
  double cosine = 0;
  for (int i = 0; i < one.size(); ++i) {
    const Eigen::VectorXd change = one.frames.row(i).transpose() - one.reference;
    const Eigen::VectorXd inputs = model.protocol().reduce(change, MeasurementOrder::rotating);
    EXPECT_LT((inputs - one.differences.row(i).transpose()).norm(), 1e-9 * inputs.norm());
    const Eigen::VectorXd a = one.differences.row(i), b = plain.differences.row(i);
    EXPECT_NE(a, b);
    cosine += a.dot(b) / (a.norm() * b.norm()) / one.size();
  }
  EXPECT_GT(cosine, 0.8);  // the same touches, seen through another sensor each
  EXPECT_LT(cosine, 0.9999);

  SimulationVariation bad;
  bad.radius_min = 0.3, bad.radius_max = 0.2;
  EXPECT_THROW(bad.validate(), InputError);
  bad = {};
  bad.radius_min = 0.2, bad.radius_max = 0.3;  // without --touch-contrast: no change at all
  EXPECT_THROW(bad.validate(), InputError);
  bad = {};
  bad.contrast_max = 0.3;  // without --touch-radius
  EXPECT_THROW(bad.validate(), InputError);
  bad = {};
  bad.snr_min_db = 50, bad.snr_max_db = 40;
  EXPECT_THROW(bad.validate(), InputError);
}

// A real sensor's measured gains and noise (--sensor-noise): every sample's change is the plain
// set's times its channel's gain (1 where the gain is NaN) plus white noise of the measured level
// in units of the reference's RMS; the same touches, the same on any thread count; gains of
// another protocol's channels refused, naming the flag.
TEST(Simulate, TheSensorsGainsAndNoiseDrawEachSampleLikeTheSensor) {
  SimulationOptions o = tiny_options(13, MeshDensity::coarse);
  const Dataset plain = simulate_dataset(o);
  const Eigen::Index channels = plain.reference.size();
  o.variation.sensor_gains = Eigen::VectorXd::LinSpaced(channels, 0.6, 1.4);
  o.variation.sensor_gains(5) = NAN;
  o.variation.sensor_noise = 0.002;
  o.threads = 1;
  const Dataset one = simulate_dataset(o);
  o.threads = 2;
  EXPECT_EQ(simulate_dataset(o).differences, one.differences);
  EXPECT_EQ(one.labels, plain.labels);
  EXPECT_NE(one.simulation_mesh.find("the sensor's noise 0.2 %"), std::string::npos)
      << one.simulation_mesh;
  Eigen::VectorXd gains = o.variation.sensor_gains;
  gains(5) = 1;
  const double sigma = 0.002 * one.reference.norm() / std::sqrt(double(channels));
  double residual2 = 0;
  for (int i = 0; i < one.size(); ++i) {
    const Eigen::VectorXd own = one.frames.row(i).transpose() - one.reference;
    const Eigen::VectorXd base = plain.frames.row(i).transpose() - plain.reference;
    residual2 += (own - gains.cwiseProduct(base)).squaredNorm();
  }
  const double rms = std::sqrt(residual2 / double(one.size() * channels));
  EXPECT_NEAR(rms / sigma, 1.0, 0.05);  // 81 samples x 208 channels: a 0.5 % standard error

  o.variation.sensor_gains = Eigen::VectorXd::Ones(channels + 1);
  EXPECT_EQ(testing::input_error_at([&] { simulate_dataset(o); }), "--sensor-noise.gains");
  o.variation.sensor_gains = Eigen::VectorXd::Constant(channels, -1.0);
  EXPECT_EQ(testing::input_error_at([&] { o.variation.validate(); }), "--sensor-noise.gains");
}

// Electrodes shifted per sample (--randomise-electrodes): each sample's own sensor, the same on
// any thread count, the same touches as without it; the bound and a sensor mesh refused.
TEST(Simulate, ElectrodeShiftsGiveEachSampleItsOwnSensor) {
  SimulationOptions o = tiny_options(12, MeshDensity::coarse);
  const Dataset plain = simulate_dataset(o);
  o.variation.electrode_shift_deg = 2;
  o.threads = 1;
  const Dataset one = simulate_dataset(o);
  o.threads = 2;
  const Dataset two = simulate_dataset(o);
  EXPECT_EQ(one.differences, two.differences);
  EXPECT_EQ(one.labels, plain.labels);
  EXPECT_NE(one.simulation_mesh.find("randomised: electrodes +-2 deg"), std::string::npos);
  double cosine = 0;
  for (int i = 0; i < one.size(); ++i) {
    const Eigen::VectorXd a = one.differences.row(i), b = plain.differences.row(i);
    EXPECT_NE(a, b);
    cosine += a.dot(b) / (a.norm() * b.norm()) / one.size();
  }
  EXPECT_GT(cosine, 0.9);  // the same touches, electrodes a little off
  EXPECT_LT(cosine, 0.99999);

  o.variation.electrode_shift_deg = 3;  // a quarter of the coarse disk's gap is 2.8 degrees
  EXPECT_THROW(simulate_dataset(o), InputError);
  o.variation.electrode_shift_deg = 1;
  o.sensor_mesh = std::make_shared<const Mesh>(generate_disk_mesh({16, MeshDensity::coarse}));
  EXPECT_THROW(simulate_dataset(o), InputError);
  SimulationVariation bad;
  bad.electrode_shift_deg = -1;
  EXPECT_THROW(bad.validate(), InputError);
}

// Shards (simulate --shard K/N, then merge, docs/scaling.md): for 2 and 3 shards, each on its own
// thread count, the joined set's arrays are those of one process's set; a shard is refused where
// a whole set is needed; merge refuses a missing, repeated or foreign shard and a whole set,
// writing nothing.
TEST(Shards, JoinedShardsAreTheWholeSet) {
  SimulationOptions o = tiny_options(21, MeshDensity::coarse);
  const std::string whole_path = dataset_path("whole.h5");
  write_dataset(whole_path, simulate_dataset(o));
  const Dataset whole = read_dataset(whole_path);
  std::vector<std::string> three;
  for (int N : {2, 3}) {
    std::vector<std::string> paths;
    for (int K = N - 1; K >= 0; --K) {  // given in reverse: merge orders them
      o.shard_index = K, o.shard_count = N, o.threads = 1 + K % 2;
      const Dataset part = simulate_dataset(o);
      EXPECT_EQ(part.shard.first, static_cast<long long>(whole.size()) * K / N);
      EXPECT_EQ(part.shard.total, whole.size());
      paths.push_back(dataset_path("shard" + std::to_string(K) + "of" + std::to_string(N) + ".h5"));
      write_dataset(paths.back(), part);
    }
    const std::string out = dataset_path("merged.h5");
    const ShardMerge merged = merge_dataset_shards(paths, out);
    EXPECT_EQ(merged.shards, N);
    EXPECT_EQ(merged.samples, whole.size());
    const Dataset m = read_dataset(out);
    EXPECT_TRUE(m.shard.whole());
    EXPECT_EQ(m.frames, whole.frames);
    EXPECT_EQ(m.differences, whole.differences);
    EXPECT_EQ(m.labels, whole.labels);
    EXPECT_EQ(m.reference, whole.reference);
    EXPECT_EQ(m.split, whole.split);
    ASSERT_EQ(m.circles.size(), whole.circles.size());
    for (std::size_t i = 0; i < m.circles.size(); ++i)
      for (std::size_t k = 0; k < m.circles[i].size(); ++k) {
        EXPECT_EQ(m.circles[i][k].x, whole.circles[i][k].x);
        EXPECT_EQ(m.circles[i][k].conductivity, whole.circles[i][k].conductivity);
      }
    EXPECT_EQ(m.seed, whole.seed);
    EXPECT_EQ(m.simulation_mesh, whole.simulation_mesh);
    fs::remove(out);
    if (N == 3)
      three = paths;
    else
      for (const auto& p : paths) fs::remove(p);
  }
  // A shard is part of a set: refused wherever a set is used.
  try {
    read_dataset(three[0]);
    ADD_FAILURE() << "a shard read as a set";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "shard_index");
    EXPECT_NE(e.message().find("eitbench merge"), std::string::npos) << e.what();
  }
  const std::string out = dataset_path("refused.h5");
  const auto refused = [&](const std::vector<std::string>& paths, const std::string& field) {
    try {
      merge_dataset_shards(paths, out);
      ADD_FAILURE() << "merged";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
    EXPECT_FALSE(fs::exists(out));
  };
  refused({three[0], three[2]}, "");  // shard 1 missing: named in the message
  refused({three[0], three[1], three[2], three[1]}, "shard_index");
  refused({three[0], three[1], whole_path}, "");
  o.seed = 22, o.shard_index = 1, o.shard_count = 3;
  const std::string foreign = dataset_path("foreign.h5");
  write_dataset(foreign, simulate_dataset(o));
  refused({three[0], foreign, three[2]}, "seed");
  o.shard_index = 3;
  EXPECT_THROW(simulate_dataset(o), InputError);
  for (const auto& p : three) fs::remove(p);
  fs::remove(foreign), fs::remove(whole_path);
}

TEST(DatasetFile, RoundTrips) {
  const Dataset& d = tiny_set();
  const std::string path = dataset_path("round.h5");
  write_dataset(path, d);
  ASSERT_TRUE(is_hdf5_file(path));
  const Dataset r = read_dataset(path);
  EXPECT_EQ(r.electrodes, 16);
  EXPECT_EQ(r.seed, 11u);
  EXPECT_EQ(r.preset, "tiny");
  EXPECT_EQ(r.frames, d.frames);
  EXPECT_EQ(r.differences, d.differences);
  EXPECT_EQ(r.reference, d.reference);
  EXPECT_EQ(r.split, d.split);
  EXPECT_EQ(r.labels, d.labels.cast<float>().cast<double>());  // labels are stored as float32
  ASSERT_EQ(r.circles.size(), d.circles.size());
  for (std::size_t i = 0; i < d.circles.size(); ++i) {
    ASSERT_EQ(r.circles[i].size(), d.circles[i].size());
    EXPECT_EQ(r.circles[i][0].x, d.circles[i][0].x);
    EXPECT_EQ(r.circles[i][0].conductivity, d.circles[i][0].conductivity);
  }
  fs::remove(path);
}

TEST(DatasetFile, AnUncommittedWriterLeavesNothingBehind) {
  const Dataset& d = tiny_set();
  const std::string path = dataset_path("never.h5");
  std::ofstream(path) << "an older file";
  {
    DatasetWriter writer(path, d, true, true);
    writer.append(d);  // ... and the run stops before commit()
  }
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "an older file") << "the existing file is untouched";
  int temporaries = 0;
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path()))
    temporaries += entry.path().filename().string().find(
                       ".eitbench_ds_" + std::to_string(::getpid()) + "_never.tmp") == 0;
  EXPECT_EQ(temporaries, 0);
  fs::remove(path);
}

TEST(Noise, MeasuredSnrMatchesTheRequest) {
  const Dataset& d = tiny_set();
  for (double snr : {50.0, 40.0, 30.0}) {
    SampleMatrix noisy = d.differences;
    add_noise(noisy, snr, 3);
    EXPECT_NEAR(measured_snr_db(d.differences, noisy), snr, 0.5) << snr;
    // Per frame too, on average (each frame's noise is scaled to that frame's power).
    double mean = 0;
    for (Eigen::Index i = 0; i < noisy.rows(); ++i)
      mean += 10 * std::log10(d.differences.row(i).squaredNorm() /
                              (noisy.row(i) - d.differences.row(i)).squaredNorm());
    EXPECT_NEAR(mean / noisy.rows(), snr, 0.5);
    SampleMatrix again = d.differences;
    add_noise(again, snr, 3);
    EXPECT_EQ(again, noisy) << "deterministic";
  }
  SampleMatrix clean = d.differences;
  add_noise(clean, INFINITY, 3);
  EXPECT_EQ(clean, d.differences);
}

TEST(AugmentFile, ExpandsTheTrainingSplitConsistentlyWithTheForwardModel) {
  const Dataset& d = tiny_set();
  const std::string in = dataset_path("in.h5"), out = dataset_path("out.h5");
  write_dataset(in, d);
  FileAugmentOptions o;
  o.block = 7;  // several blocks, boundaries inside the data
  const long long n = augment_dataset_file(in, out, o);
  const Dataset a = read_dataset(out);
  const int train = static_cast<int>(d.indices(Split::train).size());
  ASSERT_EQ(n, train * 32 + (d.size() - train));
  EXPECT_EQ(a.size(), n);
  EXPECT_EQ(a.augmentation, "d16");
  EXPECT_EQ(static_cast<int>(a.indices(Split::validation).size()),
            static_cast<int>(d.indices(Split::validation).size()));
  // Row 32 i + k is train sample i under element k: its frame is what the forward model gives
  // for the moved circles (the simulation mesh is D_16-symmetric), its label their raster.
  const Mesh mesh = generate_disk_mesh({16, MeshDensity::medium});
  const ForwardModel model(mesh);
  const auto elements = group_elements(AugmentGroup::dihedral, 16);
  const PixelGrid grid(64, 1.0);
  for (int row : {0, 5, 17, 40, 31 * 32 + 30}) {
    const int i = row / 32;
    const GroupElement& g = elements[row % 32];
    const std::vector<Circle> moved = transform_circles(d.circles[i], g, 16);
    const Eigen::VectorXd v = model.frame(conductivity_from_circles(mesh, moved, d.background));
    EXPECT_LT((v - a.frames.row(row).transpose()).norm(), 1e-9 * v.norm()) << g.to_string();
    const Eigen::VectorXd dv = model.protocol().reduce(v - d.reference, MeasurementOrder::rotating);
    EXPECT_LT((dv - a.differences.row(row).transpose()).norm(), 1e-9 * v.norm()) << g.to_string();
    EXPECT_LT((circles_image(grid, moved, d.background).cast<float>().cast<double>() -
               a.labels.row(row).transpose())
                  .norm(),
              1e-6);
    EXPECT_EQ(a.circles[row].size(), d.circles[i].size());
  }
  // Validation and test samples are copied as they are, after the expanded training rows.
  const int first_validation = d.indices(Split::validation).front();
  EXPECT_EQ(Eigen::RowVectorXd(a.differences.row(train * 32)),
            Eigen::RowVectorXd(d.differences.row(first_validation)));

  o.splits = {Split::train, Split::validation, Split::test};
  o.elements = {GroupElement{3, true}};  // one element: every sample moved, none added
  ASSERT_EQ(augment_dataset_file(in, out, o), d.size());
  const Dataset m = read_dataset(out);
  const FrameSymmetry sym(16);
  EXPECT_EQ(Eigen::VectorXd(m.differences.row(9).transpose()),
            sym.apply({3, true}, d.differences.row(9).transpose(), FrameLayout::reduced));
  EXPECT_EQ(m.augmentation, "mirror:3");
  o.splits = {Split::validation};  // one element on one split: the others stay as they are
  ASSERT_EQ(augment_dataset_file(in, out, o), d.size());
  const Dataset v = read_dataset(out);
  const int val = d.indices(Split::validation).front(), tr = d.indices(Split::train).front();
  EXPECT_EQ(Eigen::RowVectorXd(v.differences.row(tr)), Eigen::RowVectorXd(d.differences.row(tr)));
  EXPECT_EQ(Eigen::VectorXd(v.differences.row(val).transpose()),
            sym.apply({3, true}, d.differences.row(val).transpose(), FrameLayout::reduced));
  fs::remove(in);
  fs::remove(out);
}

// Malformed files, each written with the HDF5 API from a good one with one defect.
class BadDatasetFile : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dataset_path("bad.h5");
    write_dataset(path_, tiny_set());
  }
  void TearDown() override { fs::remove(path_); }
  void expect_rejected(const std::string& field) {
    try {
      read_dataset(path_);
      ADD_FAILURE() << "accepted a file with a bad " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), path_);
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
  template <typename F>
  void edit(F&& f) {
    H5::H5File file(path_, H5F_ACC_RDWR);
    f(file);
  }
  std::string path_;
};

TEST_F(BadDatasetFile, MissingDataSet) {
  edit([](H5::H5File& f) { f.unlink("frames"); });
  expect_rejected("frames");
}

TEST_F(BadDatasetFile, WrongShape) {
  edit([](H5::H5File& f) {
    f.unlink("differences");
    const hsize_t dims[2] = {81, 103};
    std::vector<double> zeros(81 * 103, 0.0);
    f.createDataSet("differences", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(2, dims))
        .write(zeros.data(), H5::PredType::NATIVE_DOUBLE);
  });
  expect_rejected("differences");
}

TEST_F(BadDatasetFile, NotANumber) {
  edit([](H5::H5File& f) {
    H5::DataSet set = f.openDataSet("differences");
    std::vector<double> values(81 * 104);
    set.read(values.data(), H5::PredType::NATIVE_DOUBLE);
    values[500] = NAN;
    set.write(values.data(), H5::PredType::NATIVE_DOUBLE);
  });
  expect_rejected("differences");
}

TEST_F(BadDatasetFile, SplitOutOfRange) {
  edit([](H5::H5File& f) {
    H5::DataSet set = f.openDataSet("split");
    std::vector<int> values(81);
    set.read(values.data(), H5::PredType::NATIVE_INT);
    values[3] = 5;
    set.write(values.data(), H5::PredType::NATIVE_INT);
  });
  expect_rejected("split");
}

TEST_F(BadDatasetFile, MissingElectrodeCount) {
  edit([](H5::H5File& f) { f.removeAttr("electrodes"); });
  expect_rejected("electrodes");
}

TEST_F(BadDatasetFile, ElectrodeCountDisagreesWithTheData) {
  edit([](H5::H5File& f) {
    f.removeAttr("electrodes");
    const long long eight = 8;
    f.createAttribute("electrodes", H5::PredType::NATIVE_LLONG, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_LLONG, &eight);
  });
  expect_rejected("protocol_channels");  // its channels name electrodes 8..15
}

TEST_F(BadDatasetFile, ElectrodeCountDisagreesWithTheDataOfAFileWithoutProtocol) {
  edit([](H5::H5File& f) {  // a file from before protocols: the adjacent one, sized by L
    f.unlink("protocol_channels");
    f.removeAttr("electrodes");
    const long long eight = 8;
    f.createAttribute("electrodes", H5::PredType::NATIVE_LLONG, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_LLONG, &eight);
  });
  expect_rejected("differences");
}

TEST_F(BadDatasetFile, EmptyOrNonIntegerProtocolChannels) {
  edit([](H5::H5File& f) {  // an empty table would read as the adjacent protocol
    f.unlink("protocol_channels");
    const hsize_t dims[2] = {0, 4};
    f.createDataSet("protocol_channels", H5::PredType::NATIVE_INT, H5::DataSpace(2, dims));
  });
  expect_rejected("protocol_channels");
}

TEST_F(BadDatasetFile, FloatProtocolChannels) {
  edit([](H5::H5File& f) {
    H5::DataSet old = f.openDataSet("protocol_channels");
    hsize_t dims[2];
    old.getSpace().getSimpleExtentDims(dims);
    std::vector<double> values(dims[0] * dims[1], 0.5);
    f.unlink("protocol_channels");
    f.createDataSet("protocol_channels", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(2, dims))
        .write(values.data(), H5::PredType::NATIVE_DOUBLE);
  });
  expect_rejected("protocol_channels");
}

TEST_F(BadDatasetFile, MagnitudeIsZeroOrOne) {
  edit([](H5::H5File& f) {
    f.removeAttr("magnitude");
    const double half = 0.5;
    f.createAttribute("magnitude", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_DOUBLE, &half);
  });
  expect_rejected("magnitude");
}

TEST_F(BadDatasetFile, HugeDeclaredDimensions) {
  edit([](H5::H5File& f) {
    f.unlink("frames");
    const hsize_t dims[2] = {81, 4000000000ULL}, chunk[2] = {1, 1024};
    H5::DSetCreatPropList props;
    props.setChunk(2, chunk);  // chunked and never written: a tiny file declaring 2.6 TB
    f.createDataSet("frames", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(2, dims), props);
  });
  expect_rejected("frames");
}

TEST_F(BadDatasetFile, TruncatedAndForeignFiles) {
  const auto size = fs::file_size(path_);
  fs::resize_file(path_, size / 2);
  expect_rejected("");
  std::ofstream(path_) << "x,y\n1,2\n";
  expect_rejected("not an HDF5 file");
  std::ofstream(path_, std::ios::trunc).close();
  expect_rejected("not an HDF5 file");
}

}  // namespace
}  // namespace eitbench
