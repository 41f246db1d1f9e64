#pragma once
// Typed exceptions thrown by the library. Command lines catch splat::Error, print
// "error: <what()>" and exit with status 2 (docs/DESIGN.md, "Errors").
#include <filesystem>
#include <stdexcept>
#include <string>

namespace splat {

// Base of every error the library raises on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bad or unreadable input: the message always starts with the file it concerns,
// so a user can tell which of several inputs is at fault.
class InputError : public Error {
 public:
  InputError(const std::filesystem::path& file, const std::string& problem)
      : Error(file.string() + ": " + problem), file_(file) {}
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
};

// A caller passed arguments that cannot work (wrong sizes, out-of-range indices).
class ArgumentError : public Error {
 public:
  using Error::Error;
};

}  // namespace splat
