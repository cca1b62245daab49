#pragma once
/// \file
/// \brief A progress bar on stderr for anything that takes longer than a second: redrawn in place
/// on a terminal, a line every 10 % otherwise (logs, CI).

#include <chrono>
#include <cstddef>
#include <string>

namespace vdtnav::tools {

class ProgressBar {
 public:
  /// \param label what is being done ("localizing"); \param total the number of steps.
  ProgressBar(std::string label, std::size_t total, bool quiet = false);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// \brief Marks `done` steps of the total as finished.
  void update(std::size_t done);
  /// \brief Finishes the bar (also done by the destructor).
  void finish();

 private:
  void draw(std::size_t done, bool final);

  std::string label_;
  std::size_t total_;
  bool quiet_;
  bool tty_;
  bool finished_ = false;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace vdtnav::tools
