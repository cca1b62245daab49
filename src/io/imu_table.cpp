#include "vdtnav/io/imu_table.hpp"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string_view>

#include "text_fields.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

constexpr std::size_t kImuColumns = 7;
constexpr std::array<std::string_view, kImuColumns> kImuNames = {"t",  "wx", "wy", "wz",
                                                                 "ax", "ay", "az"};
constexpr const char* kImuExpected = "expected 7 numbers t,wx,wy,wz,ax,ay,az";

std::string_view imu_trim(std::string_view s) {
  const std::size_t first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

/// Splits on commas and trims each field; false unless there are exactly kImuColumns.
bool split_imu_csv(std::string_view line, std::array<std::string_view, kImuColumns>& fields) {
  std::size_t n = 0;
  for (;;) {
    const std::size_t comma = line.find(',');
    if (n == kImuColumns) return false;
    fields[n++] = imu_trim(line.substr(0, comma));
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
  return n == kImuColumns;
}

}  // namespace

std::vector<ImuSample> load_imu_csv(const std::string& path, ImuCsvReport* report) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open IMU CSV: " + std::strerror(errno));
  ImuCsvReport local;
  ImuCsvReport& r = report != nullptr ? *report : local;
  r = ImuCsvReport{};
  std::vector<ImuSample> samples;
  std::string line;
  std::size_t line_no = 0;
  bool first_row = true;
  std::array<std::string_view, kImuColumns> f;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string_view text = imu_trim(line);
    if (text.empty() || text[0] == '#') continue;
    const bool split = split_imu_csv(text, f);
    const bool may_be_header = first_row;
    first_row = false;
    if (may_be_header && split && f == kImuNames) {
      r.header = true;
      continue;
    }
    std::array<double, kImuColumns> v{};
    bool numbers = split;
    for (std::size_t k = 0; numbers && k < kImuColumns; ++k)
      numbers = io_text::parse_double(f[k], v[k]);
    if (!numbers) {
      throw FormatError(path, line_no,
                        std::string(kImuExpected) + (may_be_header ? " (or that header)" : "") +
                            ", got '" + std::string(text) + "'");
    }
    bool finite = true;
    for (const double x : v) finite = finite && std::isfinite(x);
    if (!finite) {
      r.non_finite_lines.push_back(line_no);
      continue;
    }
    if (!samples.empty() && !(v[0] > samples.back().t)) {
      std::string previous, now;
      io_text::append_fixed(previous, samples.back().t);
      io_text::append_fixed(now, v[0]);
      throw FormatError(
          path, line_no,
          "expected times strictly increasing: " + now + " s after " + previous + " s");
    }
    samples.push_back({v[0], {v[1], v[2], v[3]}, {v[4], v[5], v[6]}});
  }
  if (in.bad()) throw IoError(path + ": cannot read IMU CSV");
  if (samples.empty()) {
    throw FormatError(path, 0, "expected at least one finite row t,wx,wy,wz,ax,ay,az");
  }
  return samples;
}

void save_imu_csv(const std::string& path, const std::vector<ImuSample>& samples) {
  std::string out = "t,wx,wy,wz,ax,ay,az\n";
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const ImuSample& s = samples[i];
    VDTNAV_CHECK(std::isfinite(s.t) && s.gyro.allFinite() && s.accel.allFinite(),
                 "save_imu_csv: sample " + std::to_string(i) + " is not finite");
    VDTNAV_CHECK(i == 0 || s.t > samples[i - 1].t,
                 "save_imu_csv: sample " + std::to_string(i) + "'s time is not after the previous");
    io_text::append_fixed(out, s.t);
    for (const double x :
         {s.gyro.x(), s.gyro.y(), s.gyro.z(), s.accel.x(), s.accel.y(), s.accel.z()}) {
      out += ',';
      io_text::append_fixed(out, x);
    }
    out += '\n';
  }
  io_text::write_text_file(path, out);
}

}  // namespace vdtnav
