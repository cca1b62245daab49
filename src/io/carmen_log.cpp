#include "vdtnav/io/carmen_log.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "text_fields.hpp"

namespace vdtnav {
namespace {

// ---------------------------------------------------------------- reading the file

/// The whole file as bytes, gunzipped when it starts with the gzip magic 1f 8b.
std::string read_text(const std::string& path) {
  // A directory opens, and reading it throws std::ios_base::failure (found in load_ros_map).
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw IoError(path + ": is a directory, expected a CARMEN log");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open CARMEN log: " + std::strerror(errno));
  std::string bytes;
  try {
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::ios_base::failure& e) {
    throw IoError(path + ": cannot read CARMEN log: " + e.what());
  }
  if (in.bad()) throw IoError(path + ": cannot read CARMEN log");
  if (bytes.size() < 2 || static_cast<unsigned char>(bytes[0]) != 0x1f ||
      static_cast<unsigned char>(bytes[1]) != 0x8b) {
    return bytes;
  }
  // gzip: inflate with zlib (windowBits 16 + MAX_WBITS: the gzip wrapper), member after member
  // as gunzip does for concatenated .gz files.
  if (bytes.size() > std::numeric_limits<uInt>::max()) {
    throw IoError(path + ": gzip file too large (4 GiB or more)");
  }
  z_stream z{};
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) throw IoError(path + ": zlib initialisation");
  z.next_in = reinterpret_cast<Bytef*>(bytes.data());
  z.avail_in = static_cast<uInt>(bytes.size());
  std::string text;
  std::array<char, 1 << 16> chunk{};
  for (;;) {
    z.next_out = reinterpret_cast<Bytef*>(chunk.data());
    z.avail_out = static_cast<uInt>(chunk.size());
    const int rc = inflate(&z, Z_NO_FLUSH);
    text.append(chunk.data(), chunk.size() - z.avail_out);
    if (rc == Z_STREAM_END) {
      if (z.avail_in == 0) break;
      inflateReset(&z);  // a further member
    } else if (rc != Z_OK) {
      // Z_BUF_ERROR with an empty output chunk: the input ended inside a member.
      const std::string what = rc == Z_BUF_ERROR
                                   ? "truncated gzip data: expected the end of the compressed "
                                     "stream"
                                   : std::string("corrupt gzip data (zlib: ") +
                                         (z.msg != nullptr ? z.msg : "error") + ")";
      inflateEnd(&z);
      throw FormatError(path, 0, what);
    }
  }
  inflateEnd(&z);
  return text;
}

// ---------------------------------------------------------------- fields

using Fields = std::vector<std::string_view>;

/// Thrown inside the parser for a malformed line; turned into FormatError or a count.
struct Malformed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

using io_text::parse_double;
using io_text::split_fields;

/// Reads the fields of one message in order, naming each in the error it throws.
class FieldReader {
 public:
  FieldReader(const char* type, const Fields& f) : type_(type), f_(f) {}

  void seek(std::size_t k) { next_ = k; }

  double any_number(const std::string& name) {
    double v = 0.0;
    if (!parse_double(f_[next_], v)) fail(name, "a number");
    ++next_;
    return v;
  }
  /// Reading i (0-based) of n: any number, nan and inf included (the name is built only on error).
  double reading(const char* what, std::size_t i, std::size_t n) {
    double v = 0.0;
    if (!parse_double(f_[next_], v)) {
      fail(std::string(what) + " " + std::to_string(i + 1) + " of " + std::to_string(n),
           "a number");
    }
    ++next_;
    return v;
  }
  double number(const std::string& name) {
    double v = 0.0;
    if (!parse_double(f_[next_], v) || !std::isfinite(v)) fail(name, "a finite number");
    ++next_;
    return v;
  }
  std::size_t count(const std::string& name, std::size_t min) {
    std::size_t v = 0;
    const std::string_view s = f_[next_];
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || v < min) {
      fail(name, "an integer >= " + std::to_string(min));
    }
    ++next_;
    return v;
  }
  Pose2 pose(const char* x, const char* y, const char* theta) {
    Pose2 p;
    p[0] = number(x);
    p[1] = number(y);
    p[2] = number(theta);
    return p;
  }
  std::string token() { return std::string(f_[next_++]); }

  [[noreturn]] void fail(const std::string& name, const std::string& expected) const {
    throw Malformed(std::string(type_) + ": " + name + ": expected " + expected + ", got '" +
                    std::string(f_[next_]) + "'");
  }

 private:
  const char* type_;
  const Fields& f_;
  std::size_t next_ = 1;
};

/// ipc_timestamp hostname logger_timestamp, the tail of every message.
struct Stamp {
  double ipc_time = 0.0;
  std::string hostname;
  double time = 0.0;
};

Stamp read_stamp(FieldReader& r) {
  Stamp s;
  s.ipc_time = r.number("ipc_timestamp");
  s.hostname = r.token();
  s.time = r.number("logger_timestamp");
  return s;
}

void require_fields(const char* type, const Fields& f, std::size_t expected,
                    const std::string& layout) {
  if (f.size() != expected) {
    throw Malformed(std::string(type) + ": expected " + std::to_string(expected - 1) +
                    " fields after " + type + " (" + layout + "), found " +
                    std::to_string(f.size() - 1));
  }
}

constexpr const char* kFlaserTail =
    "x y theta odom_x odom_y odom_theta ipc_timestamp hostname logger_timestamp";

CarmenLaser parse_flaser(const Fields& f, const CarmenLogOptions& o) {
  if (f.size() < 2) {
    throw Malformed("FLASER: expected the number of readings n after FLASER, found nothing");
  }
  FieldReader r("FLASER", f);
  const std::size_t n = r.count("n (number of readings)", 2);
  if (f.size() - 2 != n + 9) {
    throw Malformed("FLASER: expected " + std::to_string(n + 9) +
                    " fields after n = " + std::to_string(n) + " (" + std::to_string(n) +
                    " ranges, " + kFlaserTail + "), found " + std::to_string(f.size() - 2));
  }
  CarmenLaser laser;
  laser.scan.ranges.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    laser.scan.ranges[i] = r.reading("range", i, n);
  }
  laser.pose = r.pose("x", "y", "theta");
  laser.odom = r.pose("odom_x", "odom_y", "odom_theta");
  const Stamp s = read_stamp(r);
  laser.time = s.time;
  laser.ipc_time = s.ipc_time;
  laser.hostname = s.hostname;
  set_flaser_geometry(n, laser.scan);
  laser.scan.time = laser.time;
  laser.scan.range_min = o.range_min;
  laser.scan.range_max = o.max_range;
  return laser;
}

CarmenLaser parse_robotlaser1(const Fields& f, const CarmenLogOptions& o) {
  constexpr const char* kHead =
      "laser_type start_angle fov angular_res max_range accuracy remission_mode num_readings";
  constexpr const char* kTail =
      "laser_x laser_y laser_theta robot_x robot_y robot_theta laser_tv laser_rv "
      "forward_safety_dist side_safety_dist turn_axis ipc_timestamp hostname logger_timestamp";
  if (f.size() < 9) {
    throw Malformed("ROBOTLASER1: expected " + std::string(kHead) + " after ROBOTLASER1, found " +
                    std::to_string(f.size() - 1) + " fields");
  }
  FieldReader r("ROBOTLASER1", f);
  (void)r.number("laser_type");
  CarmenLaser laser;
  laser.scan.angle_min = r.number("start_angle");
  (void)r.number("fov");
  laser.scan.angle_increment = r.number("angular_res");
  const double max_range = r.any_number("max_range");
  (void)r.number("accuracy");
  (void)r.number("remission_mode");
  const std::size_t n = r.count("num_readings", 0);
  // n ranges, num_remissions, m remissions, 14 tail fields.
  if (f.size() < 9 + n + 1) {
    throw Malformed("ROBOTLASER1: expected " + std::to_string(n) +
                    " ranges and num_remissions after num_readings = " + std::to_string(n) +
                    ", found " + std::to_string(f.size() - 9) + " fields");
  }
  laser.scan.ranges.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    laser.scan.ranges[i] = r.reading("range", i, n);
  }
  const std::size_t m = r.count("num_remissions", 0);
  if (f.size() - (10 + n) != m + 14) {
    throw Malformed("ROBOTLASER1: expected " + std::to_string(m + 14) +
                    " fields after num_remissions = " + std::to_string(m) + " (" +
                    std::to_string(m) + " remissions, " + kTail + "), found " +
                    std::to_string(f.size() - (10 + n)));
  }
  laser.remissions.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    laser.remissions[i] = r.reading("remission", i, m);
  }
  laser.pose = r.pose("laser_x", "laser_y", "laser_theta");
  laser.odom = r.pose("robot_x", "robot_y", "robot_theta");
  for (const char* name :
       {"laser_tv", "laser_rv", "forward_safety_dist", "side_safety_dist", "turn_axis"}) {
    (void)r.number(name);
  }
  const Stamp s = read_stamp(r);
  laser.time = s.time;
  laser.ipc_time = s.ipc_time;
  laser.hostname = s.hostname;
  laser.scan.time = laser.time;
  laser.scan.range_min = o.range_min;
  laser.scan.range_max =
      std::isfinite(max_range) && max_range > 0.0 ? std::min(max_range, o.max_range) : o.max_range;
  return laser;
}

CarmenOdometry parse_odom(const Fields& f) {
  require_fields("ODOM", f, 10, "x y theta tv rv accel ipc_timestamp hostname logger_timestamp");
  FieldReader r("ODOM", f);
  CarmenOdometry odom;
  odom.pose = r.pose("x", "y", "theta");
  odom.tv = r.number("tv");
  odom.rv = r.number("rv");
  odom.accel = r.number("accel");
  const Stamp s = read_stamp(r);
  odom.time = s.time;
  odom.ipc_time = s.ipc_time;
  odom.hostname = s.hostname;
  return odom;
}

std::string join(const Fields& f, std::size_t begin, std::size_t end) {
  std::string s;
  for (std::size_t k = begin; k < end; ++k) {
    if (k > begin) s += ' ';
    s += f[k];
  }
  return s;
}

void parse_param(const Fields& f, std::map<std::string, std::string>& params) {
  if (f.size() < 6) {
    throw Malformed(
        "PARAM: expected at least 5 fields after PARAM (name value ipc_timestamp "
        "hostname logger_timestamp), found " +
        std::to_string(f.size() - 1));
  }
  // The value may span several fields: everything between the name and the timestamps.
  FieldReader r("PARAM", f);
  r.seek(f.size() - 3);
  (void)read_stamp(r);
  params[std::string(f[1])] = join(f, 2, f.size() - 3);
}

// ---------------------------------------------------------------- writing

/// Shortest text that reads back as exactly x (nan and inf as such).
void put(std::string& out, double x) {
  if (std::isnan(x)) {
    out += "nan";
    return;
  }
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), x);
  out.append(buf, r.ptr);
}

bool one_token(const std::string& s) {
  return !s.empty() && std::none_of(s.begin(), s.end(), [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
  });
}

std::string host_of(const std::string& hostname, const char* what) {
  if (hostname.empty()) return "vdtnav";
  VDTNAV_CHECK(one_token(hostname), std::string("save_carmen_log: the hostname of ") + what +
                                        " must be one token without spaces, got '" + hostname +
                                        "'");
  return hostname;
}

void put_stamp(std::string& out, double ipc_time, const std::string& host, double time) {
  out += ' ';
  put(out, ipc_time);
  out += ' ';
  out += host;
  out += ' ';
  put(out, time);
  out += '\n';
}

void put_pose(std::string& out, const Pose2& p) {
  for (int k = 0; k < 3; ++k) {
    out += ' ';
    put(out, p[k]);
  }
}

void write_flaser(std::string& out, const CarmenLaser& l, std::size_t index) {
  const LaserScan& s = l.scan;
  const std::size_t n = s.ranges.size();
  const std::string where = "save_carmen_log: laser " + std::to_string(index) + ": ";
  VDTNAV_CHECK(n >= 2, where + "FLASER needs at least 2 readings");
  VDTNAV_CHECK(s.angles.empty(), where + "explicit beam angles cannot be written as FLASER");
  VDTNAV_CHECK(s.mount == Pose2::Zero(), where + "FLASER has no mounting pose; expected zero");
  LaserScan expected;
  set_flaser_geometry(n, expected);
  VDTNAV_CHECK(std::abs(s.angle_min - expected.angle_min) <= 1e-9 &&
                   std::abs(s.angle_increment - expected.angle_increment) <= 1e-9,
               where + "the beam geometry is not FLASER's for " + std::to_string(n) +
                   " readings (180 degrees from -90)");
  out += "FLASER ";
  out += std::to_string(n);
  for (const double r : s.ranges) {
    out += ' ';
    put(out, r);
  }
  put_pose(out, l.pose);
  put_pose(out, l.odom);
  put_stamp(out, l.ipc_time, host_of(l.hostname, "a laser"), l.time);
}

void write_odom(std::string& out, const CarmenOdometry& o) {
  out += "ODOM";
  put_pose(out, o.pose);
  for (const double v : {o.tv, o.rv, o.accel}) {
    out += ' ';
    put(out, v);
  }
  put_stamp(out, o.ipc_time, host_of(o.hostname, "an odometry message"), o.time);
}

void check_options(const CarmenLogOptions& o) {
  VDTNAV_CHECK(std::isfinite(o.max_range) && std::isfinite(o.range_min) && o.range_min >= 0.0 &&
                   o.range_min < o.max_range,
               "CarmenLogOptions: expected finite 0 <= range_min < max_range");
}

}  // namespace

void set_flaser_geometry(std::size_t n, LaserScan& scan) {
  VDTNAV_CHECK(n >= 2, "set_flaser_geometry: expected at least 2 readings");
  scan.angles.clear();
  scan.angle_min = -kPi / 2.0;
  // Odd n: both ends of the 180 degrees are beams; even n: 1 deg (0.5 deg) steps from -90 deg.
  scan.angle_increment =
      n % 2 == 1 ? kPi / static_cast<double>(n - 1) : kPi / static_cast<double>(n);
}

CarmenLog load_carmen_log(const std::string& path, const CarmenLogOptions& options) {
  check_options(options);
  const std::string text = read_text(path);
  CarmenLog log;
  Fields f;
  std::size_t line_no = 0;
  for (std::size_t begin = 0; begin < text.size();) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + begin, end - begin);
    begin = end + 1;
    ++line_no;
    split_fields(line, f);
    if (f.empty()) continue;
    if (f[0].front() == '#') {
      ++log.comments;
      continue;
    }
    try {
      if (f[0] == "FLASER") {
        log.lasers.push_back(parse_flaser(f, options));
        log.lasers.back().line = line_no;
      } else if (f[0] == "ROBOTLASER1") {
        log.lasers.push_back(parse_robotlaser1(f, options));
        log.lasers.back().line = line_no;
      } else if (f[0] == "ODOM") {
        log.odometry.push_back(parse_odom(f));
        log.odometry.back().line = line_no;
      } else if (f[0] == "PARAM") {
        parse_param(f, log.params);
      } else {
        ++log.skipped[std::string(f[0])];
      }
    } catch (const Malformed& e) {
      if (!options.skip_malformed) throw FormatError(path, line_no, e.what());
      log.malformed_lines.push_back(line_no);
    }
  }
  return log;
}

void save_carmen_log(const std::string& path, const CarmenLog& log) {
  std::string out;
  for (const auto& [name, value] : log.params) {
    Fields f;
    split_fields(value, f);
    VDTNAV_CHECK(one_token(name) && !f.empty() && join(f, 0, f.size()) == value,
                 "save_carmen_log: parameter '" + name +
                     "': expected a name without spaces and a non-empty value of single-space "
                     "separated tokens");
    out += "PARAM " + name + ' ' + value + " 0 vdtnav 0\n";
  }
  // Merge by time; stable, ODOM first on ties (the odometry a scan was taken at comes first).
  std::size_t i = 0, j = 0;
  while (i < log.lasers.size() || j < log.odometry.size()) {
    if (j < log.odometry.size() &&
        (i == log.lasers.size() || !(log.lasers[i].time < log.odometry[j].time))) {
      write_odom(out, log.odometry[j++]);
    } else {
      write_flaser(out, log.lasers[i], i);
      ++i;
    }
  }
  io_text::write_text_file(path, out);
}

double detect_no_return_range(const CarmenLog& log) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kBand = 0.25;  // metres: the pile's width
  double top = -kInf;
  for (const CarmenLaser& l : log.lasers) {
    for (double r : l.scan.ranges) {
      if (std::isfinite(r) && r > 0.0) top = std::max(top, r);
    }
  }
  if (!std::isfinite(top)) return kInf;
  std::size_t pile = 0, below = 0;  // in [top - band, top], and in the metre below that
  double lowest = top;
  for (const CarmenLaser& l : log.lasers) {
    for (double r : l.scan.ranges) {
      if (!std::isfinite(r) || r <= 0.0) continue;
      if (r >= top - kBand) {
        ++pile;
        lowest = std::min(lowest, r);
      } else if (r >= top - kBand - 1.0) {
        ++below;
      }
    }
  }
  // Ten times as dense as below: the metre holds four bands.
  const double density_below = static_cast<double>(below) * kBand / 1.0;
  if (pile < 20 || static_cast<double>(pile) < 10.0 * std::max(1.0, density_below)) return kInf;
  return lowest - 0.01;
}

}  // namespace vdtnav
