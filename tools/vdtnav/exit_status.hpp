#pragma once
/// \file
/// \brief What `vdtnav`'s exit status means, and the two errors that choose one.
///
///   0  the run completed (and, for the localizers, localized at least one scan)
///   1  bad input: a file missing, unreadable or not in its format (file:line: what was expected)
///   2  bad usage: an option missing, unknown or out of its domain (CLI11's own errors too)
///   3  the run completed and wrote its outputs, but no scan was localized (a map that explains
///      nothing, a start the map cannot confirm), or with --strict some scan was lost
/// --help and --version exit 0.

#include "vdtnav/core/error.hpp"

namespace vdtnav::tools {

enum ExitStatus : int { kExitOk = 0, kExitBadInput = 1, kExitUsage = 2, kExitNotLocalized = 3 };

/// \brief An option or combination of options out of its domain: exit 2.
class UsageError : public ConfigError {
 public:
  using ConfigError::ConfigError;
};

/// \brief Thrown after the outputs are written: the run completed, but no scan was localized (or
/// --strict and a scan was lost). Exit 3.
class NotLocalized : public Error {
 public:
  using Error::Error;
};

}  // namespace vdtnav::tools
