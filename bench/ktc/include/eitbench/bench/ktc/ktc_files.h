#pragma once
// KTC2023's files (docs/ktc.md#files): a measurement (dataN.mat: Uel, Inj, Mpat; the empty tank's
// ref.mat: Uelref, Injref, Mpat), a ground truth (trueN.mat: truth), a folder of them, and the
// reconstruction file a submission writes (N.mat: reconstruction, 256 x 256 uint8). Every field is
// checked against the others; InputError names the file and the field.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "eitbench/bench/ktc/score.h"
#include "eitbench/jacobian/current_patterns.h"

namespace eitbench {

struct KtcMeasurement {
  std::string path;
  // Uel (or Uelref): one value per pattern and difference, pattern-major; NaN where missing.
  Eigen::VectorXd voltages;
  CurrentPatterns patterns;  // injection = Inj (or Injref), measurement = Mpat
};

// Reads a measurement: Uel or Uelref, Inj or Injref, and Mpat, by name (v5 or v7.3 .mat).
// InputError(path, field) for a missing variable, Inj and Mpat on different electrode counts, a
// pattern whose currents do not sum to zero, or voltages whose count is not patterns x
// differences. A value may be NaN (missing); an infinite one is refused.
KtcMeasurement read_ktc_measurement(const std::string& path);

// Reads `truth`: 256 x 256 classes 0, 1 or 2 (InputError naming the file otherwise).
ClassImage read_ktc_truth(const std::string& path);

// Writes `reconstruction` (256 x 256, values 0..2) as KTC's N.mat, whole or not at all.
// InputError(path) for an image of another size or class.
void write_ktc_reconstruction(const std::string& path, const ClassImage& reconstruction);

struct KtcFolder {
  std::string reference;  // ref.mat
  // dataN.mat by N ascending, and trueN.mat where the folder has one (empty otherwise).
  struct Sample {
    int number = 0;
    std::string data, truth;
  };
  std::vector<Sample> samples;
};

// The KTC files of a folder. InputError(folder) when it is no folder, has no ref.mat, or no
// dataN.mat.
KtcFolder scan_ktc_folder(const std::string& folder);

}  // namespace eitbench
