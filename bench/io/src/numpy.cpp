// NumPy .npy and .npz (a ZIP archive of .npy files, stored or deflated, with zip64 fields).

#include <fmt/core.h>
#include <zlib.h>

#include <algorithm>

#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "eitbench/bench/io/numpy.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/read_budget.h"
#include "inflate.h"

namespace eitbench::detail {
namespace {

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
  ReadBudget budget(source);
  return read_npy(b, source, name, budget);
}

NamedArray read_npy(const std::string& b, const std::string& source, const std::string& name,
                    ReadBudget& budget) {
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
  if (count * size > static_cast<double>(b.size() - data_at))
    throw InputError(source, "shape",
                     "declares more data than the file holds (truncated or corrupt)");
  budget.take(name.empty() ? "shape" : name, count * sizeof(double),
              fmt::format("{:.0f} values", count));
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

namespace {

// One member of a zip archive, as its central directory describes it.
struct ZipMember {
  std::string name;
  int method;
  std::uint32_t crc;
  std::uint64_t stored, size, local, data;  // compressed and declared sizes; offsets
};

// The central directory, every member's header and bounds checked; nothing is inflated yet.
std::vector<ZipMember> zip_directory(const std::string& b, const std::string& source) {
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
  if (entries > b.size() / 46)  // each directory entry takes 46 bytes at least
    throw InputError(source, "zip", "the directory lists more members than the file can hold");
  std::vector<ZipMember> members;
  std::size_t at = cd_offset;
  for (std::uint64_t e = 0; e < entries; ++e) {
    if (at + 46 > b.size() || le(b, at, 4) != 0x02014b50)
      throw InputError(source, "zip", "corrupt ZIP directory");
    ZipMember m;
    m.method = static_cast<int>(le(b, at + 10, 2));
    m.crc = static_cast<std::uint32_t>(le(b, at + 16, 4));
    m.stored = le(b, at + 20, 4), m.size = le(b, at + 24, 4), m.local = le(b, at + 42, 4);
    const std::size_t name_len = le(b, at + 28, 2), extra_len = le(b, at + 30, 2),
                      comment_len = le(b, at + 32, 2);
    if (at + 46 + name_len + extra_len > b.size())
      throw InputError(source, "zip", "corrupt ZIP directory");
    m.name = b.substr(at + 46, name_len);
    for (std::size_t x = at + 46 + name_len;
         x + 4 <= at + 46 + name_len + extra_len;) {  // zip64 sizes
      const std::size_t id = le(b, x, 2), len = le(b, x + 2, 2);
      std::size_t f = x + 4;
      if (id == 0x0001) {
        if (m.size == 0xFFFFFFFF && f + 8 <= x + 4 + len) m.size = le(b, f, 8), f += 8;
        if (m.stored == 0xFFFFFFFF && f + 8 <= x + 4 + len) m.stored = le(b, f, 8), f += 8;
        if (m.local == 0xFFFFFFFF && f + 8 <= x + 4 + len) m.local = le(b, f, 8);
      }
      x += 4 + len;
    }
    at += 46 + name_len + extra_len + comment_len;
    if (m.local > b.size() || b.size() - m.local < 30 || le(b, m.local, 4) != 0x04034b50)
      throw InputError(source, m.name, "corrupt ZIP entry");
    m.data = m.local + 30 + le(b, m.local + 26, 2) + le(b, m.local + 28, 2);
    if (m.data > b.size() || m.stored > b.size() - m.data)
      throw InputError(source, m.name, "the archive is truncated");
    members.push_back(std::move(m));
  }
  return members;
}

// Every member names its own bytes: no two share a name or a byte of the file. An archive whose
// directory points many entries at one member would be decoded as many times (2,000 copies of
// one 8 MB member asked for 16 GB).
void check_distinct(std::vector<const ZipMember*> members, const std::string& source) {
  std::sort(members.begin(), members.end(),
            [](const ZipMember* a, const ZipMember* b) { return a->local < b->local; });
  for (std::size_t k = 1; k < members.size(); ++k)
    if (members[k]->local < members[k - 1]->data + members[k - 1]->stored)
      throw InputError(source, members[k]->name,
                       "overlaps the member '" + members[k - 1]->name +
                           "' in the file: a ZIP member has bytes of its own");
  std::sort(members.begin(), members.end(),
            [](const ZipMember* a, const ZipMember* b) { return a->name < b->name; });
  for (std::size_t k = 1; k < members.size(); ++k)
    if (members[k]->name == members[k - 1]->name)
      throw InputError(source, members[k]->name, "appears twice in the archive");
}

}  // namespace

std::vector<NamedArray> read_npz(const std::string& b, const std::string& source) {
  const std::vector<ZipMember> members = zip_directory(b, source);
  std::vector<const ZipMember*> pointers;
  for (const ZipMember& m : members) pointers.push_back(&m);
  check_distinct(pointers, source);
  ReadBudget budget(source);
  for (const ZipMember& m : members) {  // every declared size, before anything is inflated
    if (m.method == 0 && m.size != m.stored)
      throw InputError(source, m.name, "a stored member's sizes differ (corrupt)");
    if (m.method != 0 && m.method != 8)
      throw InputError(source, m.name,
                       "compression method " + std::to_string(m.method) + " is not supported");
    if (m.method == 8)
      budget.take_compressed(m.name, static_cast<double>(m.size), static_cast<double>(m.stored),
                             static_cast<double>(m.size),
                             "a member of " + std::to_string(m.size) + " bytes");
  }
  std::vector<NamedArray> arrays;
  for (const ZipMember& m : members) {
    const std::string content =
        m.method == 0 ? b.substr(m.data, m.stored)
                      : inflate(b.data() + m.data, m.stored, true, m.size, source, m.name);
    if (content.size() != m.size || crc32(0, reinterpret_cast<const Bytef*>(content.data()),
                                          static_cast<uInt>(content.size())) != m.crc)
      throw InputError(source, m.name,
                       "inflates to " + std::to_string(content.size()) + " bytes, declared " +
                           std::to_string(m.size) + ", or fails its CRC: the entry is corrupt");
    std::string array_name = m.name;
    if (array_name.size() > 4 && array_name.compare(array_name.size() - 4, 4, ".npy") == 0)
      array_name.resize(array_name.size() - 4);
    arrays.push_back(read_npy(content, source, array_name, budget));
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
