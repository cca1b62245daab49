#pragma once
// A process a test starts and stops (the nodes' tests: a ROS master, the nodes, bag players):
// in its own process group, its output to a log, stopped by its id (SIGINT, then SIGKILL) and
// reaped when destroyed, so that nothing a test starts outlives it.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

namespace vdtnav::testing {

/// A process in its own process group, output to a log; stopped (SIGINT, then SIGKILL) and
/// reaped when destroyed.
class Child {
 public:
  Child(const std::vector<std::string>& argv, const std::filesystem::path& log) {
    pid_ = ::fork();
    if (pid_ == 0) {
      ::setpgid(0, 0);
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        ::dup2(fd, 1);
        ::dup2(fd, 2);
      }
      std::vector<char*> args;
      for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execvp(args[0], args.data());
      ::_exit(127);
    }
    ::setpgid(pid_, pid_);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child() { stop(); }

  /// \return whether the process exited within `seconds` (its status in *status).
  bool wait_exit(double seconds, int* status = nullptr) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (pid_ > 0) {
      int st = 0;
      const pid_t r = ::waitpid(pid_, &st, WNOHANG);
      if (r == pid_) {
        pid_ = -1;
        if (status != nullptr) *status = st;
        return true;
      }
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }

  void stop() {
    if (pid_ <= 0) return;
    ::kill(-pid_, SIGINT);
    if (!wait_exit(10.0)) {
      ::kill(-pid_, SIGKILL);
      wait_exit(10.0);
    }
  }

 private:
  pid_t pid_ = -1;
};

inline bool on_path(const std::string& tool) {
  return std::system(("command -v " + tool + " > /dev/null 2>&1").c_str()) == 0;
}

}  // namespace vdtnav::testing
