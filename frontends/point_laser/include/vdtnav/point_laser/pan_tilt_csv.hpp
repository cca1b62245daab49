#pragma once
/// \file
/// \brief Pan-tilt point-laser readings as CSV: a header naming the columns `pan`, `tilt`, `range`
/// and optionally `time` (any order), then one reading per line in radians, metres and seconds.
/// Blank lines and text after `#` are ignored. `inf`/`nan` ranges are readings (no return) that
/// point_laser_observations drops and counts. This part does not need PCL.

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "vdtnav/sensor/pan_tilt_unit.hpp"

namespace vdtnav::point_laser {

/// \brief How to treat a data line that is not a reading.
struct PanTiltCsvOptions {
  /// Skip malformed data lines (wrong number of fields, a field that is not a number) and count
  /// them instead of throwing. A missing or unusable header always throws.
  bool skip_malformed = false;
};

/// \brief The readings of a CSV file.
struct PanTiltCsv {
  std::vector<PanTiltReading> readings;    ///< in file order; time = 0 without a time column
  bool has_time = false;                   ///< the header had a `time` column
  std::size_t skipped_malformed = 0;       ///< data lines skipped (skip_malformed only)
  std::vector<std::size_t> skipped_lines;  ///< their 1-based line numbers
};

/// \brief Reads a pan-tilt CSV file.
/// \throws IoError when the file cannot be read; FormatError (`file:line: what was expected`) for
/// a missing or bad header, or a malformed data line unless options.skip_malformed.
[[nodiscard]] PanTiltCsv read_pan_tilt_csv(const std::string& path,
                                           const PanTiltCsvOptions& options = {});

/// \brief Parses pan-tilt CSV text from a stream; `name` stands for the file in messages.
[[nodiscard]] PanTiltCsv parse_pan_tilt_csv(std::istream& in, const std::string& name,
                                            const PanTiltCsvOptions& options = {});

/// \brief Writes readings as pan-tilt CSV (header `pan,tilt,range[,time]`, 17 significant
/// digits, so that read_pan_tilt_csv returns the same doubles; no return is written `inf`).
/// \throws IoError when the file cannot be written.
void write_pan_tilt_csv(const std::string& path, const std::vector<PanTiltReading>& readings,
                        bool with_time = true);

}  // namespace vdtnav::point_laser
