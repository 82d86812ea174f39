#pragma once
// ARPACK keeps Fortran SAVE state between calls: every reverse-communication loop of the process
// (EigenSolver's symmetric, KineticStability's non-symmetric) holds this lock while it runs.
#include <mutex>

namespace flexmb::solvers {
std::mutex& arpackMutex();
}
