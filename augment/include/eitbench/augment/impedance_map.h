#pragma once
// Frames in their three layouts, and the Electrical Impedance Map (SPEC section 1).
#include <Eigen/Core>
#include <string>

#include "eitbench/jacobian/protocol.h"

namespace eitbench {

enum class FrameLayout {
  rotating,   // L(L-3) values, drive-major, m = d+2 ... (the canonical order)
  ascending,  // L(L-3) values, m = 0 ... L-1 skipping d-1, d, d+1
  reduced,    // L(L-3)/2 reciprocity-reduced values (the paper's sequential 104)
};

std::string to_string(FrameLayout layout);
// The layout of a frame of `size` values for L electrodes: reduced for L(L-3)/2 values, `order`
// for L(L-3). Throws InputError(source, "frame", ...) for any other size.
FrameLayout frame_layout(Eigen::Index size, int electrodes, MeasurementOrder order,
                         const std::string& source);
Eigen::Index frame_size(FrameLayout layout, int electrodes);

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
