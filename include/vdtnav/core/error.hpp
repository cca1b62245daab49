#pragma once
/// \file
/// \brief The one exception hierarchy of vdtnav. Exceptions are thrown only at I/O and
/// configuration boundaries; estimators on the hot path return results with a status.

#include <cstddef>
#include <stdexcept>
#include <string>

namespace vdtnav {

/// \brief Base of every exception vdtnav throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief A file could not be opened, read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

/// \brief A file was read but its content is not what was expected.
/// The message has the form `file:line: what was expected` (line omitted when 0).
class FormatError : public Error {
 public:
  FormatError(const std::string& file, std::size_t line, const std::string& what)
      : Error(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what),
        file_(file),
        line_(line) {}

  /// \return the file the error was found in.
  [[nodiscard]] const std::string& file() const noexcept { return file_; }
  /// \return the 1-based line of the error, or 0 for binary files / whole-file errors.
  [[nodiscard]] std::size_t line() const noexcept { return line_; }

 private:
  std::string file_;
  std::size_t line_;
};

/// \brief An option or argument is out of its documented domain.
class ConfigError : public Error {
 public:
  using Error::Error;
};

}  // namespace vdtnav

/// Boundary check that always runs: throws vdtnav::ConfigError with the message.
#define VDTNAV_CHECK(cond, msg)                      \
  do {                                               \
    if (!(cond)) throw ::vdtnav::ConfigError((msg)); \
  } while (false)

/// Internal invariant, compiled out of release builds (NDEBUG).
#ifdef NDEBUG
#define VDTNAV_ASSERT(cond) ((void)0)
#else
#include <cassert>
#define VDTNAV_ASSERT(cond) assert(cond)
#endif
