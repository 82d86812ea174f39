#pragma once
// Model texts (.dat) shared by the tests of every floor (each test keeps its own assertions); text
// only, no dependency.
#include <sstream>
#include <string>

namespace flexmb::test {

// A datfile of the repository.
inline std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

// A flexible arm of three PLBEAMs (elongation and bending free) swung by a prescribed hinge angle
// (rheonomic input), with distributed and lumped mass, damping and gravity: every optional term of
// Eq. 13. inputAngle: the INPUTET expressions of the hinge (angle, rate, acceleration, quoted);
// tipLoad: the load line(s) on node 4.
inline std::string swungArm(const std::string& inputAngle = "\"0.3 + 2*t + 0.75*t^2\" \"2 + 1.5*t\" \"1.5\"",
                            const std::string& tipLoad = "XF 4 0.5 -2\n") {
  std::ostringstream s;
  s << "PLHINGE 10  100 101\n";
  for (int k = 1; k <= 3; ++k)
    s << "PLBEAM " << k << "  " << k << " " << 100 + k << "  " << k + 1 << " " << 101 + k << "\n";
  for (int k = 1; k <= 4; ++k) s << "X " << k << " " << 0.4 * (k - 1) << " 0\n";
  s << "FIX 1\nFIX 100\nINPUTE 10 1\n";
  for (int k = 1; k <= 3; ++k) s << "DYNE " << k << " 1 2 3\n";
  s << "END\nHALT\n";
  s << "INPUTET 10 1 " << inputAngle << "\n";
  for (int k = 1; k <= 3; ++k) s << "EM " << k << " 1.7 2e-4\nESTIFF " << k << " 4e4 30\nEDAMP " << k << " 2 0.05\n";
  s << "XM 4 0.3\n" << tipLoad << "GRAVITY 0 -9.81\nEND\nEND\n";
  return s.str();
}

// Cantilever of n PLBEAMs (inextensible, bending DYNE) clamped to a hub that turns at the
// prescribed rate W about the beam's root (input hinge), hub radius 0.
inline std::string spinningBeam(int n, double L, double EI, double rhoA, double W, const std::string& extra = "") {
  std::ostringstream s;
  s.precision(17);
  s << "PLHINGE 100  200 201\n";
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << k << "  " << k << " " << 200 + k << "  " << k + 1 << " " << 201 + k << "\n";
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " " << L * (k - 1) / n << " 0\n";
  s << "FIX 1\nFIX 200\nINPUTE 100 1\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 2 3\n";
  s << "END\nHALT\n";
  s << "INPUTET 100 1 \"" << W << "*t\" \"" << W << "\" \"0\"\n";
  for (int k = 1; k <= n; ++k) s << "EM " << k << " " << rhoA << "\nESTIFF " << k << " 0 " << EI << "\n";
  s << extra << "END\nEND\n";
  return s.str();
}

}  // namespace flexmb::test
