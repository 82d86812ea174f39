#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/elements/SinCos.hpp"

using flexmb::core::sinCos;

namespace {
// Distance in units in the last place of the reference.
double ulps(double value, double reference) {
  if (value == reference) return 0.0;
  const double ulp = std::nextafter(std::fabs(reference), INFINITY) - std::fabs(reference);
  return std::fabs(value - reference) / ulp;
}
}  // namespace

TEST(SinCos, PolynomialPathAgreesWithLibmWithinOneUlp) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> wide(-0.7853981633974483, 0.7853981633974483);
  std::uniform_real_distribution<double> exponent(-30.0, 0.0);
  double worstS = 0.0, worstC = 0.0;
  for (int k = 0; k < 400000; ++k) {
    // Half uniform on [-pi/4, pi/4], half log-uniform small angles (the usual case in a flexure).
    double a = (k & 1) ? wide(rng) : std::copysign(std::pow(10.0, exponent(rng)), wide(rng));
    double s, c;
    sinCos(a, s, c);
    worstS = std::max(worstS, ulps(s, std::sin(a)));
    worstC = std::max(worstC, ulps(c, std::cos(a)));
  }
  // fdlibm's kernels are below one ulp from the exact value, libm too: at most one apart.
  EXPECT_LE(worstS, 1.0);
  EXPECT_LE(worstC, 1.0);
  // The branch points of the cosine kernel and the ends of the interval.
  for (double a : {0.0, -0.0, 0.3, std::nextafter(0.3, 0.0), 0.78125, std::nextafter(0.78125, 1.0), 0.7853981633974483,
                   -0.7853981633974483, 1e-300, 5e-324}) {
    double s, c;
    sinCos(a, s, c);
    EXPECT_LE(ulps(s, std::sin(a)), 1.0) << a;
    EXPECT_LE(ulps(c, std::cos(a)), 1.0) << a;
  }
}

TEST(SinCos, LargeAnglesAndNonFiniteGoToLibm) {
  for (double a : {0.7853981633974484, 1.0, -3.0, 100.0, 1e22}) {
    double s, c;
    sinCos(a, s, c);
    EXPECT_EQ(s, std::sin(a)) << a;
    EXPECT_EQ(c, std::cos(a)) << a;
  }
  double s, c;
  sinCos(std::numeric_limits<double>::quiet_NaN(), s, c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
  sinCos(INFINITY, s, c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}
