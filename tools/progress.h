// A one-line progress bar on stderr: the stage, the fraction done, the rate
// (items per second where the work is counted) and the time elapsed and
// left. Drawn when stderr is a terminal, silent otherwise; the environment
// variable SVO_PROGRESS=1 forces it on (tests, logs), SVO_PROGRESS=0 off.
#pragma once

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>

namespace svo::tools {

// "0:07", "4:32", "1:02:03" (hours past 59 minutes); "?" for a negative or
// non-finite time.
inline std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0 || seconds > 1e8) return "?";
  const long s = std::lround(seconds);
  char buf[32];
  if (s < 3600) {
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  }
  return buf;
}

// Items per second with three significant digits ("12.3 frames/s"); below
// one a second, seconds per item ("4.50 s/frame": the unit without its
// plural s). Empty for a rate that is not positive and finite.
inline std::string format_rate(double per_second, const std::string& unit) {
  if (!std::isfinite(per_second) || per_second <= 0) return "";
  char buf[64];
  if (per_second >= 1) {
    const int digits = per_second >= 100 ? 0 : per_second >= 10 ? 1 : 2;
    std::snprintf(buf, sizeof buf, "%.*f %s/s", digits, per_second, unit.c_str());
    return buf;
  }
  std::string one = unit;
  if (one.size() > 1 && one.back() == 's') one.pop_back();
  const double each = 1.0 / per_second;
  std::snprintf(buf, sizeof buf, "%.*f s/%s", each >= 100 ? 0 : each >= 10 ? 1 : 2, each, one.c_str());
  return buf;
}

// What one line of the bar shows.
struct ProgressLine {
  std::string title, stage;
  double fraction = 0;  // of the whole work, 0 to 1
  double elapsed = 0;   // seconds since the bar started
  double rate = 0;      // items per second; 0: not counted
  std::string unit;     // of the items ("frames", "rows")
  uint64_t done = 0, total = 0;
  double left = -1;  // seconds; negative: not known yet
};

// The line without carriage return or padding:
// "flythrough [#####         ]  33% frames 20/60  1.52 frames/s  0:13 elapsed, 0:26 left".
inline std::string format_progress_line(const ProgressLine& p) {
  const int width = 20;
  const double f = std::clamp(std::isfinite(p.fraction) ? p.fraction : 0.0, 0.0, 1.0);
  const int filled = int(f * width + 0.5);
  char pct[8];
  std::snprintf(pct, sizeof pct, "%3d%%", int(f * 100 + 0.5));
  std::string line = p.title + " [" + std::string(size_t(filled), '#') + std::string(size_t(width - filled), ' ') +
                     "] " + pct + " " + p.stage;
  if (p.total > 0) line += " " + std::to_string(p.done) + "/" + std::to_string(p.total);
  const std::string rate = p.rate > 0 ? format_rate(p.rate, p.unit) : "";
  if (!rate.empty()) line += "  " + rate;
  line += "  " + format_duration(p.elapsed) + " elapsed";
  if (p.left >= 0 && f < 1) line += ", " + format_duration(p.left) + " left";
  return line;
}

// Whether a bar is drawn: SVO_PROGRESS=1 or 0 decides, else whether stderr
// is a terminal.
inline bool progress_enabled() {
  if (const char* v = std::getenv("SVO_PROGRESS")) {
    if (std::strcmp(v, "1") == 0) return true;
    if (std::strcmp(v, "0") == 0) return false;
  }
  return ::isatty(STDERR_FILENO) == 1;
}

// The bar of one command. Thread-safe; redraws at most 10 times a second on
// updates, and once a second between them (so that the elapsed time moves
// through a long stage that reports nothing).
class ProgressBar {
 public:
  explicit ProgressBar(std::string title) : title_(std::move(title)), enabled_(progress_enabled()) {
    start_ = base_time_ = Clock::now();
    if (enabled_) ticker_ = std::thread([this] { tick(); });
  }
  ~ProgressBar() {
    if (ticker_.joinable()) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
      }
      wake_.notify_all();
      ticker_.join();
    }
    finish();
  }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Uncounted work: `fraction` of the whole done; the time left is
  // extrapolated from the time so far.
  void update(const std::string& stage, double fraction) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = Clock::now();
    const bool changed = stage != line_.stage || line_.total != 0;
    if (!changed && fraction < 1.0 && now - last_ < std::chrono::milliseconds(100)) return;
    line_.stage = stage;
    line_.done = line_.total = 0;
    line_.rate = 0;
    line_.unit.clear();
    line_.left = time_left(now, fraction);
    line_.fraction = fraction;
    draw(now);
  }

  // Counted work: `done` of `total` items (`unit`: "frames", "rows") of
  // this stage; the rate is measured over the stage (from its first update).
  // The bar shows `fraction` of the whole when given (a stage of a longer
  // job; the time left is then extrapolated from it), else done / total
  // (the time left from the rate).
  void update(const std::string& stage, uint64_t done, uint64_t total, const std::string& unit, double fraction = -1) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = Clock::now();
    if (stage != line_.stage || line_.total != total || unit != line_.unit || done < stage_done_) {
      line_.stage = stage;
      line_.unit = unit;
      stage_start_ = now;
      stage_done_ = done;
      line_.rate = 0;
      line_.left = -1;
    } else if (done < total && now - last_ < std::chrono::milliseconds(100)) {
      line_.done = done;
      return;
    }
    line_.done = done;
    line_.total = total;
    if (fraction >= 0) line_.left = time_left(now, fraction);
    line_.fraction = fraction >= 0 ? fraction : total > 0 ? double(done) / double(total) : 0;
    const double t = seconds(now - stage_start_);
    if (done > stage_done_ && t > 0) {
      line_.rate = double(done - stage_done_) / t;
      if (fraction < 0) line_.left = double(total - std::min(done, total)) / line_.rate;
    }
    draw(now);
  }

  // Ends the line (a newline after a drawn bar); a later update starts a new one.
  void finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (enabled_ && drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
  }

  bool enabled() const { return enabled_; }

 private:
  using Clock = std::chrono::steady_clock;
  static double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

  // Under the lock. The time left at `fraction` (before line_.fraction
  // takes it), extrapolated from the time since the fraction started
  // rising: a fraction that goes back (a command whose stages each run from
  // 0 to 1) starts a new extrapolation. Negative: not known yet.
  double time_left(Clock::time_point now, double fraction) {
    if (!(fraction >= base_fraction_) || line_.fraction > fraction) {
      base_fraction_ = std::clamp(fraction, 0.0, 1.0);
      base_time_ = now;
    }
    const double t = seconds(now - base_time_), gained = fraction - base_fraction_;
    return gained > 0.005 && t > 1.0 ? t * (1 - fraction) / gained : -1;
  }

  // Under the lock.
  void draw(Clock::time_point now) {
    last_ = now;
    line_.title = title_;
    line_.elapsed = seconds(now - start_);
    std::string text = format_progress_line(line_);
    winsize ws{};
    if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 10 && text.size() >= ws.ws_col) {
      text.resize(size_t(ws.ws_col) - 1);
    }
    std::fprintf(stderr, "\r%s\033[K", text.c_str());
    std::fflush(stderr);
    drawn_ = true;
  }

  void tick() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
      wake_.wait_for(lock, std::chrono::seconds(1));
      if (stopping_ || !drawn_) continue;
      const auto now = Clock::now();
      if (now - last_ < std::chrono::milliseconds(900)) continue;
      // The time left counts down between updates of a counted stage.
      if (line_.left >= 0) line_.left = std::max(0.0, line_.left - seconds(now - last_));
      draw(now);
    }
  }

  std::string title_;
  bool enabled_;
  bool drawn_ = false;
  bool stopping_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread ticker_;
  ProgressLine line_;
  Clock::time_point start_, last_{}, stage_start_{}, base_time_{};
  uint64_t stage_done_ = 0;
  double base_fraction_ = 0;
};

}  // namespace svo::tools
