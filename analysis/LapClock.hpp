#pragma once
// The wall-clock seconds of a job's parts (reading, integration, accuracy check, writing, ...), for
// the `wall time` line and the manifest (issue 48: the process time of a run is said in full).
#include <chrono>

namespace flexmb::analysis {

class LapClock {
 public:
  // Seconds since the start or the previous lap.
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return s;
  }
  // Seconds since the start.
  double total() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_ = start_;
};

}  // namespace flexmb::analysis
