#pragma once
// eitbench/solvers: model-based reconstruction on the Jacobian: one-step Tikhonov (identity, NOSER,
// Laplace priors) with GCV, L-curve and validation choices; total variation; Gauss-Newton; GREIT;
// the shape fit (circles by Ceres).
#include "eitbench/solvers/gauss_newton.h"
#include "eitbench/solvers/greit.h"
#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/missing_values.h"
#include "eitbench/solvers/press_frame.h"
#include "eitbench/solvers/press_sensor.h"  // with Ceres
#include "eitbench/solvers/reconstructor.h"
#include "eitbench/solvers/shape.h"
#include "eitbench/solvers/tikhonov.h"
#include "eitbench/solvers/total_variation.h"
