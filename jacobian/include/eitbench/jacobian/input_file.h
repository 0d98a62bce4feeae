#pragma once
// The first check of every reader: the path names a file this process can read. One message for
// each way it cannot, whatever the format ("no such file" rather than a parser's guess).
#include <string>

namespace eitbench {

// InputError(path): "no such file", "is a folder, not a file", "is not a regular file" (a FIFO,
// a device or a socket, which a reader would block on or drain), or "cannot be read: <reason>".
void require_input_file(const std::string& path);

// InputError(path): "no such folder" or "is a file, not a folder".
void require_input_folder(const std::string& path);

}  // namespace eitbench
