#pragma once
// The one exception type for bad input anywhere in eitbench: it names where the input came from
// (a file path, "--option", or in the libraries the options struct or argument) and the field that
// is wrong, so a user can fix it.
//
// The convention, in every library: InputError for data and options that come from a user (a
// file, a flag, an options struct, a frame); std::logic_error and its subclasses (such as
// std::invalid_argument) for a programming error, a call the code around it should never make
// (a null pointer, a size that an earlier check guaranteed); NumericalError for a computation that
// the numbers it was given defeat (a system that lost definiteness in floating point), which an
// iterative solver may treat as "no descent there"; std::runtime_error for the rest (memory, the
// file system).
#include <stdexcept>
#include <string>

namespace eitbench {

class InputError : public std::runtime_error {
 public:
  InputError(std::string source, std::string field, const std::string& message)
      : std::runtime_error(compose(source, field, message)),
        source_(std::move(source)),
        field_(std::move(field)),
        message_(message) {}

  const std::string& source() const { return source_; }
  const std::string& field() const { return field_; }
  const std::string& message() const { return message_; }  // what() without source and field

 private:
  static std::string compose(const std::string& source, const std::string& field,
                             const std::string& message) {
    std::string out = source.empty() ? std::string("input") : source;
    if (!field.empty()) out += ": " + field;
    return out + ": " + message;
  }
  std::string source_;
  std::string field_;
  std::string message_;
};

// The numbers defeated a computation (not the memory, not the input's form): for example, a
// conductivity so extreme that the CEM matrix is no longer positive definite in floating point.
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace eitbench
