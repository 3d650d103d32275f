// Error types. Every error that reaches the user names what is wrong and where.
#pragma once

#include <stdexcept>
#include <string>

namespace arcs {

// Base class of all arcs errors.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Malformed or unusable input data (a file, an array, a YAML document).
// The message is "FILE:LINE: what" (line 0 = whole file; for binary files the
// location is "FILE: offset N: what").
class InputError : public Error {
 public:
  InputError(const std::string& file, long line, const std::string& what)
      : Error(Format(file, line, what)), file_(file), line_(line) {}
  const std::string& file() const { return file_; }
  long line() const { return line_; }

  static std::string Format(const std::string& file, long line, const std::string& what) {
    if (file.empty()) return what;
    if (line > 0) return file + ":" + std::to_string(line) + ": " + what;
    return file + ": " + what;
  }

 private:
  std::string file_;
  long line_;
};

// A parameter or option value out of its allowed range / choices.
class OptionError : public Error {
 public:
  using Error::Error;
};

// Thrown when a run was cancelled through the context's stop flag.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

// Throws OptionError("<name> = <value>: must be <rule>") unless `ok`.
#define ARCS_CHECK_OPTION(ok, name, value, rule)                                          \
  do {                                                                                    \
    if (!(ok)) {                                                                          \
      throw ::arcs::OptionError(std::string(name) + " = " + std::to_string(value) +     \
                                ": must be " + (rule));                                   \
    }                                                                                     \
  } while (0)

}  // namespace arcs
