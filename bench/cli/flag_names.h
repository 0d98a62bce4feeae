#pragma once
// The libraries name a bad option by its options struct and field ("TrainingOptions",
// "batch_size") or, for a name they parse, by the enum and "name"; the user set it by a flag. This
// maps one to the other per subcommand, so that the message names what the user typed.
#include <string>

#include "eitbench/jacobian/error.h"

namespace eitbench::cli {

// `error` with the flag that sets its struct and field in `command` as its source (the field
// dropped), or `error` itself when no flag of `command` does.
InputError name_the_flag(const InputError& error, const std::string& command);

}  // namespace eitbench::cli
