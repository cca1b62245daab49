#include "vdtnav/point_laser/pan_tilt_csv.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <istream>
#include <string_view>

#include "vdtnav/core/error.hpp"

namespace vdtnav::point_laser {
namespace {

constexpr const char* kExpectedHeader =
    "expected a header naming the columns pan,tilt,range and optionally time";

std::string_view trim(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

/// Parses a whole field as a double (from_chars: also "inf", "-inf", "nan").
bool parse_number(std::string_view s, double& v) {
  s = trim(s);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

std::vector<std::string_view> split(std::string_view text) {
  std::vector<std::string_view> fields;
  for (std::size_t start = 0;;) {
    const std::size_t comma = text.find(',', start);
    fields.push_back(trim(text.substr(start, comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

enum Column : int { kPan = 0, kTilt = 1, kRange = 2, kTime = 3, kNumColumns = 4 };

}  // namespace

PanTiltCsv parse_pan_tilt_csv(std::istream& in, const std::string& name,
                              const PanTiltCsvOptions& options) {
  PanTiltCsv out;
  std::array<int, kNumColumns> field_of{-1, -1, -1, -1};  // column -> field index
  std::size_t num_fields = 0;
  bool have_header = false;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::string_view text = line;
    text = trim(text.substr(0, text.find('#')));
    if (text.empty()) continue;
    const std::vector<std::string_view> fields = split(text);

    if (!have_header) {
      for (std::size_t f = 0; f < fields.size(); ++f) {
        int column = -1;
        if (fields[f] == "pan") column = kPan;
        if (fields[f] == "tilt") column = kTilt;
        if (fields[f] == "range") column = kRange;
        if (fields[f] == "time") column = kTime;
        if (column < 0 || field_of[column] >= 0)
          throw FormatError(
              name, line_no,
              std::string(kExpectedHeader) + " (each once), got '" + std::string(text) + "'");
        field_of[column] = static_cast<int>(f);
      }
      if (field_of[kPan] < 0 || field_of[kTilt] < 0 || field_of[kRange] < 0)
        throw FormatError(name, line_no,
                          std::string(kExpectedHeader) + ", got '" + std::string(text) + "'");
      num_fields = fields.size();
      out.has_time = field_of[kTime] >= 0;
      have_header = true;
      continue;
    }

    std::string problem;
    std::array<double, kNumColumns> value{0.0, 0.0, 0.0, 0.0};
    if (fields.size() != num_fields) {
      problem = "expected " + std::to_string(num_fields) +
                " comma-separated numbers as in the header, got " + std::to_string(fields.size()) +
                " fields in '" + std::string(text) + "'";
    } else {
      for (int c = 0; c < kNumColumns && problem.empty(); ++c) {
        if (field_of[c] < 0) continue;
        const std::string_view field = fields[static_cast<std::size_t>(field_of[c])];
        if (!parse_number(field, value[c])) {
          static constexpr const char* kNames[kNumColumns] = {"pan (radians)", "tilt (radians)",
                                                              "range (metres)", "time (seconds)"};
          problem = std::string("expected a number for ") + kNames[c] + ", got '" +
                    std::string(field) + "' in '" + std::string(text) + "'";
        }
      }
    }
    if (!problem.empty()) {
      if (!options.skip_malformed) throw FormatError(name, line_no, problem);
      ++out.skipped_malformed;
      out.skipped_lines.push_back(line_no);
      continue;
    }
    PanTiltReading reading;
    reading.pan = value[kPan];
    reading.tilt = value[kTilt];
    reading.range = value[kRange];
    reading.time = value[kTime];
    out.readings.push_back(reading);
  }
  if (in.bad()) throw IoError(name + ": read error");
  if (!have_header) throw FormatError(name, 0, std::string(kExpectedHeader) + ", found none");
  return out;
}

PanTiltCsv read_pan_tilt_csv(const std::string& path, const PanTiltCsvOptions& options) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open pan-tilt CSV: " + std::strerror(errno));
  return parse_pan_tilt_csv(in, path, options);
}

void write_pan_tilt_csv(const std::string& path, const std::vector<PanTiltReading>& readings,
                        bool with_time) {
  std::ofstream out(path);
  if (!out) throw IoError(path + ": cannot create pan-tilt CSV: " + std::strerror(errno));
  out << (with_time ? "pan,tilt,range,time\n" : "pan,tilt,range\n");
  char buffer[128];
  for (const PanTiltReading& z : readings) {
    const int n = with_time ? std::snprintf(buffer, sizeof buffer, "%.17g,%.17g,%.17g,%.17g\n",
                                            z.pan, z.tilt, z.range, z.time)
                            : std::snprintf(buffer, sizeof buffer, "%.17g,%.17g,%.17g\n", z.pan,
                                            z.tilt, z.range);
    out.write(buffer, n);
  }
  out.flush();
  if (!out) throw IoError(path + ": write error");
}

}  // namespace vdtnav::point_laser
