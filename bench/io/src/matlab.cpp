// MATLAB .mat files: level 5 (as EIDORS and many instruments write, usually compressed) and
// v7.3 (HDF5 with a 512-byte header; arrays stored transposed). Numeric matrices are read;
// structs, cells and text are listed by name so the message can say what the file holds.
#include <H5Cpp.h>
#include <fmt/core.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "eitbench/bench/io/child_read.h"
#include "eitbench/bench/io/matlab.h"
#include "eitbench/bench/io/wire.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/read_budget.h"
#include "inflate.h"

namespace eitbench::detail {
namespace {

enum : std::uint32_t {
  miINT8 = 1,
  miUINT8,
  miINT16,
  miUINT16,
  miINT32,
  miUINT32,
  miSINGLE,
  miDOUBLE = 9,
  miINT64 = 12,
  miUINT64,
  miMATRIX,
  miCOMPRESSED,
  miUTF8,
  miUTF16,
  miUTF32
};

std::uint32_t u32(const std::string& b, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;  // little-endian files on a little-endian machine ("IM")
}

int type_size(std::uint32_t type) {
  switch (type) {
    case miINT8:
    case miUINT8:
      return 1;
    case miINT16:
    case miUINT16:
      return 2;
    case miINT32:
    case miUINT32:
    case miSINGLE:
      return 4;
    case miDOUBLE:
    case miINT64:
    case miUINT64:
      return 8;
    default:
      return 0;
  }
}

double number(std::uint32_t type, const char* p) {
  switch (type) {
    case miINT8: {
      std::int8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case miUINT8: {
      std::uint8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case miINT16: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case miUINT16: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case miINT32: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case miUINT32: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case miSINGLE: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case miDOUBLE: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    case miINT64: {
      std::int64_t v;
      std::memcpy(&v, p, 8);
      return static_cast<double>(v);
    }
    default: {
      std::uint64_t v;
      std::memcpy(&v, p, 8);
      return static_cast<double>(v);
    }
  }
}

struct Element {
  std::uint32_t type;
  std::size_t begin, size;  // data bytes within the buffer
};

// The data element at `at`, in the full or the small (4-byte) format; `at` moves past it.
Element next_element(const std::string& b, std::size_t& at, const std::string& source,
                     const std::string& field) {
  if (at + 8 > b.size()) throw InputError(source, field, "truncated data element");
  const std::uint32_t first = u32(b, at);
  if (first >> 16) {  // small element: size in the upper half, data in the next four bytes
    Element e{first & 0xFFFF, at + 4, first >> 16};
    if (e.size > 4) throw InputError(source, field, "corrupt small data element");
    at += 8;
    return e;
  }
  Element e{first, at + 8, u32(b, at + 4)};
  if (e.size > b.size() - e.begin)
    throw InputError(source, field, "a data element runs past the end (truncated)");
  // Elements are padded to 8 bytes, except compressed ones, which end where their data ends.
  at = e.begin + (e.type == miCOMPRESSED ? e.size : ((e.size + 7) / 8) * 8);
  return e;
}

const char* class_name(int c) {
  static const char* names[] = {"?",      "cell",   "struct", "object", "char",  "sparse",
                                "double", "single", "int8",   "uint8",  "int16", "uint16",
                                "int32",  "uint32", "int64",  "uint64"};
  return c >= 0 && c < 16 ? names[c] : "unknown";
}

NamedArray read_matrix(const std::string& b, std::size_t begin, std::size_t end,
                       const std::string& source, ReadBudget& budget) {
  std::string m = b.substr(begin, end - begin);
  std::size_t at = 0;
  const Element flags = next_element(m, at, source, "array flags");
  if (flags.type != miUINT32 || flags.size != 8)
    throw InputError(source, "array flags", "corrupt matrix header");
  const std::uint32_t f = u32(m, flags.begin);
  const int cls = static_cast<int>(f & 0xFF);
  const bool complex = f & 0x0800;
  NamedArray a;
  a.kind = class_name(cls);
  const Element dims = next_element(m, at, source, "dimensions");
  if (dims.type != miINT32 || dims.size % 4)
    throw InputError(source, "dimensions", "corrupt matrix dimensions");
  double count = 1;
  for (std::size_t k = 0; k < dims.size / 4; ++k) {
    std::int32_t d;
    std::memcpy(&d, m.data() + dims.begin + 4 * k, 4);
    if (d < 0) throw InputError(source, "dimensions", "negative dimension");
    a.shape.push_back(static_cast<std::size_t>(d));
    count *= d;
  }
  const Element name = next_element(m, at, source, "array name");
  a.name = m.substr(name.begin, name.size);
  if (cls < 6 || cls > 15 || complex) {
    a.numeric = false;
    if (complex) a.kind = "complex " + a.kind;
    return a;
  }
  const Element real = next_element(m, at, source, a.name);
  const int size = type_size(real.type);
  if (size == 0)
    throw InputError(source, a.name,
                     "unsupported numeric storage type " + std::to_string(real.type));
  if (count * size != static_cast<double>(real.size))
    throw InputError(source, a.name, "data size does not match its dimensions");
  budget.take(a.name, count * sizeof(double), fmt::format("{:.0f} values", count));
  const std::size_t n = static_cast<std::size_t>(count);
  std::vector<double> column(n);
  for (std::size_t i = 0; i < n; ++i)
    column[i] = number(real.type, m.data() + real.begin + i * size);
  a.values.resize(n);
  if (a.shape.size() == 2) {  // MATLAB stores column-major
    const std::size_t r = a.shape[0], c = a.shape[1];
    for (std::size_t i = 0; i < r; ++i)
      for (std::size_t j = 0; j < c; ++j) a.values[i * c + j] = column[j * r + i];
  } else {
    a.values = column;
  }
  return a;
}

// The variables of `b` from `at` on. A compressed variable is inflated once, against what is left
// of the budget; MATLAB never nests one in another, and a file that does (8,000 layers kept 2.4 GB
// alive through the recursion) is refused at the second layer.
void read_elements(const std::string& b, std::size_t at, const std::string& source,
                   std::vector<NamedArray>& out, ReadBudget& budget, bool inside_compressed) {
  while (at + 8 <= b.size()) {
    const Element e = next_element(b, at, source, "data element");
    if (e.type == miCOMPRESSED) {
      if (inside_compressed)
        throw InputError(source, "compressed variable",
                         "holds another compressed element: MATLAB never nests them");
      const std::string inner =
          inflate(b.data() + e.begin, e.size, false, static_cast<std::size_t>(budget.left()),
                  source, "compressed variable");
      budget.take("compressed variable", static_cast<double>(inner.size()));
      read_elements(inner, 0, source, out, budget, true);
    } else if (e.type == miMATRIX) {
      if (e.size > 0) out.push_back(read_matrix(b, e.begin, e.begin + e.size, source, budget));
    }
  }
}

}  // namespace

std::vector<NamedArray> read_mat_v5(const std::string& b, const std::string& source) {
  if (b.size() < 128 || b.compare(0, 6, "MATLAB") != 0)
    throw InputError(source, "header", "not a MATLAB .mat file");
  if (b.compare(126, 2, "IM") != 0)
    throw InputError(source, "header",
                     b.compare(126, 2, "MI") == 0
                         ? "big-endian .mat files are not supported"
                         : "not a level-5 MAT file (bad endian indicator)");
  std::vector<NamedArray> out;
  ReadBudget budget(source);
  read_elements(b, 128, source, out, budget, false);
  if (out.empty()) throw InputError(source, "variables", "the file holds no variables");
  return out;
}

namespace {

void append_u32(std::string& b, std::uint32_t v) {
  b.append(reinterpret_cast<const char*>(&v), 4);  // little-endian ("IM")
}

// A data element: its tag, its bytes, padding to 8 bytes.
void append_element(std::string& b, std::uint32_t type, const std::string& data) {
  append_u32(b, type);
  append_u32(b, static_cast<std::uint32_t>(data.size()));
  b += data;
  b.append((8 - data.size() % 8) % 8, '\0');
}

bool matlab_name(const std::string& n) {
  if (n.empty() || n.size() > 63 || !std::isalpha(static_cast<unsigned char>(n[0]))) return false;
  for (char c : n)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

}  // namespace

std::string mat_v5_bytes(const std::vector<MatMatrix>& matrices) {
  std::string b = "MATLAB 5.0 MAT-file, written by eitbench";
  b.resize(116, ' ');
  b.append(8, '\0');  // no subsystem data
  b += std::string("\x00\x01", 2) + "IM";
  for (const MatMatrix& m : matrices) {
    if (!matlab_name(m.name))
      throw std::invalid_argument("mat_v5_bytes: bad name '" + m.name + "'");
    if (m.values.size() != m.rows * m.cols)
      throw std::invalid_argument("mat_v5_bytes: " + m.name + " has the wrong number of values");
    if (m.rows > 0x7fffffff || m.cols > 0x7fffffff || m.values.size() > 0x0fffffff)
      throw std::invalid_argument("mat_v5_bytes: " + m.name + " is too large");
    std::string matrix, word;
    append_u32(word, m.uint8 ? 9 : 6);  // mxUINT8_CLASS or mxDOUBLE_CLASS, no flags
    append_u32(word, 0);
    append_element(matrix, miUINT32, word);
    word.clear();
    append_u32(word, static_cast<std::uint32_t>(m.rows));
    append_u32(word, static_cast<std::uint32_t>(m.cols));
    append_element(matrix, miINT32, word);
    append_element(matrix, miINT8, m.name);
    std::string data(m.values.size() * (m.uint8 ? 1 : 8), '\0');
    for (std::size_t i = 0; i < m.rows; ++i)
      for (std::size_t j = 0; j < m.cols; ++j) {
        const double v = m.values[i * m.cols + j];
        const std::size_t at = j * m.rows + i;  // MATLAB stores column-major
        if (!m.uint8) {
          std::memcpy(&data[8 * at], &v, 8);
          continue;
        }
        if (!(v >= 0 && v <= 255 && v == std::floor(v)))
          throw std::invalid_argument("mat_v5_bytes: " + m.name +
                                      " holds a value that is no uint8");
        data[at] = static_cast<char>(static_cast<std::uint8_t>(v));
      }
    append_element(matrix, m.uint8 ? miUINT8 : miDOUBLE, data);
    append_element(b, miMATRIX, matrix);
  }
  return b;
}

namespace {

std::string hdf5_shape_text(const std::vector<hsize_t>& dims) {
  std::string text;
  for (hsize_t d : dims) text += (text.empty() ? "" : " x ") + std::to_string(d);
  return text + " values";
}

std::vector<NamedArray> read_mat_v73_here(const std::string& path) {
  std::vector<NamedArray> out;
  ReadBudget budget(path);
  try {
    H5::Exception::dontPrint();
    H5::H5File file(path, H5F_ACC_RDONLY);
    const hsize_t count = file.getNumObjs();
    for (hsize_t k = 0; k < count; ++k) {
      const std::string name = file.getObjnameByIdx(k);
      if (name.empty() || name[0] == '#' || file.getObjTypeByIdx(k) != H5G_DATASET)
        continue;  // MATLAB's #refs#
      H5::DataSet set = file.openDataSet(name);
      NamedArray a;
      a.name = name;
      if (set.attrExists("MATLAB_class")) {
        H5::Attribute c = set.openAttribute("MATLAB_class");
        c.read(c.getStrType(), a.kind);
      }
      H5::DataSpace space = set.getSpace();
      std::vector<hsize_t> dims(space.getSimpleExtentNdims());
      space.getSimpleExtentDims(dims.data());
      const H5T_class_t type = set.getTypeClass();
      if ((type != H5T_FLOAT && type != H5T_INTEGER) || a.kind == "char" || a.kind == "logical" ||
          dims.size() > 2) {
        a.numeric = false;
        out.push_back(a);
        continue;
      }
      double n = 1;
      for (hsize_t d : dims) n *= static_cast<double>(d);
      budget.take_compressed(name, n * set.getDataType().getSize(),
                             static_cast<double>(set.getStorageSize()), n * sizeof(double),
                             hdf5_shape_text(dims));
      // MATLAB's r x c matrix is an HDF5 array of c x r: its bytes are the matrix column by column.
      std::vector<double> column(static_cast<std::size_t>(n));
      if (!column.empty()) set.read(column.data(), H5::PredType::NATIVE_DOUBLE);
      std::vector<std::size_t> shape(dims.rbegin(), dims.rend());
      if (shape.size() == 1) shape.insert(shape.begin(), 1);
      a.shape = shape;
      const std::size_t r = shape[0], c = shape[1];
      a.values.resize(column.size());
      for (std::size_t i = 0; i < r; ++i)
        for (std::size_t j = 0; j < c; ++j) a.values[i * c + j] = column[j * r + i];
      out.push_back(a);
    }
  } catch (const H5::Exception& e) {
    throw InputError(path, "", "cannot read the MATLAB v7.3 (HDF5) file: " + e.getDetailMsg());
  }
  if (out.empty()) throw InputError(path, "variables", "the file holds no variables");
  return out;
}

}  // namespace

std::vector<NamedArray> read_mat_v73(const std::string& path) {
  // libhdf5 may crash or hang on a corrupt file: it reads the file in a child (child_read.h).
  const std::string bytes = read_in_child(path, [&path] {
    WireWriter w;
    const std::vector<NamedArray> arrays = read_mat_v73_here(path);
    w.pod<std::uint64_t>(arrays.size());
    for (const NamedArray& a : arrays) {
      w.text(a.name), w.text(a.kind), w.pod(a.numeric);
      w.vector(a.shape), w.vector(a.values);
    }
    return w.take();
  });
  WireReader r(bytes);
  std::vector<NamedArray> arrays(r.pod<std::uint64_t>());
  for (NamedArray& a : arrays) {
    a.name = r.text(), a.kind = r.text(), a.numeric = r.pod<bool>();
    a.shape = r.vector<std::size_t>(), a.values = r.vector<double>();
  }
  return arrays;
}

}  // namespace eitbench::detail
