#pragma once
// Ctrl-C during spacar(): the run stops at its next check, keeps what it computed (the .sbd and the
// workspace get the steps so far) and then raises an error, as the command line stops with exit
// code 130. In Octave the SIGINT goes to Octave's own handling (a watcher thread sets
// octave_interrupt_state), which a MEX function never sees unless it looks: InterruptWatch looks,
// from a thread, and raises the analysis' interrupt flag (analysis::SimulationOptions::interrupt).
// A Ctrl-C that arrives while a user function runs in the interpreter unwinds out of
// mexCallMATLAB instead; MatlabUserFunctions catches it and calls noteInterpreterInterrupt().
// In MATLAB (no Octave headers) nothing watches: a run ends at Ctrl-C as MATLAB ends MEX functions.
#include <atomic>
#include <thread>

namespace flexmb::octave_gateway {

class InterruptWatch {
 public:
  InterruptWatch();   // clears the flag and starts watching
  ~InterruptWatch();  // stops watching; after an interrupt, clears Octave's pending interrupt
  InterruptWatch(const InterruptWatch&) = delete;
  InterruptWatch& operator=(const InterruptWatch&) = delete;
  const std::atomic<bool>* flag() const;
  bool interrupted() const;

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// A Ctrl-C was caught as an exception of the interpreter: raise the flag and clear Octave's
// interrupt state so that the results can still be written and assigned.
void noteInterpreterInterrupt();
// True when the interpreter's interrupt exception is what `current` holds (Octave builds).
bool isInterpreterInterrupt(const std::exception_ptr& current);

}  // namespace flexmb::octave_gateway
