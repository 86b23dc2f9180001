// A one-line progress bar on stderr when it is a terminal; silent otherwise.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace svo::tools {

class ProgressBar {
 public:
  explicit ProgressBar(std::string title) : title_(std::move(title)), enabled_(isatty(STDERR_FILENO)) {}
  ~ProgressBar() { finish(); }

  // Thread-safe; redraws at most 10 times a second.
  void update(const std::string& stage, double fraction) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    auto now = std::chrono::steady_clock::now();
    if (fraction < 1.0 && now - last_ < std::chrono::milliseconds(100) && stage == stage_) return;
    last_ = now;
    stage_ = stage;
    const int width = 30;
    int filled = int(std::clamp(fraction, 0.0, 1.0) * width + 0.5);
    std::fprintf(stderr, "\r%s [%s%s] %3d%% %-28s", title_.c_str(), std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), ' ').c_str(), int(fraction * 100 + 0.5), stage.c_str());
    std::fflush(stderr);
    drawn_ = true;
  }

  void finish() {
    if (enabled_ && drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
  }

 private:
  std::string title_;
  bool enabled_;
  bool drawn_ = false;
  std::mutex mutex_;
  std::string stage_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace svo::tools
