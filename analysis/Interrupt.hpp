#pragma once
// A request to stop an analysis, set asynchronously (the command line's SIGINT / SIGTERM handler,
// Octave's Ctrl-C): the analyses look at the flag at their checks (a load step, a sweep point, a
// batch of right-hand sides), stop there and return what they have, marked as interrupted.
#include <atomic>
#include <csignal>
#include <string>

namespace flexmb::analysis {

inline bool stopRequested(const std::atomic<bool>* flag) { return flag && flag->load(std::memory_order_relaxed); }

// The cause a time limit (--max-seconds of --accuracy) sets where a stop is not the user's.
constexpr int kTimeAllowedCause = SIGALRM;

// What stopped the run, for stop reasons and manifests: "terminated (SIGTERM)" when that signal set
// the flag, "stopped at the time allowed" when a time limit did, else "interrupted (Ctrl-C)".
inline std::string interruptCause(const std::atomic<int>* signal) {
  if (signal && signal->load() == SIGTERM) return "terminated (SIGTERM)";
  if (signal && signal->load() == kTimeAllowedCause) return "stopped at the time allowed (--max-seconds)";
  return "interrupted (Ctrl-C)";
}

}  // namespace flexmb::analysis
