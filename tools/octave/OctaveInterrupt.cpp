#include "tools/octave/OctaveInterrupt.hpp"

#include <chrono>
#include <exception>

#if defined(FLEXMB_OCTAVE_MEX)
#include <octave/quit.h>
#endif

namespace flexmb::octave_gateway {
namespace {
std::atomic<bool> g_interrupted{false};

#if defined(FLEXMB_OCTAVE_MEX)
bool octavePending() { return octave_interrupt_state > 0; }
void clearOctave() {
  octave_interrupt_state = 0;
  octave_signal_caught = 0;
}
#else
bool octavePending() { return false; }
void clearOctave() {}
#endif
}  // namespace

InterruptWatch::InterruptWatch() {
  g_interrupted.store(false);
#if defined(FLEXMB_OCTAVE_MEX)
  // 20 ms polls: nothing measurable beside an analysis, and Ctrl-C feels immediate.
  thread_ = std::thread([this] {
    while (!stop_.load()) {
      if (octavePending()) g_interrupted.store(true);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
#endif
}

InterruptWatch::~InterruptWatch() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  if (g_interrupted.load()) clearOctave();  // handled here: results are written, then the error is raised
}

const std::atomic<bool>* InterruptWatch::flag() const { return &g_interrupted; }
bool InterruptWatch::interrupted() const { return g_interrupted.load(); }

void noteInterpreterInterrupt() {
  g_interrupted.store(true);
  clearOctave();
}

bool isInterpreterInterrupt(const std::exception_ptr& current) {
#if defined(FLEXMB_OCTAVE_MEX)
  try {
    std::rethrow_exception(current);
  } catch (const octave::interrupt_exception&) {
    return true;
  } catch (...) {}
#else
  (void)current;
#endif
  return false;
}

}  // namespace flexmb::octave_gateway
