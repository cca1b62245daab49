#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace vdtnav::tools {

ProgressBar::ProgressBar(std::string label, std::size_t total, bool quiet)
    : label_(std::move(label)),
      total_(std::max<std::size_t>(total, 1)),
      quiet_(quiet),
      tty_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(std::size_t done) {
  if (quiet_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (tty_) {
    if (now - last_draw_ < std::chrono::milliseconds(100) && done < total_) return;
    last_draw_ = now;
    draw(done, false);
  } else {
    const int decile = static_cast<int>(10 * std::min(done, total_) / total_);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    draw(done, false);
  }
}

void ProgressBar::finish() {
  if (quiet_ || finished_) return;
  finished_ = true;
  draw(total_, true);
}

void ProgressBar::draw(std::size_t done, bool final) {
  done = std::min(done, total_);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction = static_cast<double>(done) / static_cast<double>(total_);
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(kWidth, '.');
  const double eta = done > 0 ? seconds * (1.0 - fraction) / fraction : 0.0;
  if (tty_) {
    std::fprintf(stderr, "\r%s [%s] %zu/%zu %5.1f s%s", label_.c_str(), bar.c_str(), done, total_,
                 final ? seconds : eta, final ? "    \n" : " left");
  } else if (final || done < total_) {
    std::fprintf(stderr, "%s [%s] %zu/%zu %.1f s\n", label_.c_str(), bar.c_str(), done, total_,
                 seconds);
  }
  std::fflush(stderr);
}

}  // namespace vdtnav::tools
