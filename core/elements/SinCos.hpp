#pragma once
// sin and cos of one angle with a fast path for |a| <= pi/4, where libm's sincos still costs about
// 100 instructions: the planar beam takes the sines of its node rotations relative to their
// reference (small in a flexure) several times per right-hand side. The kernels are the minimax
// polynomials of fdlibm's __kernel_sin / __kernel_cos (Sun Microsystems, 1993; error below one ulp
// on [-pi/4, pi/4]); larger angles go to libm. core/tests/test_sin_cos.cpp checks both against libm.
#include <bit>
#include <cmath>
#include <cstdint>

namespace flexmb::core {

inline void sinCos(double a, double& s, double& c) {
  const double ax = std::fabs(a);
  if (!(ax <= 0.7853981633974483)) {  // pi/4 (and NaN): libm with its range reduction
    s = std::sin(a);
    c = std::cos(a);
    return;
  }
  constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03, S3 = -1.98412698298579493134e-04,
                   S4 = 2.75573137070700676789e-06, S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
  constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03, C3 = 2.48015872894767294178e-05,
                   C4 = -2.75573143513906633035e-07, C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
  const double z = a * a;
  const double rs = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
  s = a + (z * a) * (S1 + z * rs);
  const double r = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
  if (ax < 0.3) {
    c = 1.0 - (0.5 * z - z * r);
    return;
  }
  // 1 - z/2 split as (1 - qx) - (z/2 - qx), qx ~ |a|/4 with a short mantissa so that 1 - qx is exact.
  const double qx =
      ax > 0.78125 ? 0.28125 : std::bit_cast<double>(std::bit_cast<std::uint64_t>(0.25 * ax) & 0xFFFFFFFF00000000ull);
  c = (1.0 - qx) - ((0.5 * z - qx) - z * r);
}

}  // namespace flexmb::core
