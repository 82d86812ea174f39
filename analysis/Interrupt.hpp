#pragma once
// A request to stop an analysis, set asynchronously (the command line's SIGINT / SIGTERM handler,
// Octave's Ctrl-C): the analyses look at the flag at their checks (a load step, a sweep point, a
// batch of right-hand sides), stop there and return what they have, marked as interrupted.
#include <atomic>
#include <csignal>
#include <string>

namespace flexmb::analysis {

inline bool stopRequested(const std::atomic<bool>* flag) { return flag && flag->load(std::memory_order_relaxed); }

// What stopped the run, for stop reasons and manifests: "terminated (SIGTERM)" when that signal set
// the flag, else "interrupted (Ctrl-C)".
inline std::string interruptCause(const std::atomic<int>* signal) {
  return signal && signal->load() == SIGTERM ? "terminated (SIGTERM)" : "interrupted (Ctrl-C)";
}

}  // namespace flexmb::analysis
