#include "study_figures.hpp"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "vdtnav/core/error.hpp"

namespace vdtnav::studies {

namespace {

constexpr const char* kMarkIt = "mark it known_short with why and the issue that will close it";

using Table = std::vector<std::map<std::string, std::string>>;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string f;
  while (std::getline(s, f, ',')) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

/// A CSV with a header line, as rows of column -> text.
Table read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open (did the main job run this study?)");
  std::string line;
  if (!std::getline(in, line)) throw FormatError(path, 1, "expected a header line");
  const std::vector<std::string> header = split(line);
  Table t;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    const std::vector<std::string> fields = split(line);
    if (fields.size() != header.size()) {
      throw FormatError(path, static_cast<std::size_t>(n),
                        "expected " + std::to_string(header.size()) + " fields, found " +
                            std::to_string(fields.size()));
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size(); ++i) row[header[i]] = fields[i];
    t.push_back(std::move(row));
  }
  return t;
}

/// "<= v", ">= v", "< v", "> v", "in [a, b]" as [lo, hi] (`strict`: "<" or ">"); false for an
/// unparsed target.
bool interval(const std::string& target, double* lo, double* hi, bool* strict = nullptr) {
  double a = 0.0, b = 0.0;
  bool open = false;
  char op[3] = {0, 0, 0};
  if (std::sscanf(target.c_str(), " in [ %lf , %lf ]", &a, &b) == 2) {
    *lo = a;
    *hi = b;
  } else if (std::sscanf(target.c_str(), " %2[<>=] %lf", op, &a) == 2 &&
             (op[0] == '<' || op[0] == '>') && (op[1] == 0 || op[1] == '=')) {
    *lo = op[0] == '>' ? a : -INFINITY;
    *hi = op[0] == '<' ? a : INFINITY;
    open = op[1] == 0;
  } else {
    return false;
  }
  if (strict != nullptr) *strict = open;
  return true;
}

/// Whether x meets the target (true for an unparsed target).
bool meets(const std::string& target, double x) {
  double lo = 0.0, hi = 0.0;
  bool strict = false;
  if (!interval(target, &lo, &hi, &strict)) return true;
  return strict ? x > lo && x < hi : x >= lo && x <= hi;
}

/// A known shortfall names the issue that will close it ("issue 60").
bool names_an_issue(const std::string& text) {
  for (std::size_t at = text.find("issue "); at != std::string::npos;
       at = text.find("issue ", at + 1)) {
    if (at + 6 < text.size() && std::isdigit(static_cast<unsigned char>(text[at + 6]))) return true;
  }
  return false;
}

}  // namespace

std::vector<FigureCheck> check_study_figures(const std::string& expected_yaml,
                                             const std::string& out_dir,
                                             const std::string& data_dir) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(expected_yaml);
  } catch (const YAML::BadFile&) {
    throw IoError(expected_yaml + ": cannot open");
  } catch (const YAML::Exception& e) {
    throw FormatError(expected_yaml, static_cast<std::size_t>(e.mark.line + 1), e.msg);
  }
  if (!root.IsSequence()) {
    throw FormatError(expected_yaml, 1, "expected a list of figures (- file: ..., column: ...)");
  }
  std::map<std::string, Table> tables;
  std::vector<FigureCheck> out;
  for (const YAML::Node& e : root) {
    const std::size_t line = static_cast<std::size_t>(e.Mark().line + 1);
    if (!e.IsMap() || !e["file"] || !e["column"] || !e["row"] || !e["row"].IsMap()) {
      throw FormatError(expected_yaml, line,
                        "expected file, row (a map of column: value) and column");
    }
    if (!e["value"] && !e["min"] && !e["max"]) {
      throw FormatError(expected_yaml, line, "expected value (with tolerance), min or max");
    }
    FigureCheck c;
    c.file = e["file"].as<std::string>();
    c.column = e["column"].as<std::string>();
    c.target = e["target"] ? e["target"].as<std::string>() : "";
    c.reason = e["reason"] ? e["reason"].as<std::string>() : "";
    c.known_short = e["known_short"] ? e["known_short"].as<std::string>() : "";
    if (!c.known_short.empty() && !names_an_issue(c.known_short)) {
      throw FormatError(expected_yaml, line,
                        "known_short must name the issue that will close it (\"... issue N\")");
    }
    if (!c.known_short.empty() && c.target.empty()) {
      throw FormatError(expected_yaml, line, "known_short without a target to be short of");
    }
    std::map<std::string, std::string> key;
    for (const auto& kv : e["row"]) {
      key[kv.first.as<std::string>()] = kv.second.as<std::string>();
      c.row += (c.row.empty() ? "" : ", ") + kv.first.as<std::string>() + "=" +
               kv.second.as<std::string>();
    }
    const double value = e["value"] ? e["value"].as<double>() : std::nan("");
    const double tolerance = e["tolerance"] ? e["tolerance"].as<double>() : 0.0;
    const double lo = e["min"] ? e["min"].as<double>() : -INFINITY;
    const double hi = e["max"] ? e["max"].as<double>() : INFINITY;
    if (e["seeds"]) {
      if (!e["seeds"].IsSequence() || e["seeds"].size() == 0) {
        throw FormatError(expected_yaml, line, "expected seeds: [the figure on seed 1, 2, ...]");
      }
      for (const YAML::Node& v : e["seeds"]) {
        c.seeds.push_back(v.as<double>());
        c.seeds_met += meets(c.target, c.seeds.back());
      }
      if (c.short_on_seeds() && c.known_short.empty()) {
        throw FormatError(expected_yaml, line,
                          "the target '" + c.target + "' is met on " + std::to_string(c.seeds_met) +
                              " of " + std::to_string(c.seeds.size()) + " seeds: " + kMarkIt);
      }
    }
    if (e["value"] && !meets(c.target, value) && c.known_short.empty()) {
      throw FormatError(expected_yaml, line,
                        "the recorded value is outside its target '" + c.target + "': " + kMarkIt);
    }
    if ((!meets(c.target, lo) || !meets(c.target, hi)) && !c.target.empty() &&
        c.known_short.empty() && !e["value"]) {
      throw FormatError(expected_yaml, line,
                        "min / max admit values outside the target '" + c.target + "': " + kMarkIt);
    }
    if (e["skip_without"]) {
      const std::string input = e["skip_without"].as<std::string>();
      if (!std::filesystem::exists(std::filesystem::path(data_dir) / input)) {
        c.skipped = true;
        c.passed = true;
        c.message = "no " + input + " in " + data_dir;
        out.push_back(c);
        continue;
      }
    }
    const std::string path = (std::filesystem::path(out_dir) / c.file).string();
    try {
      auto it = tables.find(path);
      if (it == tables.end()) it = tables.emplace(path, read_csv(path)).first;
      const std::map<std::string, std::string>* match = nullptr;
      int matches = 0;
      for (const auto& row : it->second) {
        bool all = true;
        for (const auto& [k, v] : key) {
          const auto f = row.find(k);
          all = all && f != row.end() && f->second == v;
        }
        if (all) {
          match = &row;
          ++matches;
        }
      }
      if (matches != 1) {
        c.message = std::to_string(matches) + " rows with " + c.row;
      } else if (match->count(c.column) == 0) {
        c.message = "no column " + c.column;
      } else {
        const std::string& text = match->at(c.column);
        char* end = nullptr;
        c.measured = std::strtod(text.c_str(), &end);
        c.read = end != text.c_str();
        if (!c.read) {
          c.message = "'" + text + "' is not a number";
        } else if (e["value"] && !(std::abs(c.measured - value) <= tolerance)) {
          char m[160];
          std::snprintf(m, sizeof m, "%g is not %g +- %g", c.measured, value, tolerance);
          c.message = m;
        } else if (!(c.measured >= lo && c.measured <= hi)) {
          char m[160];
          std::snprintf(m, sizeof m, "%g is not in [%g, %g]", c.measured, lo, hi);
          c.message = m;
        } else if (!meets(c.target, c.measured) && c.known_short.empty()) {
          char m[200];
          std::snprintf(m, sizeof m, "%g is outside its target %s (not marked known_short)",
                        c.measured, c.target.c_str());
          c.message = m;
        } else {
          c.passed = true;
        }
        c.within_target = meets(c.target, c.measured);
        c.distance = distance_to_target(c.target, c.measured);
      }
    } catch (const Error& err) {
      c.message = err.what();
    }
    out.push_back(c);
  }
  return out;
}

double distance_to_target(const std::string& target, double x) {
  double lo = 0.0, hi = 0.0;
  if (meets(target, x) || !interval(target, &lo, &hi)) return 0.0;
  return x < lo ? lo - x : x - hi;
}

std::string report(const std::vector<FigureCheck>& checks) {
  std::string out;
  char line[512];
  int failed = 0, skipped = 0;
  for (const auto& c : checks) {
    // A known shortfall passes, but reads as one: "short", not "ok".
    const char* verdict = c.skipped                       ? "skip "
                          : !c.passed                     ? "FAIL "
                          : c.read && c.short_of_target() ? "short"
                                                          : "ok   ";
    std::snprintf(line, sizeof line, "%s %-38s %-40s %-24s", verdict, c.file.c_str(), c.row.c_str(),
                  c.column.c_str());
    out += line;
    if (!c.skipped && c.message.empty()) {
      std::snprintf(line, sizeof line, " %-12.6g", c.measured);
      out += line;
    }
    if (!c.target.empty()) out += " target " + c.target;
    if (!c.message.empty()) out += " (" + c.message + ")";
    if (c.passed && !c.skipped && !c.known_short.empty() && c.read && !c.short_of_target())
      out += " [marked known_short, meets its target now: the mark can go]";
    out += "\n";
    failed += !c.passed;
    skipped += c.skipped;
  }
  int shorts = 0;
  for (const auto& c : checks) {
    if (c.skipped || !c.read || !c.short_of_target() || c.known_short.empty()) continue;
    if (shorts++ == 0)
      out += "\nKnown shortfalls (measured, target, distance: why, and the issue closing it):\n";
    if (c.within_target) {  // met on this run, not on enough seeds
      std::snprintf(line, sizeof line,
                    "- %s [%s] %s: %.6g, target %s, met on %d of %zu seeds: ", c.file.c_str(),
                    c.row.c_str(), c.column.c_str(), c.measured, c.target.c_str(), c.seeds_met,
                    c.seeds.size());
    } else {
      std::snprintf(line, sizeof line,
                    "- %s [%s] %s: %.6g, target %s, short by %.4g: ", c.file.c_str(), c.row.c_str(),
                    c.column.c_str(), c.measured, c.target.c_str(), c.distance);
    }
    out += line + c.known_short + "\n";
  }
  std::snprintf(line, sizeof line,
                "%zu figures: %zu pass (%d of them known short of their target), %d skipped (no "
                "data), %d failed\n",
                checks.size(), checks.size() - failed - skipped, shorts, skipped, failed);
  return out + line;
}

std::string seeds_table(const std::string& expected_yaml, const std::vector<std::string>& out_dirs,
                        const std::vector<std::string>& labels, const std::string& data_dir) {
  std::vector<std::vector<FigureCheck>> runs;
  for (const std::string& d : out_dirs)
    runs.push_back(check_study_figures(expected_yaml, d, data_dir));
  std::ostringstream md;
  md << "| study | row | figure | target |";
  for (std::size_t r = 0; r < runs.size(); ++r)
    md << ' ' << (r < labels.size() ? labels[r] : out_dirs[r]) << " |";
  md << " meets the target |\n|---|---|---|---|";
  for (std::size_t r = 0; r < runs.size(); ++r) md << "---|";
  md << "---|\n";
  const std::size_t figures = runs.empty() ? 0 : runs.front().size();
  for (std::size_t f = 0; f < figures; ++f) {
    const FigureCheck& first = runs.front()[f];
    int read = 0, met = 0;
    for (const auto& run : runs) {
      read += run[f].read;
      met += run[f].read && run[f].within_target;
    }
    if (first.target.empty() || read == 0) continue;
    const std::string study = first.file.substr(0, first.file.find('/'));
    md << "| " << study << " | " << first.row << " | " << first.column << " | " << first.target
       << " |";
    for (const auto& run : runs) {
      char v[32] = "—";
      if (run[f].read) std::snprintf(v, sizeof v, "%.4g", run[f].measured);
      md << ' ' << v << " |";
    }
    md << ' ' << met << '/' << read << " |\n";
  }
  return md.str();
}

}  // namespace vdtnav::studies
