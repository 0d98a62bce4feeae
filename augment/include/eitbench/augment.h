#pragma once
// eitbench/augment: the data augmentation of the paper through the sensor's symmetry group D_L,
// with the correct mirror (docs/conventions.md) and the paper's literal variant for comparison.
#include "eitbench/augment/augmented_set.h"
#include "eitbench/augment/channel_symmetry.h"
#include "eitbench/augment/impedance_map.h"
#include "eitbench/augment/label_transform.h"
#include "eitbench/augment/pattern_symmetry.h"
#include "eitbench/augment/sensor_group.h"
#include "eitbench/augment/symmetry.h"
