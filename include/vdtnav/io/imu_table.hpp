#pragma once
/// \file
/// \brief IMU readings as CSV: one sample a line, `t,wx,wy,wz,ax,ay,az` — time in seconds, the
/// body angular velocity in rad/s, the specific force in m/s^2 (body frame, +9.81 on z at rest,
/// level: sensor/imu.hpp). Commas with optional spaces around them; lines starting with `#` and
/// blank lines are skipped; a first line naming exactly these columns is an optional header.

#include <cstddef>
#include <string>
#include <vector>

#include "vdtnav/sensor/imu.hpp"

namespace vdtnav {

/// \brief What load_imu_csv skipped.
struct ImuCsvReport {
  bool header = false;                        ///< the file had the header line
  std::vector<std::size_t> non_finite_lines;  ///< 1-based lines dropped for a NaN or inf
};

/// \brief Reads IMU samples. Rows with a NaN or infinite number are dropped (listed in `report`).
/// \throws IoError when the file cannot be read; FormatError (`file:line: what was expected`) for
/// a row that is not 7 numbers, for a time not after the previous row's (times strictly
/// increasing), or for a file without a row.
[[nodiscard]] std::vector<ImuSample> load_imu_csv(const std::string& path,
                                                  ImuCsvReport* report = nullptr);

/// \brief Writes samples with the header line, every number in the shortest fixed-point form that
/// reads back as the same double (load_imu_csv returns them bit for bit).
/// \throws ConfigError for a non-finite sample or times not strictly increasing; IoError when the
/// file cannot be written.
void save_imu_csv(const std::string& path, const std::vector<ImuSample>& samples);

}  // namespace vdtnav
