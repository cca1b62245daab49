#pragma once
// Running the `vdtnav` binary as a user does (the path comes from the build: VDTNAV_CLI) and
// reading what it wrote, for the command-line tests.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace vdtnav::test {

/// Runs `vdtnav ARGS` with stdout and stderr into `output`. \return std::system's status.
inline int run_cli(const std::string& args, const std::filesystem::path& output) {
  return std::system(
      (std::string(VDTNAV_CLI) + " " + args + " > " + output.string() + " 2>&1").c_str());
}

inline std::string read_all(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline bool contains(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

}  // namespace vdtnav::test
