// The settings file's reader: YAML text over defaults, every key through the visitors of
// localizer_config_keys.hpp, every mistake an error naming file, line and key path.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "localizer_config_schema.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_config.hpp"

namespace vdtnav {
namespace {

using namespace config_keys;  // NOLINT(google-build-using-namespace): the schema's names

class Reader {
 public:
  Reader(const YAML::Node& node, std::string source, std::string path)
      : node_(node), source_(std::move(source)), path_(std::move(path)) {
    if (!node_.IsMap()) fail(node_, "expected a mapping of keys");
  }

  void number(const char* key, double& x, const char*, const char*) {
    const YAML::Node n = take(key);
    if (!n) return;
    double v = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v))
      fail(n, std::string("expected a finite number, got '") + text(n) + "'", key);
    x = v;
  }
  /// As number(), also NaN (`.nan`): a key whose NaN means "not given" (the writer's `.nan`).
  void number_or_nan(const char* key, double& x, const char*, const char*) {
    const YAML::Node n = take(key);
    if (!n) return;
    double v = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || std::isinf(v))
      fail(n, std::string("expected a finite number or .nan, got '") + text(n) + "'", key);
    x = v;
  }
  void integer(const char* key, int& x, const char*, const char*) {
    long long v = 0;
    if (read_integer(key, &v, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()))
      x = static_cast<int>(v);
  }
  void size(const char* key, std::size_t& x, const char*, const char*) {
    long long v = 0;
    if (read_integer(key, &v, 0, std::numeric_limits<int>::max())) x = static_cast<std::size_t>(v);
  }
  void uint32(const char* key, std::uint32_t& x, const char*, const char*) {
    long long v = 0;
    if (read_integer(key, &v, 0, std::numeric_limits<std::uint32_t>::max()))
      x = static_cast<std::uint32_t>(v);
  }
  void flag(const char* key, bool& x, const char*) {
    const YAML::Node n = take(key);
    if (!n) return;
    bool v = false;
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v))
      fail(n, std::string("expected true or false, got '") + text(n) + "'", key);
    x = v;
  }
  template <typename E>
  void choice(const char* key, E& x, const Names<E>& names, const char*) {
    const YAML::Node n = take(key);
    if (!n) return;
    const std::string s = n.IsScalar() ? n.Scalar() : "";
    std::string known;
    for (const auto& [name, value] : names) {
      if (s == name) {
        x = value;
        return;
      }
      known += (known.empty() ? "" : ", ") + std::string(name);
    }
    fail(n, "expected one of " + known + ", got '" + text(n) + "'", key);
  }
  template <typename F>
  void section(const char* key, const char*, F body) {
    const YAML::Node n = take(key);
    if (!n) return;
    Reader sub(n, source_, path_ + "." + key);
    body(sub);
    sub.check_unknown();
  }

  void sensor(const char* key, const char* doc, VdtSensorModelOptions& o) {
    section(key, doc, [&](Reader& s) { visit(s, o); });
  }

  /// Any key of this mapping that no visit() named is a typo or a key of another version.
  void check_unknown() const {
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      // Fuzzing found a key that is itself a mapping or a list: as<string> threw past every
      // catch of vdtnav::Error.
      if (!it->first.IsScalar()) fail(it->first, "expected a key name (a plain word)");
      const std::string key = it->first.as<std::string>();
      if (used_.count(key) == 0) {
        std::string known;
        for (const std::string& k : known_) known += (known.empty() ? "" : ", ") + k;
        fail(it->first, "unknown key (known: " + known + ")", key);
      }
    }
  }

 private:
  YAML::Node take(const char* key) {
    known_.emplace_back(key);
    used_.insert(key);
    const YAML::Node& map = node_;  // const: a missing key is not inserted
    const YAML::Node n = map[key];
    if (n && n.IsNull()) fail(n, "expected a value", key);
    return n;
  }
  bool read_integer(const char* key, long long* out, long long lo, long long hi) {
    const YAML::Node n = take(key);
    if (!n) return false;
    long long v = 0;
    if (!n.IsScalar() || !YAML::convert<long long>::decode(n, v) || v < lo || v > hi)
      fail(n,
           std::string("expected an integer in [") + std::to_string(lo) + ", " +
               std::to_string(hi) + "], got '" + text(n) + "'",
           key);
    *out = v;
    return true;
  }
  static std::string text(const YAML::Node& n) {
    if (n.IsScalar()) return n.Scalar();
    return n.IsMap() ? "a mapping" : n.IsSequence() ? "a sequence" : "nothing";
  }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what,
                         const std::string& key = "") const {
    const int line = n.Mark().line >= 0 ? n.Mark().line + 1 : 0;
    throw ConfigError(source_ + ":" + std::to_string(line) + ": " + path_ +
                      (key.empty() ? "" : "." + key) + ": " + what);
  }

  YAML::Node node_;
  std::string source_;
  std::string path_;
  std::vector<std::string> known_;
  std::set<std::string> used_;
};

}  // namespace

LocalizerSettings parse_localizer_config(const std::string& text, const std::string& source,
                                         const LocalizerSettings& defaults) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(source + ":" + std::to_string(e.mark.line + 1) +
                      ": malformed YAML: " + e.msg);
  }
  LocalizerSettings s = defaults;
  if (!root || root.IsNull()) return s;  // an empty file: the defaults
  if (!root.IsMap()) {
    throw ConfigError(source + ":" + std::to_string(root.Mark().line + 1) +
                      ": expected a mapping of sections (" + section_list() + ")");
  }
  for (auto it = root.begin(); it != root.end(); ++it) {
    if (!it->first.IsScalar()) {
      throw ConfigError(source + ":" + std::to_string(it->first.Mark().line + 1) +
                        ": expected a section name (a plain word), not a mapping or a list");
    }
    const std::string name = it->first.as<std::string>();
    if (name == kThreads) {
      long long v = 0;
      if (!it->second.IsScalar() || !YAML::convert<long long>::decode(it->second, v) || v < 0 ||
          v > 4096) {
        throw ConfigError(source + ":" + std::to_string(it->second.Mark().line + 1) + ": " +
                          kThreads +
                          ": expected an integer in [0, 4096] (0: the machine's "
                          "cores), got '" +
                          (it->second.IsScalar() ? it->second.Scalar() : "not a number") + "'");
      }
      s.threads = static_cast<int>(v);
      continue;
    }
    bool known = false;
    for (const std::string& sec : sections()) known = known || sec == name;
    if (!known) {
      throw ConfigError(source + ":" + std::to_string(it->first.Mark().line + 1) +
                        ": unknown section '" + name + "' (known: " + section_list() +
                        "; and the key " + kThreads + ")");
    }
  }
  // The shared sensor: block first, wherever it stands: every 2D VDT method's sensor model gets
  // the keys it names; the methods' own sensor: keys, read next, override them.
  const YAML::Node& map = root;  // const: a missing section is not inserted
  if (const YAML::Node shared = map[kSharedSensor]) {
    for (VdtSensorModelOptions* target : shared_sensor_targets(s)) {
      Reader r(shared, source, kSharedSensor);
      visit(r, *target);
      r.check_unknown();
    }
  }
  for (auto it = root.begin(); it != root.end(); ++it) {
    const std::string name = it->first.as<std::string>();
    if (name == kSharedSensor || name == kThreads) continue;
    Reader r(it->second, source, name);
    visit_section(r, name, s);
    r.check_unknown();
  }
  return s;
}

LocalizerSettings load_localizer_config(const std::string& path,
                                        const LocalizerSettings& defaults) {
  std::ifstream in(path);
  VDTNAV_CHECK(in.good(), "cannot read the settings file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_localizer_config(text.str(), path, defaults);
}

}  // namespace vdtnav
