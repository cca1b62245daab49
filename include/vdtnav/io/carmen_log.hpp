#pragma once
/// \file
/// \brief CARMEN log files (`.clf`, `.log`, plain or gzip): laser scans, odometry and parameters,
/// and a writer whose output the reader takes back to full double precision.
///
/// Messages read (one a line, fields separated by spaces or tabs):
///  - `FLASER n r1..rn x y theta odom_x odom_y odom_theta ipc_timestamp hostname logger_timestamp`
///  - `ROBOTLASER1 laser_type start_angle fov angular_res max_range accuracy remission_mode
///     n r1..rn m rem1..remm laser_x laser_y laser_theta robot_x robot_y robot_theta laser_tv
///     laser_rv forward_safety_dist side_safety_dist turn_axis ipc_timestamp hostname
///     logger_timestamp`
///  - `ODOM x y theta tv rv accel ipc_timestamp hostname logger_timestamp`
///  - `PARAM name value ipc_timestamp hostname logger_timestamp` (a value of several fields is
///    kept joined by single spaces)
/// Lines starting with `#` are comments, blank lines are ignored, and every other message type
/// (NEFF, RAWLASER1, TRUEPOS, RLASER, ...) is skipped and counted per type.
///
/// Time base: a record's `time` is the logger_timestamp (the clock the logger wrote the line
/// with, the one gmapping-corrected logs and their derived tables use); the ipc_timestamp (when
/// the message was published) is kept beside it.

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav {

/// \brief How a CARMEN log is read.
struct CarmenLogOptions {
  /// No-return threshold, metres: the scan's range_max, so readings >= max_range are dropped by
  /// scan_points() and never become obstacles. FLASER carries no maximum range; 80 m is the
  /// longest range of the SICK LMS that recorded most CARMEN logs, whose no-return code lies just
  /// above it (81.83 in the Intel lab log, 81.91 elsewhere). Logs with a lower code need a lower
  /// value: 32.0 for logs that mark no return with 32.76, 51.0 for the MIT Killian Court log (its
  /// no-return readings are 51.05..51.16). ROBOTLASER1 carries its own max_range: the scan's
  /// range_max is the smaller of the two (a non-finite or non-positive message value is ignored).
  double max_range = 80.0;
  /// Readings below this (metres) are dropped as well: the scan's range_min. SICK reports
  /// dazzling and other errors as ranges near 0.
  double range_min = 0.1;
  /// false: a malformed line throws FormatError. true: it is skipped and its line number recorded
  /// in CarmenLog::malformed_lines.
  bool skip_malformed = false;
};

/// \brief One laser message (FLASER or ROBOTLASER1).
struct CarmenLaser {
  double time = 0.0;      ///< logger_timestamp, seconds (the log's time base)
  double ipc_time = 0.0;  ///< ipc_timestamp, seconds
  std::string hostname;   ///< as logged (one token)
  /// The laser's pose as the message gives it: FLASER x y theta, ROBOTLASER1 laser_x/y/theta. In
  /// gmapping-corrected logs this is the corrected pose, in raw logs the odometry.
  Pose2 pose = Pose2::Zero();
  /// The robot's odometry pose: FLASER odom_x/y/theta, ROBOTLASER1 robot_x/y/theta.
  Pose2 odom = Pose2::Zero();
  /// The readings, in the frame of `pose` (mount zero). time = `time`; NaN/inf readings are kept
  /// (scan_points() drops and counts them); range_max is the no-return threshold.
  LaserScan scan;
  std::vector<double> remissions;  ///< ROBOTLASER1's remission values (empty for FLASER)
  std::size_t line = 0;            ///< 1-based line in the file read (0 when not read)
};

/// \brief One ODOM message.
struct CarmenOdometry {
  double time = 0.0;           ///< logger_timestamp, seconds
  double ipc_time = 0.0;       ///< ipc_timestamp, seconds
  std::string hostname;        ///< as logged (one token)
  Pose2 pose = Pose2::Zero();  ///< x, y, theta
  double tv = 0.0;             ///< translational velocity, m/s
  double rv = 0.0;             ///< rotational velocity, rad/s
  double accel = 0.0;          ///< acceleration, m/s^2
  std::size_t line = 0;        ///< 1-based line in the file read (0 when not read)
};

/// \brief The content of a CARMEN log, in file order per message type.
struct CarmenLog {
  std::vector<CarmenLaser> lasers;            ///< FLASER and ROBOTLASER1 messages
  std::vector<CarmenOdometry> odometry;       ///< ODOM messages
  std::map<std::string, std::string> params;  ///< PARAM name -> value (the last one wins)
  /// Lines of other message types skipped, per type (e.g. {"NEFF", 910}).
  std::map<std::string, std::size_t> skipped;
  std::size_t comments = 0;                  ///< `#` lines
  std::vector<std::size_t> malformed_lines;  ///< 1-based lines skipped with skip_malformed
};

/// \brief FLASER's beam geometry for n readings over its 180 degree field of view: beam i at
/// angle_min + i angle_increment with angle_min = -pi/2 and, for odd n (181, 361), the beams
/// spanning -pi/2..+pi/2 exactly (increment pi / (n - 1)) or, for even n (180, 360), the step
/// still 1 (0.5) degree, pi / n, so the last beam is at +89 (+89.5) degrees.
/// \param n the number of readings (>= 2).
/// \param scan receives angle_min and angle_increment (angles is cleared).
void set_flaser_geometry(std::size_t n, LaserScan& scan);

/// \brief Loads a CARMEN log, plain text or gzip (told apart by the gzip magic bytes).
///
/// A line is malformed when its field count is not the one the message's own counts imply, when
/// a field that must be a number is not one (ranges and remissions may be nan/inf; poses,
/// timestamps, velocities and parameters of the scan must be finite), or when a count is not a
/// non-negative integer (FLASER needs n >= 2).
/// \param path the log file.
/// \param options the no-return threshold and what to do with malformed lines.
/// \throws IoError when the file cannot be read.
/// \throws FormatError (`file:line: what was expected`, e.g. `intel.log:171: FLASER: expected
///         189 fields after n = 180 (...), found 12`) for the first malformed line unless
///         options.skip_malformed, and (line 0) for corrupt gzip data.
/// \throws ConfigError when options.max_range or options.range_min is not finite, or
///         range_min < 0 or range_min >= max_range.
[[nodiscard]] CarmenLog load_carmen_log(const std::string& path,
                                        const CarmenLogOptions& options = {});

/// \brief The range from which a log's readings are no-return codes, found in the readings
/// themselves: a scanner writes "no return" as one value just past its reach (81.83 in the
/// Intel lab log, 81.91 or 32.76 in others; 51.05-51.16 in MIT Killian Court), so the log's
/// largest readings pile up within 0.25 m of its maximum, at least 20 of them and ten times as
/// dense as in the metre below. Real far readings thin out towards the maximum instead.
/// \return the lower edge of that pile (its smallest reading less 1 cm), or +inf when there is
/// none (the scans' own range_max then decides).
[[nodiscard]] double detect_no_return_range(const CarmenLog& log);

/// \brief Writes a CARMEN log in plain text: PARAM lines (timestamps 0), then FLASER and ODOM
/// lines merged in order of time (an ODOM before a laser of equal time). Every number is written
/// in the shortest form that reads back as the same double (nan and inf as `nan`, `inf`).
///
/// load_carmen_log() reads the result back with the same times, hostnames, poses, odometry and
/// ranges, bit for bit; remissions are not written (FLASER has none), and the scans' range
/// limits come from the reader's options. An empty hostname is written as `vdtnav`.
/// \throws ConfigError when a scan cannot be written as FLASER (explicit angles, a mount other
///         than zero, fewer than 2 readings, or a geometry other than set_flaser_geometry()'s
///         within 1e-9 rad), a hostname or parameter name is not one token (no spaces), or a
///         parameter value is empty or not tokens separated by single spaces.
/// \throws IoError when the file cannot be written.
void save_carmen_log(const std::string& path, const CarmenLog& log);

}  // namespace vdtnav
