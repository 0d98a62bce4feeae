#pragma once
// A press set's truth from a file: where each measured frame was pressed (docs/data.md#press-sets).
// `eitbench import --touches FILE` reads it beside the frames.
#include <string>
#include <vector>

#include "eitbench/bench/data/dataset.h"

namespace eitbench {

struct TouchFileOptions {
  std::string path;      // CSV, NPY, NPZ or MAT: a row a frame, x, y and optionally a size
  std::string variable;  // the array (.npz) or variable (.mat); default: the only numeric one,
                         // else the first of touches, positions, xy
  double scale = 1;      // multiplies every length (x, y, size): the file's unit to the mesh's
  std::string size = "depth";  // what a third column holds: depth | radius
  // The file's frame to the mesh's, after scaling: first y -> -y when `mirror` (electrodes
  // numbered clockwise in the file's frame), then a counter-clockwise turn by `rotate_degrees`
  // about the centre. The mesh's electrode 0 lies on +x, the others counter-clockwise: a file
  // whose electrode 0 lies at 282 degrees, counter-clockwise, takes rotate_degrees = -282.
  bool mirror = false;
  double rotate_degrees = 0;
};

// One touch a frame from an N x 2 (x, y) or N x 3 (x, y, size) array, its lengths times
// `options.scale`, mirrored and turned as the options say: the touches and what their size is (""
// for N x 2). InputError naming the file and row for another number of rows than `frames`, another
// width, a centre that is not a finite number, a size that is not positive, or a centre outside the
// disk of `radius` (mesh units).
struct PressTruth {
  std::vector<std::vector<PressTouch>> touches;
  std::string size;
};
PressTruth read_touch_file(const TouchFileOptions& options, long long frames, double radius);

// A press set that presses can be scored or tuned on beside others read on `protocol`: one known
// touch a frame, the same channels and magnitudes. InputError(path, "touches" or "protocol").
void check_press_set(const std::string& path, const Dataset& data,
                     const MeasurementProtocol& protocol);

}  // namespace eitbench
