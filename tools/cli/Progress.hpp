#pragma once
// A progress line on stderr for long analyses ("static: 12 of 40 load steps (30%), 3.1 s, about
// 7 s left"). Silent for the first second and with --quiet; rewritten at most four times a second.
#include <chrono>
#include <cstdio>
#include <string>

namespace flexmb::cli {

class Progress {
 public:
  Progress(std::string what, bool enabled) : what_(std::move(what)), enabled_(enabled) {}
  ~Progress() { finish(); }
  void update(long done, long total, const char* unit) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (elapsed < 1.0 || now - last_ < std::chrono::milliseconds(250)) return;
    last_ = now;
    printed_ = true;
    const double share = total > 0 ? static_cast<double>(done) / total : 0.0;
    std::fprintf(stderr, "\r  %s: %ld of %ld %s (%3.0f%%), %.1f s", what_.c_str(), done, total, unit, 100 * share,
                 elapsed);
    if (share > 0) std::fprintf(stderr, ", about %.0f s left", elapsed * (1 - share) / share);
    std::fprintf(stderr, "   ");
    std::fflush(stderr);
  }
  void finish() {
    if (printed_) std::fprintf(stderr, "\n");
    printed_ = false;
  }

 private:
  std::string what_;
  bool enabled_;
  bool printed_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_ = start_;
};

}  // namespace flexmb::cli
