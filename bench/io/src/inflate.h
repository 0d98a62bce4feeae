#pragma once
// Internal: zlib for the .npz and .mat readers.
#include <cstddef>
#include <string>

namespace eitbench::detail {

// Inflates zlib (raw = false) or raw deflate (raw = true) data, refusing output beyond `limit`.
std::string inflate(const char* data, std::size_t size, bool raw, std::size_t limit,
                    const std::string& source, const std::string& field);

}  // namespace eitbench::detail
