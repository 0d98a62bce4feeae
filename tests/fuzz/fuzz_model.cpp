// The learned model's file (a LibTorch archive with eitbench's metadata).
#include "eitbench/learned.h"
#include "fuzz_target.h"

EITBENCH_FUZZ_TARGET(eitbench::LearnedModel::from_bytes(bytes, "fuzz.pt"))
