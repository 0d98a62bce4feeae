#pragma once
// eitbench/learned: the learned reconstructor (MLP encoder from the difference
// frame to a latent, CNN decoder to the image), its training with the symmetry augmentation, and
// its file format. LibTorch is an implementation detail: nothing here includes it.
#include "eitbench/learned/learned_model.h"
#include "eitbench/learned/network_options.h"
#include "eitbench/learned/runtime.h"
#include "eitbench/learned/schedule.h"
#include "eitbench/learned/trainer.h"
