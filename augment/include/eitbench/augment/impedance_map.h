#pragma once
// The Electrical Impedance Map of a frame in any of its layouts (docs/conventions.md).
#include <Eigen/Core>
#include <string>

#include "eitbench/jacobian/frame_layout.h"
#include "eitbench/jacobian/protocol.h"

namespace eitbench {

// A frame or map of the wrong size is data, not a programming error: InputError("frame",
// "values") or InputError("map", "shape").

// The L x (L-3) map: row d, column k holds v(d, d+2+k). A reduced frame is completed by
// reciprocity.
Eigen::MatrixXd impedance_map(const Eigen::VectorXd& frame, const Protocol& protocol,
                              FrameLayout layout);
// The L x L form: (d, m) holds v(d, m); pairs that share an electrode with the drive hold NaN.
Eigen::MatrixXd full_impedance_map(const Eigen::VectorXd& frame, const Protocol& protocol,
                                   FrameLayout layout);
// Back from the L x (L-3) map. To `reduced`, the values v(d, m) with d < m are taken as they stand.
Eigen::VectorXd frame_from_map(const Eigen::MatrixXd& map, const Protocol& protocol,
                               FrameLayout layout);

}  // namespace eitbench
