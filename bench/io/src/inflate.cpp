#include "inflate.h"

#include <zlib.h>

#include <limits>

#include "eitbench/jacobian/error.h"

namespace eitbench::detail {

std::string inflate(const char* data, std::size_t size, bool raw, std::size_t limit,
                    const std::string& source, const std::string& field) {
  z_stream z{};
  if (inflateInit2(&z, raw ? -MAX_WBITS : MAX_WBITS) != Z_OK)
    throw InputError(source, field, "zlib failed to start");
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
  z.avail_in = static_cast<uInt>(std::min<std::size_t>(size, std::numeric_limits<uInt>::max()));
  std::string out;
  char buffer[1 << 16];
  int status = Z_OK;
  while (status != Z_STREAM_END) {
    z.next_out = reinterpret_cast<Bytef*>(buffer);
    z.avail_out = sizeof buffer;
    status = ::inflate(&z, Z_NO_FLUSH);
    if (status != Z_OK && status != Z_STREAM_END) {
      inflateEnd(&z);
      throw InputError(source, field, "compressed data are corrupt or truncated");
    }
    out.append(buffer, sizeof buffer - z.avail_out);
    if (out.size() > limit) {
      inflateEnd(&z);
      throw InputError(source, field,
                       "decompresses to more than " + std::to_string(limit) + " bytes");
    }
    if (status == Z_OK && z.avail_in == 0 && z.avail_out != 0) {
      inflateEnd(&z);
      throw InputError(source, field, "compressed data end early (truncated)");
    }
  }
  inflateEnd(&z);
  return out;
}

}  // namespace eitbench::detail
