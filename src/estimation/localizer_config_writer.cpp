// The settings file's writer: every key with its unit and meaning, through the visitors of
// localizer_config_keys.hpp; what it writes reads back to the same settings.
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "localizer_config_schema.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_config.hpp"

namespace vdtnav {
namespace {

using namespace config_keys;  // NOLINT(google-build-using-namespace): the schema's names

class Writer {
 public:
  /// `shared`: the shared sensor: block, against which sensor() prints only what differs;
  /// nullptr: sensor() prints every key (the shared block itself, localize3d's 3D map).
  Writer(std::ostringstream& out, int indent, const VdtSensorModelOptions* shared)
      : out_(out), indent_(indent), shared_(shared) {}

  void number(const char* key, double& x, const char* unit, const char* doc) {
    std::ostringstream v;
    v << std::setprecision(17) << x;
    // Shortest representation that reads back to the same double.
    for (int p = 1; p <= 17; ++p) {
      std::ostringstream t;
      t << std::setprecision(p) << x;
      if (std::stod(t.str()) == x) {
        v.str(t.str());
        break;
      }
    }
    line(key, v.str(), unit, doc);
  }
  void number_or_nan(const char* key, double& x, const char* unit, const char* doc) {
    if (std::isnan(x)) {
      line(key, ".nan", unit, doc);  // YAML's NaN, which the reader reads back
    } else {
      number(key, x, unit, doc);
    }
  }
  void integer(const char* key, int& x, const char* unit, const char* doc) {
    line(key, std::to_string(x), unit, doc);
  }
  void size(const char* key, std::size_t& x, const char* unit, const char* doc) {
    line(key, std::to_string(x), unit, doc);
  }
  void uint32(const char* key, std::uint32_t& x, const char* unit, const char* doc) {
    line(key, std::to_string(x), unit, doc);
  }
  void flag(const char* key, bool& x, const char* doc) { line(key, x ? "true" : "false", "", doc); }
  template <typename E>
  void choice(const char* key, E& x, const Names<E>& names, const char* doc) {
    for (const auto& [name, value] : names) {
      if (value == x) line(key, name, "", doc);
    }
  }
  template <typename F>
  void section(const char* key, const char* doc, F body) {
    out_ << std::string(static_cast<std::size_t>(indent_), ' ') << key << ":  # " << doc << "\n";
    Writer sub(out_, indent_ + 2, shared_);
    body(sub);
  }
  /// A method's sensor model: the keys whose value differs from the shared block's (the reader
  /// gives the others the shared block's). Each key is one line written the same way for equal
  /// values, so the lines that differ are the keys that do.
  void sensor(const char* key, const char* doc, VdtSensorModelOptions& o) {
    if (shared_ == nullptr) {
      section(key, doc, [&](Writer& s) { visit(s, o); });
      return;
    }
    std::ostringstream mine, theirs;
    Writer a(mine, indent_ + 2, nullptr), b(theirs, indent_ + 2, nullptr);
    VdtSensorModelOptions shared = *shared_;
    visit(a, o);
    visit(b, shared);
    std::istringstream ml(mine.str()), tl(theirs.str());
    std::string m, t, differ;
    while (std::getline(ml, m) && std::getline(tl, t)) {
      if (m != t) differ += m + "\n";
    }
    const std::string pad(static_cast<std::size_t>(indent_), ' ');
    if (differ.empty()) {
      out_ << pad << key << ": {}  # " << doc << ": the shared sensor: block's\n";
    } else {
      out_ << pad << key << ":  # " << doc << ": the shared sensor: block's, except\n" << differ;
    }
  }

 private:
  void line(const char* key, const std::string& value, const char* unit, const char* doc) {
    std::string head = std::string(static_cast<std::size_t>(indent_), ' ') + key + ": " + value;
    if (head.size() < 40) head.resize(40, ' ');
    out_ << head << "  # " << (unit[0] != '\0' ? std::string("[") + unit + "] " : "") << doc
         << "\n";
  }

  std::ostringstream& out_;
  int indent_;
  const VdtSensorModelOptions* shared_;
};

}  // namespace

std::string localizer_config_section(const std::string& method) {
  if (method == "udt-opt" || method == "udt-ekf") return "udt";
  for (const std::string& s : sections()) {
    if (s == method && s != "udt" && s != kSharedSensor) return s;
  }
  std::string known;
  for (const auto& m : localizer_methods()) known += (known.empty() ? "" : ", ") + m;
  throw ConfigError("unknown localization method '" + method + "' (expected one of: " + known +
                    ", or localize3d)");
}

std::string localizer_settings_yaml(const LocalizerSettings& settings, const std::string& method) {
  const std::string only = method.empty() ? "" : localizer_config_section(method);
  LocalizerSettings s = settings;  // the visitors take non-const references
  // The shared block holds vdt-opt's sensor model; each method's sensor: then lists what differs.
  // vdt-opt's own is then never changed by reading back a file printed for another method.
  const VdtSensorModelOptions shared = s.vdt_opt.sensor;
  std::ostringstream out;
  out << "# vdtnav localizer settings: every key, [unit] and meaning (docs/settings.md).\n";
  out << kThreads << ": " << s.threads << "  # " << kThreadsDoc << "\n";
  for (const std::string& sec : sections()) {
    if (only == kLocalize3d) {
      if (sec != kLocalize3d) continue;  // `vdtnav localize3d --print-config`: its section only
    } else if (!only.empty() && sec != only && sec != kSharedSensor && sec != "global" &&
               sec != "recovery") {
      continue;  // the shared block, --init global and recovery: any 2D method
    }
    out << sec << ":  # " << section_doc(sec) << "\n";
    if (sec == kSharedSensor) {
      Writer w(out, 2, nullptr);
      VdtSensorModelOptions keys = shared;
      visit(w, keys);
    } else {
      Writer w(out, 2, sec == kLocalize3d ? nullptr : &shared);
      visit_section(w, sec, s);
    }
  }
  return out.str();
}

}  // namespace vdtnav
