#pragma once
// Internal: reading a file from outside in a child process first.
//
// Debian 12's libhdf5 (1.10.8) is not safe on corrupt files. Fuzzing the data-set reader found it
// loop forever in the global heap behind variable-length strings, read freed memory, and ask
// malloc for exabytes. None of that can be caught in the process that suffers it. So a file from
// outside is read in a forked child, which hands what it read to this process as bytes
// (wire.h). When the child crashes or runs past its limit, the caller gets an InputError naming
// the file instead, and libhdf5 never parses the file in this process.
#include <functional>
#include <string>

namespace eitbench::detail {

// Runs `read` in a child process and returns the bytes it returned. An InputError there is thrown
// here again (same source, field and message); any other exception, a crash or a run past
// child_read_limit(path) (the child is then killed) becomes an InputError naming `path`. Where no
// child can be made, `read` runs here.
std::string read_in_child(const std::string& path, const std::function<std::string()>& read);

// The time a child may take: the base (20 s unless set) and a second for each 5 MB the file
// occupies on disk (not its apparent size, which a sparse file inflates), at most 120 s more.
double child_read_limit(const std::string& path);
// For the fuzz targets, whose driver counts 10 s as a hang.
void set_child_read_base_limit(double seconds);

}  // namespace eitbench::detail
