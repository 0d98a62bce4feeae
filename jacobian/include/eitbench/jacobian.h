#pragma once
// eitbench/jacobian: the physics of the sensor. Meshes (generated with exact D_L symmetry, or read
// from Gmsh), the measurement protocol, the complete-electrode-model forward solver and its
// Jacobian on elements and on the 64x64 pixel grid.
#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/current_patterns.h"
#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/jacobian/electrode_shift.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/forward_model.h"
#include "eitbench/jacobian/frame_layout.h"
#include "eitbench/jacobian/geometry.h"
#include "eitbench/jacobian/measurement_protocol.h"
#include "eitbench/jacobian/mesh.h"
#include "eitbench/jacobian/msh_io.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/jacobian/protocol.h"
#include "eitbench/jacobian/random.h"
#include "eitbench/jacobian/sample_matrix.h"
