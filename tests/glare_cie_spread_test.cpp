// The CIE 146:2002 glare spread function (glare/analytic/cie_glare_spread.h) against values computed by
// hand from the formula, and its PSF (glare/analytic/analytic_psf.h): scattered light plus peak is 1.
#include <cmath>

#include <gtest/gtest.h>

#include "glare/analytic/analytic_psf.h"
#include "glare/analytic/cie_glare_spread.h"

namespace glarelab {
namespace {

TEST(CieGlareSpread, HandComputedValuesForAYoungBrownAndAnOldBlueEye) {
  // A = 25, p = 0.5: (A / 62.5)^4 = 0.4^4 = 0.0256, age factor 1.0256; 0.0025 p = 0.00125.
  //   0.1 deg: 10 / 0.001 + (500 + 0.5) 1.0256 + 0.00125 = 10000 + 513.3128 + 0.00125
  //   1 deg:   10 + (5 + 0.05) 1.0256 + 0.00125 = 10 + 5.17928 + 0.00125
  //   10 deg:  0.01 + (0.05 + 0.005) 1.0256 + 0.00125 = 0.01 + 0.056408 + 0.00125
  //   30 deg:  10 / 27000 + (5 / 900 + 0.05 / 30) 1.0256 + 0.00125
  //   90 deg:  10 / 729000 + (5 / 8100 + 0.05 / 90) 1.0256 + 0.00125
  const double young[5] = {10513.31405, 15.18053, 0.067658, 0.0090274815, 0.0024665816};
  // A = 70, p = 1: (70 / 62.5)^4 = 1.12^4 = 1.57351936, age factor 2.57351936; 0.0025 p = 0.0025.
  //   0.1 deg: 10000 + (500 + 1) 2.57351936 + 0.0025 = 10000 + 1289.33320 + 0.0025
  //   1 deg:   10 + (5 + 0.1) 2.57351936 + 0.0025 = 10 + 13.12494874 + 0.0025
  //   10 deg:  0.01 + (0.05 + 0.01) 2.57351936 + 0.0025 = 0.01 + 0.15441116 + 0.0025
  //   30 deg:  10 / 27000 + (5 / 900 + 0.1 / 30) 2.57351936 + 0.0025
  //   90 deg:  10 / 729000 + (5 / 8100 + 0.1 / 90) 2.57351936 + 0.0025
  const double old[5] = {11289.33570, 23.12744874, 0.1669111616, 0.0257460980, 0.0069617756};
  const double angles[5] = {0.1, 1.0, 10.0, 30.0, 90.0};
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(cie146_glare_spread_per_sr(angles[i], 25.0, 0.5), young[i], 1e-8 * young[i]) << angles[i];
    EXPECT_NEAR(cie146_glare_spread_per_sr(angles[i], 70.0, 1.0), old[i], 1e-8 * old[i]) << angles[i];
  }
}

TEST(CieGlareSpread, PsfHoldsTheCoreAtItsSmallestAngleAndKeepsUnitEnergy) {
  const ObserverEye eye{25.0, 0.5};
  EXPECT_EQ(cie146_scattered_per_sr(0.01, 25.0, 0.5), cie146_glare_spread_per_sr(0.1, 25.0, 0.5));
  EXPECT_EQ(cie146_scattered_per_sr(0.5, 25.0, 0.5), cie146_glare_spread_per_sr(0.5, 25.0, 0.5));
  const AnalyticPsf psf = AnalyticPsf::cie(eye);
  // Independent of radial_energy: the core disc in closed form, the rest by composite Simpson on
  // a logarithmic grid.
  const double core = cie146_glare_spread_per_sr(0.1, 25.0, 0.5) * 2.0 * std::numbers::pi *
                      (1.0 - std::cos(0.1 * std::numbers::pi / 180.0));
  double tail = 0.0;
  const int n = 20000;
  const double a = std::log(0.1), b = std::log(90.0), h = (b - a) / n;
  for (int i = 0; i <= n; ++i) {
    const double t = std::exp(a + i * h);
    const double f = cie146_glare_spread_per_sr(t, 25.0, 0.5) * std::sin(t * std::numbers::pi / 180.0) * t;  // dt = t du
    tail += f * ((i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0));
  }
  tail *= h / 3.0 * 2.0 * std::numbers::pi * std::numbers::pi / 180.0;
  EXPECT_NEAR(1.0 - psf.peak_fraction(), core + tail, 1e-7);
  EXPECT_GT(psf.peak_fraction(), 0.5);  // most light is not scattered
  // An older, lighter eye scatters more.
  EXPECT_LT(AnalyticPsf::cie(ObserverEye{70.0, 1.0}).peak_fraction(), psf.peak_fraction());
}

TEST(CieGlareSpread, ObserverOutsideTheRangesIsRefused) {
  EXPECT_THROW(check_observer_eye(ObserverEye{0.5, 0.5}), std::invalid_argument);
  EXPECT_THROW(check_observer_eye(ObserverEye{101.0, 0.5}), std::invalid_argument);
  EXPECT_THROW(check_observer_eye(ObserverEye{30.0, 1.2}), std::invalid_argument);
  EXPECT_THROW(check_observer_eye(ObserverEye{30.0, std::nan("")}), std::invalid_argument);
  EXPECT_NO_THROW(check_observer_eye(ObserverEye{1.0, 0.0}));
  EXPECT_NO_THROW(check_observer_eye(ObserverEye{100.0, 1.0}));
}

}  // namespace
}  // namespace glarelab
