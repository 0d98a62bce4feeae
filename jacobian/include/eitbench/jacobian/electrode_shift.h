#pragma once
// Moving a disk's electrodes along its rim: an electrode glued a little off its nominal place, as
// on a hand-made skin. Simulation draws such shifts per sample (domain randomisation).
#include <vector>

#include "eitbench/jacobian/mesh.h"

namespace eitbench {

// The angle of electrode e on a mesh centred at the origin: the direction of the mean of its
// nodes, in (-pi, pi].
double electrode_angle(const Mesh& disk, int e);

// The largest shift shift_electrodes accepts between neighbours: half the narrowest gap between
// two electrodes (radians), so that no gap is squeezed to less than half its width.
double max_neighbour_shift(const Mesh& disk);

// The disk mesh with electrode e turned by shifts[e] radians counter-clockwise about the centre,
// the mesh following. Each electrode moves rigidly (its nodes turn by its shift, its length is
// kept); the gaps between electrodes stretch or shrink, their rim nodes' turns interpolated
// linearly in angle; an interior node at radius rho turns by (rho/R)^2 times the turn of the rim
// at its angle, so the centre stays and the map is smooth there. The connectivity and electrode
// segments are unchanged. Throws InputError("--randomise-electrodes", ...) for a shift count other
// than the electrodes', two neighbours' shifts differing by more than max_neighbour_shift, or a
// triangle the warp would turn over.
Mesh shift_electrodes(const Mesh& disk, const std::vector<double>& shifts);

}  // namespace eitbench
