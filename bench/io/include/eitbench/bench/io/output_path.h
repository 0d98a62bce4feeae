#pragma once
// Where an output may go. Every writer asks here first (through temporary_path_for), so one rule
// holds for all of them: eitbench writes regular files only, and never onto one of the running
// command's inputs, whatever the spelling (./x, a hard link, a symbolic link).
#include <string>
#include <vector>

namespace eitbench {

// The files the running command reads (its file arguments). Paths that name no regular file are
// ignored, so a caller may pass every argument it has.
void declare_inputs(const std::vector<std::string>& paths);

// The file to write for `path`: `path` itself, or for a symbolic link the file it points to (the
// link stays and keeps pointing there; its target is replaced whole). InputError(path) when it is
// empty, a folder, a FIFO, a device or a socket, a link to nothing, or a declared input.
std::string output_target(const std::string& path);

}  // namespace eitbench
