#include "cli/progress.hpp"

#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace loopscan::cli {

namespace {

constexpr double kQuietFirstSeconds = 1.0;  // short steps show only their summary
constexpr double kRedrawSeconds = 0.1;

double seconds_between(std::chrono::steady_clock::time_point a,
                       std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

std::string format_duration(double s) {
  char buf[32];
  if (!(s < 60.0)) {
    const long total = std::lround(s);
    std::snprintf(buf, sizeof buf, "%ld min %02ld s", total / 60, total % 60);
  } else {
    std::snprintf(buf, sizeof buf, s < 10.0 ? "%.1f s" : "%.0f s", s);
  }
  return buf;
}

StepProgress::StepProgress(std::string label, std::string unit, bool quiet)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      quiet_(quiet),
      terminal_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

double StepProgress::seconds() const {
  return seconds_between(start_, std::chrono::steady_clock::now());
}

void StepProgress::update(std::size_t done, std::size_t total) {
  done_ = done;
  total_ = total;
  if (quiet_ || total == 0) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = seconds_between(start_, now);
  if (elapsed < kQuietFirstSeconds) return;
  const double rate = done / std::max(elapsed, 1e-9);
  const double remaining = done > 0 ? (total - std::min(done, total)) / rate : NAN;
  if (terminal_) {
    if (seconds_between(last_draw_, now) < kRedrawSeconds && done < total) return;
    last_draw_ = now;
    constexpr int kWidth = 24;
    const int filled = static_cast<int>(kWidth * std::min(done, total) / total);
    std::fprintf(stderr, "\r%s [%s%s] %zu/%zu %s, %.1f/s, %s left   ", label_.c_str(),
                 std::string(filled, '#').c_str(), std::string(kWidth - filled, '.').c_str(), done,
                 total, unit_.c_str(), rate,
                 std::isfinite(remaining) ? format_duration(remaining).c_str() : "?");
    drawn_ = true;
  } else {
    const int decile = static_cast<int>(10 * std::min(done, total) / total);
    if (decile <= last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s: %zu/%zu %s (%d %%), %.1f/s, %s left\n", label_.c_str(), done, total,
                 unit_.c_str(), decile * 10, rate,
                 std::isfinite(remaining) ? format_duration(remaining).c_str() : "?");
  }
  std::fflush(stderr);
}

StepProgress::~StepProgress() {
  if (drawn_ && !finished_) std::fprintf(stderr, "\n");
}

void StepCounter::next(const std::string& what) {
  std::printf("[%d/%d] %s\n", ++done_, steps_, what.c_str());
  std::fflush(stdout);
}

void StepProgress::finish(const std::string& extra) {
  finished_ = true;
  if (quiet_) return;
  const double s = seconds();
  if (drawn_) std::fprintf(stderr, "\r\033[K");  // clear the bar's line
  std::fprintf(stderr, "%s: %zu %s in %s", label_.c_str(), done_, unit_.c_str(),
               format_duration(s).c_str());
  if (done_ > 0 && s >= kQuietFirstSeconds) std::fprintf(stderr, " (%.1f/s)", done_ / s);
  std::fprintf(stderr, "%s\n", extra.c_str());
  std::fflush(stderr);
}

}  // namespace loopscan::cli
