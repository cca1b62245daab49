#pragma once
// Running the `vdtnav` binary as a user does (the path comes from the build: VDTNAV_CLI) and
// reading what it wrote, for the command-line tests.
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace vdtnav::test {

/// Runs `vdtnav ARGS` with stdout and stderr into `output`. \return its exit status (0 done,
/// 1 bad input, 2 bad usage, 3 nothing localized), or -1 when it did not exit (a signal).
inline int run_cli(const std::string& args, const std::filesystem::path& output) {
  const int status = std::system(
      (std::string(VDTNAV_CLI) + " " + args + " > " + output.string() + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The files in `dir` (names), sorted: what a run left behind.
inline std::vector<std::string> files_in(const std::filesystem::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
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
