// Importers of measured frames against files written by numpy, scipy and h5py (tests/data,
// made by make_fixtures.py from frames.csv), and corrupted copies of them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "eitbench/bench/io/numpy.h"
#include "eitbench/jacobian.h"

namespace eitbench {
namespace {
namespace fs = std::filesystem;

const std::string kData = std::string(EITBENCH_BAD_INPUTS) + "/../data/";

Eigen::MatrixXd expected_frames() {
  return read_frames_csv(kData + "frames.csv");
}

Measurements import(const std::string& file, MeasurementOrder order = MeasurementOrder::rotating,
                    const std::string& variable = "") {
  ImportOptions o;
  o.order = order;
  o.variable = variable;
  return read_measurements(kData + file, o);
}

struct Fixture {
  const char* file;
  MeasurementOrder order;
  const char* variable;
  double tolerance;  // relative: float32 files keep 7 digits
};

void PrintTo(const Fixture& f, std::ostream* os) {
  *os << f.file;
}

class Importer : public ::testing::TestWithParam<Fixture> {};

TEST_P(Importer, ReadsTheSameFramesAsTheCsv) {
  const auto& [file, order, variable, tolerance] = GetParam();
  const Measurements m = import(file, order, variable);
  const Eigen::MatrixXd expected = expected_frames();
  ASSERT_EQ(m.frames.rows(), 3) << m.description;
  ASSERT_EQ(m.frames.cols(), 208);
  EXPECT_LE((m.frames - expected).cwiseAbs().maxCoeff(), tolerance * expected.cwiseAbs().maxCoeff())
      << m.description;
  if (!m.reduced_input) {
    EXPECT_LT(m.reciprocity_error, 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Formats, Importer,
    ::testing::Values(Fixture{"frames.csv", MeasurementOrder::rotating, "", 0},
                      Fixture{"frames_ascending.csv", MeasurementOrder::ascending, "", 0},
                      Fixture{"frames_reduced.csv", MeasurementOrder::rotating, "", 1e-12},
                      Fixture{"frames_square.csv", MeasurementOrder::rotating, "", 0},
                      Fixture{"frames_rotating.npy", MeasurementOrder::rotating, "", 0},
                      Fixture{"frames_fortran.npy", MeasurementOrder::rotating, "", 0},
                      Fixture{"frames_ascending_f4.npy", MeasurementOrder::ascending, "", 1e-6},
                      Fixture{"frames_compressed.npz", MeasurementOrder::rotating, "", 0},
                      Fixture{"frames_plain.npz", MeasurementOrder::rotating, "", 1e-12},
                      Fixture{"frames_v5.mat", MeasurementOrder::rotating, "vv", 0},
                      Fixture{"frames_v5_plain.mat", MeasurementOrder::rotating, "", 0},
                      Fixture{"frames_v73.mat", MeasurementOrder::rotating, "vv", 0}),
    [](const auto& info) {
      std::string n = info.param.file;
      for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

TEST(Import, DifferencesAgainstTheReference) {
  ImportOptions o;
  const Dataset d =
      import_measurements(kData + "frames_compressed.npz", kData + "frames_v5.mat", o, "vh");
  const Eigen::MatrixXd frames = expected_frames();
  const Eigen::VectorXd reference = read_frames_csv(kData + "reference.csv").row(0).transpose();
  const Protocol p(16);
  ASSERT_EQ(d.size(), 3);
  for (int i = 0; i < 3; ++i) {
    const Eigen::VectorXd dv =
        p.reduce(frames.row(i).transpose() - reference, MeasurementOrder::rotating);
    EXPECT_LT((d.differences.row(i).transpose() - dv).cwiseAbs().maxCoeff(), 1e-15);
  }
  EXPECT_FALSE(d.has_labels());
  // And through the file.
  const std::string path = (fs::temp_directory_path() / "eitbench_import.h5").string();
  write_dataset(path, d);
  EXPECT_EQ(read_dataset(path).differences, d.differences);
  fs::remove(path);
}

TEST(Import, ReportsTheReciprocityErrorOfMeasuredFrames) {
  const Eigen::MatrixXd frames = expected_frames();
  Eigen::VectorXd v = frames.row(0).transpose();
  const Protocol p(16);
  v[p.index(0, 2, MeasurementOrder::rotating)] += 0.01;  // one value off
  const std::string path = (fs::temp_directory_path() / "eitbench_recip.csv").string();
  write_frames_csv(path, v.transpose());
  ImportOptions o;
  const Measurements m = read_measurements(path, o);
  EXPECT_NEAR(m.reciprocity_error, p.reciprocity_error(v, MeasurementOrder::rotating), 1e-15);
  EXPECT_GT(m.reciprocity_error, 1e-4);
  fs::remove(path);
}

// Corrupted copies: truncated, a flipped byte in the compressed stream, an emptied file.
std::string corrupt(const std::string& file, const std::string& how) {
  std::string bytes;
  {
    std::ifstream in(kData + file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  if (how == "truncate") bytes.resize(bytes.size() * 2 / 3);
  if (how == "flip") bytes[bytes.size() / 2] ^= 0x5a;
  if (how == "empty") bytes.clear();
  const std::string path = (fs::temp_directory_path() / ("eitbench_" + how + "_" + file)).string();
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

TEST(Import, RejectsBadFilesNamingFileAndField) {
  ImportOptions o;
  struct Bad {
    std::string path, words;
    ImportOptions options;
  };
  ImportOptions eight = o;
  eight.electrodes = 8;
  ImportOptions missing = o;
  missing.variable = "nope";
  const std::vector<Bad> bad = {
      {kData + "bad_struct.mat", "struct", o},
      {kData + "bad_bigendian.npy", "little-endian", o},
      {kData + "bad_nan.npy", "NaN", o},
      {kData + "bad_length.npy", "103 values", o},
      {kData + "bad_nul_shape.npy", "not a dimension", o},  // found by fuzz_npy (a hang)
      {kData + "bad_two_arrays.npz", "--variable", o},
      {kData + "frames_v5.mat", "nope", missing},
      {kData + "frames.csv", "8 electrodes", eight},
      {corrupt("frames_rotating.npy", "truncate"), "truncated", o},
      {corrupt("frames_compressed.npz", "truncate"), "ZIP", o},
      {corrupt("frames_compressed.npz", "flip"), "corrupt", o},
      {corrupt("frames_v5.mat", "truncate"), "", o},
      {corrupt("frames_v5.mat", "flip"), "", o},
      {corrupt("frames_v73.mat", "truncate"), "", o},
      {corrupt("frames_rotating.npy", "empty"), "the file is empty", o},
      {corrupt("frames_v5.mat", "empty"), "the file is empty", o},
      {kData + "make_fixtures.py", "unknown file type", o},
      {kData + "missing.npy", "no such file", o},
  };
  for (const Bad& b : bad) {
    try {
      read_measurements(b.path, b.options);
      ADD_FAILURE() << "accepted " << b.path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), b.path) << e.what();
      EXPECT_NE(std::string(e.what()).find(b.words), std::string::npos) << e.what();
    }
  }
}

// The writer of the run's reconstructions.npy against the reader every import uses: shapes of one
// and four dimensions, values float32-exact, a count that does not fit the shape refused.
TEST(Npy, WrittenArraysReadBack) {
  const std::vector<float> values{1.5f, -2.0f, 3e-7f, 1e30f, 0.0f, -0.125f};
  for (const std::vector<std::size_t>& shape :
       {std::vector<std::size_t>{6}, std::vector<std::size_t>{1, 3, 1, 2}}) {
    const auto a = detail::read_npy(detail::npy_bytes(values, shape), "mem.npy", "");
    EXPECT_EQ(a.shape, shape);
    ASSERT_EQ(a.values.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(a.values[i], values[i]) << i;
  }
  // NumPy aligns the data to 64 bytes.
  EXPECT_EQ((detail::npy_bytes(values, {2, 3}).size() - values.size() * sizeof(float)) % 64, 0u);
  EXPECT_THROW(detail::npy_bytes(values, {4, 2}), std::logic_error);
}

TEST(Calibration, FitsTheMeasuredReferenceToTheModels) {
  const Eigen::VectorXd model = read_frames_csv(kData + "reference.csv").row(0).transpose();
  // An instrument reading millivolts where the model reads volts, and one wired with the other
  // polarity at twice the gain.
  const ReferenceCalibration mv = calibrate_to_model(1000 * model, model);
  EXPECT_NEAR(mv.scale, 1e-3, 1e-15);
  EXPECT_NEAR(mv.fit, 1, 1e-12);
  const ReferenceCalibration flipped = calibrate_to_model(-2 * model, model);
  EXPECT_NEAR(flipped.scale, -0.5, 1e-12);
  EXPECT_NEAR(flipped.fit, -1, 1e-12);
  // Noise moves the scale only to first order in its size, and lowers the fit a little.
  Eigen::VectorXd noisy = 3 * model;
  for (Eigen::Index i = 0; i < noisy.size(); ++i) noisy[i] += 1e-3 * ((i * 7919) % 13 - 6);
  const ReferenceCalibration n = calibrate_to_model(noisy, model);
  EXPECT_NEAR(n.scale, 1.0 / 3, 1e-3);
  EXPECT_LT(n.fit, 1);
  EXPECT_GT(n.fit, 0.999);
  // Frames in the instrument's ascending order read as rotating ones fit poorly: the warning's cue.
  const Protocol p(16);
  Eigen::VectorXd misread(model.size());
  for (int d = 0, k = 0; d < 16; ++d)
    for (int m = 0; m < 16; ++m)
      if (m != (d + 15) % 16 && m != d && m != (d + 1) % 16)
        misread[k++] = model[p.index(d, m, MeasurementOrder::rotating)];
  EXPECT_LT(calibrate_to_model(misread, model).fit, 0.95);
  // No reference (frames imported as differences): no calibration.
  const ReferenceCalibration none = calibrate_to_model(Eigen::VectorXd::Zero(model.size()), model);
  EXPECT_EQ(none.scale, 1);
  EXPECT_TRUE(std::isnan(none.fit));
}

}  // namespace
}  // namespace eitbench
