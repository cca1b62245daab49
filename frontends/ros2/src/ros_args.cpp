// A ROS 2 node's command line without rcl (ros_args.hpp).
#include "vdtnav/ros2/ros_args.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>

#include "vdtnav/core/error.hpp"

namespace vdtnav::ros2 {
namespace {

/// "name:=value" split at ":=".
std::pair<std::string, std::string> split_rule(const std::string& rule, const char* what) {
  const std::size_t at = rule.find(":=");
  if (at == std::string::npos || at == 0) {
    throw ConfigError(std::string("--ros-args ") + what + ": expected name:=value, got '" + rule +
                      "'");
  }
  return {rule.substr(0, at), rule.substr(at + 2)};
}

/// A YAML scalar's text, or a sequence/map in flow style.
std::string scalar_text(const YAML::Node& n) {
  if (n.IsScalar()) return n.Scalar();
  YAML::Emitter e;
  e << YAML::Flow << n;
  return e.c_str();
}

/// Adds the parameters of a ros__parameters block, nested maps as dotted names.
void flatten(const YAML::Node& n, const std::string& prefix, const std::string& source,
             std::map<std::string, std::pair<std::string, std::string>>* out) {
  for (const auto& kv : n) {
    const std::string key = prefix + kv.first.as<std::string>();
    if (kv.second.IsMap()) {
      flatten(kv.second, key + ".", source, out);
    } else {
      (*out)[key] = {scalar_text(kv.second), source};
    }
  }
}

}  // namespace

RosArgs::RosArgs(int argc, const char* const* argv, std::string default_name)
    : name_(std::move(default_name)) {
  // Pass 1: collect in order (parameters need the node's final name to pick file blocks).
  struct Param {
    bool file;
    std::string a, b;
  };
  std::vector<Param> params;
  bool ros = false;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (i == 0) {
      rest_.push_back(a);
      continue;
    }
    if (a == "--ros-args") {
      ros = true;
      continue;
    }
    if (!ros) {
      rest_.push_back(a);
      continue;
    }
    if (a == "--") {
      ros = false;
      continue;
    }
    const auto value = [&](const char* what) -> std::string {
      if (i + 1 >= argc) throw ConfigError(std::string("--ros-args ") + what + ": missing value");
      return argv[++i];
    };
    if (a == "-r" || a == "--remap") {
      raw_remaps_.push_back(split_rule(value("--remap"), "--remap"));
    } else if (a == "-p" || a == "--param") {
      auto [k, v] = split_rule(value("--param"), "--param");
      params.push_back({false, k, v});
    } else if (a == "--params-file") {
      params.push_back({true, value("--params-file"), ""});
    } else if (a == "--log-level" || a == "-e" || a == "--enclave" || a == "--log-config-file" ||
               a == "--log-file-name") {
      (void)value(a.c_str());
    } else if (a.rfind("--enable-", 0) == 0 || a.rfind("--disable-", 0) == 0) {
      // --disable-rosout-logs, --enable-stdout-logs, ...: logging, not ours.
    } else {
      throw ConfigError("--ros-args: unknown argument '" + a +
                        "' (expected -r, -p, --params-file, --log-level, -e)");
    }
  }
  for (const auto& [from, to] : raw_remaps_) {
    if (from == "__node" || from == "__name") name_ = to;
    if (from == "__ns") {
      namespace_ = to.empty() || to.front() != '/' ? "/" + to : to;
      while (namespace_.size() > 1 && namespace_.back() == '/') namespace_.pop_back();
    }
  }
  for (const auto& [from, to] : raw_remaps_) {
    if (from == "__node" || from == "__name" || from == "__ns") continue;
    // "node:from" applies to that node only.
    std::string f = from;
    const std::size_t colon = f.find(':');
    if (colon != std::string::npos) {
      if (f.substr(0, colon) != name_) continue;
      f = f.substr(colon + 1);
    }
    remaps_.emplace_back(expand(f), expand(to));
  }
  // Pass 2: parameters in the order given.
  for (const Param& p : params) {
    if (p.file) {
      read_params_file(p.a);
    } else {
      YAML::Node n;
      try {
        n = YAML::Load(p.b);
      } catch (const YAML::Exception& e) {
        throw ConfigError("--ros-args -p " + p.a + ":=" + p.b + ": expected a YAML value (" +
                          e.msg + ")");
      }
      params_[p.a] = {n.IsNull() ? p.b : scalar_text(n), "-p " + p.a + ":=" + p.b};
    }
  }
}

void RosArgs::read_params_file(const std::string& path) {
  if (!std::filesystem::exists(path)) throw IoError("--params-file " + path + ": no such file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw FormatError(path, e.mark.line + 1, std::string("expected YAML: ") + e.msg);
  }
  if (!root.IsMap()) throw FormatError(path, 1, "expected a map of node names");
  const std::string fq = fully_qualified_name();
  // rcl's order: the wildcard blocks, then the node's own (which win).
  for (int pass = 0; pass < 2; ++pass) {
    for (const auto& kv : root) {
      const std::string key = kv.first.as<std::string>();
      const bool wildcard = key == "/**" || key == "**";
      const bool mine = key == name_ || key == fq || key == "/" + name_;
      if (!(pass == 0 ? wildcard : mine)) continue;
      const YAML::Node block = kv.second["ros__parameters"];
      if (!block) {
        throw FormatError(path, kv.first.Mark().line + 1,
                          "expected '" + key + ": ros__parameters:' (a node's parameters)");
      }
      if (!block.IsMap()) {
        throw FormatError(path, block.Mark().line + 1, "expected a map under ros__parameters");
      }
      flatten(block, "", path, &params_);
    }
  }
}

std::string RosArgs::fully_qualified_name() const {
  return (namespace_ == "/" ? "" : namespace_) + "/" + name_;
}

std::string RosArgs::expand(const std::string& name) const {
  if (name.empty()) throw ConfigError("a ROS name: expected a name, got ''");
  if (name.front() == '/') return name;
  if (name.front() == '~') {
    const std::string rest = name.size() > 1 && name[1] == '/' ? name.substr(2) : name.substr(1);
    return fully_qualified_name() + (rest.empty() ? "" : "/" + rest);
  }
  return (namespace_ == "/" ? "" : namespace_) + "/" + name;
}

std::string RosArgs::resolve(const std::string& name) const {
  const std::string fq = expand(name);
  for (auto it = remaps_.rbegin(); it != remaps_.rend(); ++it) {
    if (it->first == fq) return it->second;
  }
  return fq;
}

bool RosArgs::has(const std::string& parameter) const { return params_.count(parameter) != 0; }

double RosArgs::number(const std::string& parameter, double fallback) const {
  const auto it = params_.find(parameter);
  if (it == params_.end()) return fallback;
  const std::string& v = it->second.first;
  char* end = nullptr;
  errno = 0;
  const double d = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || errno == ERANGE) {
    throw ConfigError("parameter " + parameter + " (" + it->second.second +
                      "): expected a number, got '" + v + "'");
  }
  return d;
}

bool RosArgs::boolean(const std::string& parameter, bool fallback) const {
  const auto it = params_.find(parameter);
  if (it == params_.end()) return fallback;
  const std::string& v = it->second.first;
  // YAML 1.1's booleans, as ROS 2's parameter parser reads them.
  for (const char* t : {"true", "True", "TRUE", "yes", "Yes", "on", "On"}) {
    if (v == t) return true;
  }
  for (const char* f : {"false", "False", "FALSE", "no", "No", "off", "Off"}) {
    if (v == f) return false;
  }
  throw ConfigError("parameter " + parameter + " (" + it->second.second +
                    "): expected true or false, got '" + v + "'");
}

std::string RosArgs::text(const std::string& parameter, const std::string& fallback) const {
  const auto it = params_.find(parameter);
  return it == params_.end() ? fallback : it->second.first;
}

}  // namespace vdtnav::ros2
