#pragma once
// Internal: the bytes in which a child process hands what it read to its parent (child_read.h).
// Both ends are this program, built once, so this is no file format: no version, no byte order;
// the reader only refuses to step outside its buffer.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace eitbench::detail {

class WireWriter {
 public:
  template <typename T>
  void pod(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  void text(const std::string& s) {
    pod<std::uint64_t>(s.size());
    bytes_ += s;
  }
  template <typename T>
  void vector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod<std::uint64_t>(v.size());
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  template <typename Matrix>  // an Eigen matrix or vector, in its own storage order
  void matrix(const Matrix& m) {
    pod<std::int64_t>(m.rows()), pod<std::int64_t>(m.cols());
    bytes_.append(reinterpret_cast<const char*>(m.data()),
                  static_cast<std::size_t>(m.size()) * sizeof(typename Matrix::Scalar));
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class WireReader {
 public:
  explicit WireReader(const std::string& bytes) : bytes_(bytes) {}
  template <typename T>
  T pod() {
    T value;
    std::memcpy(&value, step(sizeof value), sizeof value);
    return value;
  }
  std::string text() {
    const auto size = pod<std::uint64_t>();
    return std::string(step(size), size);
  }
  template <typename T>
  std::vector<T> vector() {
    const auto size = pod<std::uint64_t>();
    if (size > (bytes_.size() - at_) / sizeof(T)) step(bytes_.size() + 1);  // throws
    std::vector<T> v(size);
    if (size) std::memcpy(v.data(), step(size * sizeof(T)), size * sizeof(T));
    return v;
  }
  template <typename Matrix>
  Matrix matrix() {
    const auto rows = pod<std::int64_t>(), cols = pod<std::int64_t>();
    Matrix m(rows, cols);
    const std::size_t size =
        static_cast<std::size_t>(rows * cols) * sizeof(typename Matrix::Scalar);
    if (size) std::memcpy(m.data(), step(size), size);
    return m;
  }

 private:
  const char* step(std::size_t size) {
    if (size > bytes_.size() - at_) throw std::logic_error("WireReader: read past the end");
    const char* p = bytes_.data() + at_;
    at_ += size;
    return p;
  }
  const std::string& bytes_;
  std::size_t at_ = 0;
};

}  // namespace eitbench::detail
