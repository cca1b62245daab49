#pragma once
/// \file
/// \brief The command line a ROS 2 launch file gives a node (ROS 2 design article "ROS command
/// line arguments"; what rcl parses), without rcl: everything after `--ros-args` up to `--` or
/// the end is ROS's,
///   -r / --remap [node:]from:=to      a name remapping (`__node:=amcl`, `__ns:=/robot1` rename
///                                     the node and set its namespace)
///   -p / --param name:=value          a parameter (value in YAML: 1, 0.5, true, text)
///   --params-file FILE                parameters of a YAML file, `node: ros__parameters: ...`
///                                     blocks for this node's name (`amcl`, `/amcl`, `/ns/amcl`)
///                                     or for every node (`/**`); nested keys become dotted names
///   --log-level, -e / --enclave, --disable-*-logs and the like: accepted and ignored;
/// the rest are the program's own. Later arguments win; `-p` over a file named before it.
/// Names resolve as rcl resolves them: `/abs`, `rel` in the namespace, `~/priv` in the node's.

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace vdtnav::ros2 {

/// \brief A node's ROS arguments (see the file comment).
class RosArgs {
 public:
  /// \brief Parses argv (argv[0] is the program) for a node named `default_name`.
  /// \throws ConfigError for a malformed rule or parameter, IoError/FormatError for a params
  /// file that cannot be read (its path and line).
  RosArgs(int argc, const char* const* argv, std::string default_name);

  [[nodiscard]] const std::string& node_name() const noexcept { return name_; }
  /// The namespace, "/" or "/a/b" (no trailing slash).
  [[nodiscard]] const std::string& node_namespace() const noexcept { return namespace_; }
  /// The node's fully qualified name ("/amcl", "/robot1/amcl").
  [[nodiscard]] std::string fully_qualified_name() const;
  /// The arguments that are not ROS's (argv[0] first).
  [[nodiscard]] const std::vector<std::string>& program_args() const noexcept { return rest_; }

  /// \brief A topic or service name as the node uses it, resolved and remapped ("/scan").
  [[nodiscard]] std::string resolve(const std::string& name) const;

  [[nodiscard]] bool has(const std::string& parameter) const;
  /// \brief Typed parameters; the default when the parameter is not given.
  /// \throws ConfigError naming the parameter, its value and where it came from when the value
  /// is not of the type asked.
  [[nodiscard]] double number(const std::string& parameter, double fallback) const;
  [[nodiscard]] bool boolean(const std::string& parameter, bool fallback) const;
  [[nodiscard]] std::string text(const std::string& parameter, const std::string& fallback) const;
  /// \return every parameter given: name -> (value as written, where it came from).
  [[nodiscard]] const std::map<std::string, std::pair<std::string, std::string>>& parameters()
      const noexcept {
    return params_;
  }

 private:
  void read_params_file(const std::string& path);
  [[nodiscard]] std::string expand(const std::string& name) const;

  std::string name_, namespace_ = "/";
  std::vector<std::string> rest_;
  std::vector<std::pair<std::string, std::string>> remaps_;  // expanded from -> expanded to
  std::vector<std::pair<std::string, std::string>> raw_remaps_;
  std::vector<std::string> params_files_;
  std::map<std::string, std::pair<std::string, std::string>> params_;
};

}  // namespace vdtnav::ros2
