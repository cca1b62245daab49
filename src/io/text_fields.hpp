#pragma once
/// \file
/// \brief Private to vdtnav::io: the whitespace-separated text formats (CARMEN logs, relations,
/// TUM trajectories) share their field splitting, number parsing, line loop and file writing
/// (and the binary map files their checksums' hex).

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav::io_text {

/// Splits on spaces and tabs (a '\r' counts as space) into `out`.
inline void split_fields(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

/// Parses a whole field as a double; nan, inf and a leading '+' are accepted.
inline bool parse_double(std::string_view s, double& v) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

/// \brief Splits `line` into exactly N finite numbers named `names` (TUM poses, relations).
/// \return an empty string with `v` and the fields `f`, or what was expected.
template <std::size_t N>
std::string parse_finite_fields(std::string_view line, const std::array<const char*, N>& names,
                                std::vector<std::string_view>& f, std::array<double, N>& v) {
  split_fields(line, f);
  const std::size_t n = f.size();
  if (n != N) {
    std::string listed;
    for (const char* name : names) listed += (listed.empty() ? "" : " ") + std::string(name);
    return "expected " + std::to_string(N) + " fields (" + listed + "), found " +
           (n > N ? "more than " + std::to_string(N) : std::to_string(n));
  }
  for (std::size_t k = 0; k < N; ++k) {
    if (!parse_double(f[k], v[k]) || !std::isfinite(v[k])) {
      return std::string(names[k]) + ": expected a finite number, got '" + std::string(f[k]) + "'";
    }
  }
  return {};
}

/// A 32-bit word as 0x%08x, for the binary formats' checksum messages.
inline std::string hex(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%08x", v);
  return buf;
}

/// Shortest fixed-point text that reads back as exactly x.
inline void append_fixed(std::string& out, double x) {
  char buf[400];  // fixed notation of the largest double needs 309 digits
  const auto r = std::to_chars(buf, buf + sizeof(buf), x, std::chars_format::fixed);
  out.append(buf, r.ptr);
}

/// \brief Parses every line of `path` that is neither blank nor a '#' comment with
/// parse(line, item) -> "" or what was expected; collects the items, and the numbers of the
/// malformed lines when `skip_malformed`.
/// \throws IoError if the file cannot be read, FormatError (file:line: what) for a malformed line.
template <class Item, class Parse>
void read_data_lines(const std::string& path, const char* what, bool skip_malformed, Parse&& parse,
                     std::vector<Item>& items, std::vector<std::size_t>& malformed_lines) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open " + what + ": " + std::strerror(errno));
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    Item item;
    const std::string error = parse(line, item);
    if (error.empty()) {
      items.push_back(std::move(item));
    } else if (skip_malformed) {
      malformed_lines.push_back(line_no);
    } else {
      throw FormatError(path, line_no, error);
    }
  }
  if (in.bad()) throw IoError(path + ": cannot read " + what);
}

/// Writes `text` to `path`. \throws IoError when it cannot.
inline void write_text_file(const std::string& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary);
  if (!file) throw IoError(path + ": cannot open for writing: " + std::strerror(errno));
  file.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!file.flush()) throw IoError(path + ": write failed");
}

}  // namespace vdtnav::io_text
