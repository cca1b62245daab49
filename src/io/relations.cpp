#include "vdtnav/io/relations.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string_view>
#include <system_error>

namespace vdtnav {
namespace {

constexpr double kPlanarTolerance = 1e-9;
constexpr std::size_t kFields = 8;
constexpr std::array<const char*, kFields> kNames = {"t1", "t2",   "x",     "y",
                                                     "z",  "roll", "pitch", "yaw"};

/// Splits on spaces and tabs (a trailing '\r' counts as space); at most max + 1 fields.
std::size_t split(std::string_view line, std::array<std::string_view, kFields + 1>& out) {
  std::size_t n = 0, i = 0;
  while (i < line.size() && n < out.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out[n++] = line.substr(start, i - start);
  }
  return n;
}

bool parse_double(std::string_view s, double& v) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

/// \return an empty string and the relation, or what was expected.
std::string parse_line(std::string_view line, Relation& rel) {
  std::array<std::string_view, kFields + 1> f;
  const std::size_t n = split(line, f);
  if (n != kFields) {
    return "expected 8 fields (t1 t2 x y z roll pitch yaw), found " +
           (n > kFields ? std::string("more than 8") : std::to_string(n));
  }
  std::array<double, kFields> v{};
  for (std::size_t k = 0; k < kFields; ++k) {
    if (!parse_double(f[k], v[k]) || !std::isfinite(v[k])) {
      return std::string(kNames[k]) + ": expected a finite number, got '" + std::string(f[k]) + "'";
    }
  }
  for (std::size_t k = 4; k < 7; ++k) {
    if (std::abs(v[k]) > kPlanarTolerance) {
      return std::string(kNames[k]) +
             ": expected 0 (a planar relation: z, roll and pitch 0 within 1e-9), got '" +
             std::string(f[k]) + "'";
    }
  }
  rel.t1 = v[0];
  rel.t2 = v[1];
  rel.delta = Pose2(v[2], v[3], v[7]);
  return {};
}

/// Shortest fixed-point text that reads back as exactly x.
void put(std::string& out, double x) {
  char buf[400];  // fixed notation of the largest double needs 309 digits
  const auto r = std::to_chars(buf, buf + sizeof(buf), x, std::chars_format::fixed);
  out.append(buf, r.ptr);
}

}  // namespace

RelationsFile load_relations(const std::string& path, const RelationsOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open relations: " + std::strerror(errno));
  RelationsFile file;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    Relation rel;
    const std::string error = parse_line(line, rel);
    if (error.empty()) {
      file.relations.push_back(rel);
    } else if (options.skip_malformed) {
      file.malformed_lines.push_back(line_no);
    } else {
      throw FormatError(path, line_no, error);
    }
  }
  if (in.bad()) throw IoError(path + ": cannot read relations");
  return file;
}

void save_relations(const std::string& path, const std::vector<Relation>& relations) {
  std::string out;
  for (std::size_t k = 0; k < relations.size(); ++k) {
    const Relation& r = relations[k];
    VDTNAV_CHECK(std::isfinite(r.t1) && std::isfinite(r.t2) && r.delta.allFinite(),
                 "save_relations: relation " + std::to_string(k) + " has a non-finite value");
    put(out, r.t1);
    out += ' ';
    put(out, r.t2);
    out += ' ';
    put(out, r.delta[0]);
    out += ' ';
    put(out, r.delta[1]);
    out += " 0 0 0 ";
    put(out, r.delta[2]);
    out += '\n';
  }
  std::ofstream file(path, std::ios::binary);
  if (!file) throw IoError(path + ": cannot open for writing: " + std::strerror(errno));
  file.write(out.data(), static_cast<std::streamsize>(out.size()));
  if (!file.flush()) throw IoError(path + ": write failed");
}

}  // namespace vdtnav
