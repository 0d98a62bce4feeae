// NumPy .npy and .npz (a ZIP archive of .npy files, stored or deflated, with zip64 fields).

#include <zlib.h>

#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "eitbench/bench/io/numpy.h"
#include "eitbench/jacobian/error.h"
#include "inflate.h"

namespace eitbench::detail {
namespace {

constexpr std::size_t kMaxElements = std::size_t(1) << 31;  // 16 GB of doubles

// Text from a binary header, fit for a message: control bytes become '?'.
std::string printable(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 32 || c == 127) c = '?';
  return text;
}

std::uint64_t le(const std::string& b, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int k = bytes - 1; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(b[at + k]);
  return v;
}

template <typename T>
double load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

// The value of `key` in a NumPy header dict: {'descr': '<f8', 'fortran_order': False, 'shape': (3,
// 208), }
std::string header_value(const std::string& header, const std::string& key,
                         const std::string& source) {
  const std::size_t k = header.find("'" + key + "'");
  if (k == std::string::npos) throw InputError(source, key, "the .npy header has no '" + key + "'");
  std::size_t v = header.find(':', k);
  if (v == std::string::npos) throw InputError(source, key, "malformed .npy header");
  ++v;
  while (v < header.size() && header[v] == ' ') ++v;
  if (v < header.size() && (header[v] == '\'' || header[v] == '"')) {
    const std::size_t end = header.find(header[v], v + 1);
    if (end == std::string::npos) throw InputError(source, key, "malformed .npy header");
    return header.substr(v + 1, end - v - 1);
  }
  if (v < header.size() && header[v] == '(') {
    const std::size_t end = header.find(')', v);
    if (end == std::string::npos) throw InputError(source, key, "malformed .npy header");
    return header.substr(v + 1, end - v - 1);
  }
  const std::size_t end = header.find_first_of(",}", v);
  return header.substr(v, end - v);
}

}  // namespace

NamedArray read_npy(const std::string& b, const std::string& source, const std::string& name) {
  const std::string field = name.empty() ? "header" : name;
  if (b.size() < 10 || b.compare(0, 6, "\x93NUMPY") != 0)
    throw InputError(source, field, "not a NumPy .npy array (bad magic)");
  const int major = static_cast<unsigned char>(b[6]);
  if (major < 1 || major > 3)
    throw InputError(source, field, "unsupported .npy version " + std::to_string(major));
  const std::size_t header_at = major == 1 ? 10 : 12;
  if (b.size() < header_at) throw InputError(source, field, "truncated .npy header");
  const std::size_t header_len = le(b, 8, major == 1 ? 2 : 4);
  if (header_at + header_len > b.size()) throw InputError(source, field, "truncated .npy header");
  const std::string header = b.substr(header_at, header_len);
  const std::string descr = header_value(header, "descr", source);
  const bool fortran =
      header_value(header, "fortran_order", source).find("True") != std::string::npos;
  NamedArray a;
  a.name = name;
  std::stringstream dims(header_value(header, "shape", source));
  std::string item;
  double count = 1;
  while (std::getline(dims, item, ',')) {
    if (item.find_first_not_of(" ") == std::string::npos) continue;
    char* end = nullptr;
    const char* begin = item.c_str() + item.find_first_not_of(" ");
    const long long d = std::strtoll(begin, &end, 10);
    // Digits, then spaces only (a NUL inside the header is not the string's end: fuzzing found
    // "(7777777777777773\0..., \0 50)" read as 7.8e15 x 0 and a reorder loop of 7.8e15 turns).
    if (d < 0 || end == begin ||
        std::string(static_cast<const char*>(end), item.c_str() + item.size())
                .find_first_not_of(" ") != std::string::npos)
      throw InputError(source, "shape", "'" + printable(item) + "' is not a dimension");
    a.shape.push_back(static_cast<std::size_t>(d));
    count *= static_cast<double>(d);
  }
  if (descr.size() < 3 || (descr[0] != '<' && descr[0] != '|' && descr[0] != '='))
    throw InputError(source, "descr",
                     "dtype '" + descr + "' is not supported (little-endian numbers only)");
  const char kind = descr[1];
  const int size = std::atoi(descr.c_str() + 2);
  const bool ok =
      (kind == 'f' && (size == 4 || size == 8)) ||
      ((kind == 'i' || kind == 'u') && (size == 1 || size == 2 || size == 4 || size == 8));
  if (!ok)
    throw InputError(source, "descr", "dtype '" + descr + "' is not a supported numeric type");
  a.kind = descr;
  const std::size_t data_at = header_at + header_len;
  if (count > static_cast<double>(kMaxElements) ||
      count * size > static_cast<double>(b.size() - data_at))
    throw InputError(source, "shape",
                     "declares more data than the file holds (truncated or corrupt)");
  const std::size_t n = static_cast<std::size_t>(count);
  a.values.resize(n);
  const char* p = b.data() + data_at;
  for (std::size_t i = 0; i < n; ++i, p += size) {
    if (kind == 'f')
      a.values[i] = size == 8 ? load<double>(p) : load<float>(p);
    else if (kind == 'i')
      a.values[i] = size == 1   ? load<std::int8_t>(p)
                    : size == 2 ? load<std::int16_t>(p)
                    : size == 4 ? load<std::int32_t>(p)
                                : load<std::int64_t>(p);
    else
      a.values[i] = size == 1   ? load<std::uint8_t>(p)
                    : size == 2 ? load<std::uint16_t>(p)
                    : size == 4 ? load<std::uint32_t>(p)
                                : load<std::uint64_t>(p);
  }
  if (fortran && a.shape.size() == 2 && n > 0) {  // column-major on disk: reorder to row-major
    std::vector<double> row(n);
    const std::size_t r = a.shape[0], c = a.shape[1];
    for (std::size_t i = 0; i < r; ++i)
      for (std::size_t j = 0; j < c; ++j) row[i * c + j] = a.values[j * r + i];
    a.values.swap(row);
  }
  return a;
}

std::vector<NamedArray> read_npz(const std::string& b, const std::string& source) {
  // End of central directory: the last PK\5\6 within the final 64 KiB + 22 bytes.
  if (b.size() < 22) throw InputError(source, "zip", "too short to be a .npz archive");
  std::size_t eocd = std::string::npos;
  for (std::size_t i = b.size() - 22 + 1; i-- > 0 && b.size() - i <= 65557;)
    if (le(b, i, 4) == 0x06054b50) {
      eocd = i;
      break;
    }
  if (eocd == std::string::npos)
    throw InputError(source, "zip", "no ZIP directory: not a .npz archive, or truncated");
  std::uint64_t entries = le(b, eocd + 10, 2), cd_offset = le(b, eocd + 16, 4);
  if ((entries == 0xFFFF || cd_offset == 0xFFFFFFFF) && eocd >= 20 &&
      le(b, eocd - 20, 4) == 0x07064b50) {
    const std::uint64_t at = le(b, eocd - 20 + 8, 8);  // the zip64 end of central directory
    if (at + 56 > b.size() || le(b, at, 4) != 0x06064b50)
      throw InputError(source, "zip", "corrupt zip64 directory");
    entries = le(b, at + 32, 8);
    cd_offset = le(b, at + 48, 8);
  }
  std::vector<NamedArray> arrays;
  std::size_t at = cd_offset;
  for (std::uint64_t e = 0; e < entries; ++e) {
    if (at + 46 > b.size() || le(b, at, 4) != 0x02014b50)
      throw InputError(source, "zip", "corrupt ZIP directory");
    const int method = static_cast<int>(le(b, at + 10, 2));
    const std::uint32_t crc = static_cast<std::uint32_t>(le(b, at + 16, 4));
    std::uint64_t csize = le(b, at + 20, 4), usize = le(b, at + 24, 4), local = le(b, at + 42, 4);
    const std::size_t name_len = le(b, at + 28, 2), extra_len = le(b, at + 30, 2),
                      comment_len = le(b, at + 32, 2);
    if (at + 46 + name_len + extra_len > b.size())
      throw InputError(source, "zip", "corrupt ZIP directory");
    const std::string name = b.substr(at + 46, name_len);
    for (std::size_t x = at + 46 + name_len;
         x + 4 <= at + 46 + name_len + extra_len;) {  // zip64 sizes
      const std::size_t id = le(b, x, 2), len = le(b, x + 2, 2);
      std::size_t f = x + 4;
      if (id == 0x0001) {
        if (usize == 0xFFFFFFFF && f + 8 <= x + 4 + len) usize = le(b, f, 8), f += 8;
        if (csize == 0xFFFFFFFF && f + 8 <= x + 4 + len) csize = le(b, f, 8), f += 8;
        if (local == 0xFFFFFFFF && f + 8 <= x + 4 + len) local = le(b, f, 8);
      }
      x += 4 + len;
    }
    at += 46 + name_len + extra_len + comment_len;
    if (local + 30 > b.size() || le(b, local, 4) != 0x04034b50)
      throw InputError(source, name, "corrupt ZIP entry");
    const std::size_t data = local + 30 + le(b, local + 26, 2) + le(b, local + 28, 2);
    if (data > b.size() || csize > b.size() - data)
      throw InputError(source, name, "the archive is truncated");
    if (usize > (std::size_t(1) << 34))
      throw InputError(source, name, "declares " + std::to_string(usize) + " bytes, too large");
    std::string content;
    if (method == 0)
      content = b.substr(data, csize);
    else if (method == 8)
      content = inflate(b.data() + data, csize, true, usize, source, name);
    else
      throw InputError(source, name,
                       "compression method " + std::to_string(method) + " is not supported");
    if (content.size() != usize || crc32(0, reinterpret_cast<const Bytef*>(content.data()),
                                         static_cast<uInt>(content.size())) != crc)
      throw InputError(source, name, "the entry is corrupt (size or CRC mismatch)");
    std::string array_name = name;
    if (array_name.size() > 4 && array_name.compare(array_name.size() - 4, 4, ".npy") == 0)
      array_name.resize(array_name.size() - 4);
    arrays.push_back(read_npy(content, source, array_name));
  }
  if (arrays.empty()) throw InputError(source, "zip", "the archive holds no arrays");
  return arrays;
}

std::string npy_bytes(const std::vector<float>& values, const std::vector<std::size_t>& shape) {
  std::size_t count = 1;
  std::string dims;
  for (std::size_t d : shape) count *= d, dims += (dims.empty() ? "" : ", ") + std::to_string(d);
  if (count != values.size())
    throw std::logic_error("npy_bytes: " + std::to_string(values.size()) +
                           " values for a shape of " + std::to_string(count));
  if (shape.size() == 1) dims += ',';  // Python's one-element tuple: (3,)
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + dims + "), }";
  // Magic, version 1.0, header length; the header padded with spaces to a multiple of 64, '\n'.
  const std::size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header += '\n';
  std::string out = "\x93NUMPY\x01";
  out += '\0';
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>(header.size() >> 8);
  out += header;
  const std::size_t at = out.size();
  out.resize(at + values.size() * sizeof(float));
  std::memcpy(out.data() + at, values.data(), values.size() * sizeof(float));  // little-endian
  return out;
}

}  // namespace eitbench::detail
