#pragma once
// Files written whole or not at all, and read whole within a size limit. Every output goes to a
// temporary beside its target and is renamed into place only when complete, so an interrupted or
// failed run never leaves a half-written file.
#include <functional>
#include <iosfwd>
#include <string>

namespace eitbench {

// Writes `path` (output_target's choice: a link's target) through `write(temporary_path)`, then
// renames. The temporary keeps the target's extension (some writers choose the format by it) and
// is removed when write() throws.
void write_atomically(const std::string& path,
                      const std::function<void(const std::string&)>& write);
// The temporary beside `path` that write_atomically uses: checks output_target(path) and that
// the folder exists. For a symbolic link, beside the file it points to.
std::string temporary_path_for(const std::string& path);
void write_text_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

// The whole file; InputError naming it when it is missing, unreadable, empty or larger than
// max_bytes (checked before anything is allocated; -1: the cap of eitbench/jacobian/read_budget.h).
std::string read_file_bytes(const std::string& path, long long max_bytes = -1);
void write_bytes_atomically(const std::string& path, const std::string& bytes);

}  // namespace eitbench
