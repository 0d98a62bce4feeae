#pragma once
// The tank's symmetry group acting on simulated tanks (docs/ktc.md#simulated-tanks): a difference
// frame moved by pattern_action (augment/pattern_symmetry.h), its labels moved on KTC's pixel grid
// to match. KTC's patterns keep the quarter turns and four mirrors of D32; with electrode 1 on an
// axis of the image (KTC's orientation puts it at the top) each maps the grid onto itself.
#include <vector>

#include "eitbench/augment/symmetry.h"
#include "eitbench/bench/ktc/tank_simulation.h"

namespace eitbench {

// The elements of D32 that map `patterns` onto itself (8 for KTC's).
std::vector<GroupElement> ktc_group(const CurrentPatterns& patterns);

// The labels of the tank g moves: label'(p) = label(g^-1 p). InputError("GroupElement", g) when g
// does not map the square grid onto itself in `orientation` (electrode 1 off the image's axes).
ClassImage move_ktc_labels(const ClassImage& labels, const GroupElement& g,
                           const KtcOrientation& orientation);

// Every sample under every element, sample-major (row n * elements + k), the first element
// first. Frames must be difference frames: a raw frame's offsets do not move with the tank
// (docs/ktc.md#the-frames-noise). The targets are left out (the labels carry them).
KtcSimulatedSet augment_ktc_set(const KtcSimulatedSet& set, const CurrentPatterns& patterns,
                                const std::vector<GroupElement>& elements,
                                const KtcOrientation& orientation);

}  // namespace eitbench
