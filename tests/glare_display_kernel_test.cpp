// Analytic PSFs on display pixels (glare/analytic/display_glare_kernel.h): each pixel's energy against an
// independent adaptive Gauss-Kronrod integration over the pixel in the display plane, and the
// kernel's total against the PSF's energy over the display rectangle by a 1D integral over
// directions of the radial energy (no pixels involved).
#include <cmath>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include "glare/analytic/display_glare_kernel.h"

namespace glarelab {
namespace {

// The pixel's energy by nested adaptive quadrature in x and y, the pixel split at the source's
// coordinates (where the integrand has its cusp) and at its middle.
double reference_pixel_energy(const AnalyticPsf& psf, int channel, int dx, int dy, const DisplayGeometry& g) {
  using boost::math::quadrature::gauss_kronrod;
  const double p = g.pixel_pitch_mm, d = g.viewing_distance_mm;
  auto density = [&](double x, double y) {
    const double r2 = x * x + y * y;
    const double angle_deg = std::atan2(std::sqrt(r2), d) * 180.0 / std::numbers::pi;
    return psf.per_sr(angle_deg, channel) * d / std::pow(d * d + r2, 1.5);
  };
  auto splits = [&](double lo, double hi) {
    std::vector<double> s{lo};
    if (lo < 0.0 && hi > 0.0) s.push_back(0.0);
    s.push_back(hi);
    return s;
  };
  const std::vector<double> xs = splits((dx - 0.5) * p, (dx + 0.5) * p), ys = splits((dy - 0.5) * p, (dy + 0.5) * p);
  double sum = 0.0;
  for (std::size_t j = 0; j + 1 < ys.size(); ++j)
    for (std::size_t i = 0; i + 1 < xs.size(); ++i)
      sum += gauss_kronrod<double, 15>::integrate(
          [&](double y) {
            return gauss_kronrod<double, 15>::integrate([&](double x) { return density(x, y); }, xs[i], xs[i + 1], 12, 1e-8);
          },
          ys[j], ys[j + 1], 12, 1e-8);
  return sum;
}

TEST(DisplayGlareKernel, PixelEnergiesMatchAdaptiveIntegration) {
  const DisplayGeometry geometry{600.0, 0.25};  // 0.0239 degrees per pixel at the centre
  const AnalyticPsf scotopic = AnalyticPsf::spencer(SpencerRegime::scotopic, 0.001, ObserverEye{30.0, 0.5});
  const AnalyticPsf cie = AnalyticPsf::cie(ObserverEye{60.0, 1.0});
  // The core, the knee of f1, CIE's 0.1 degree kink (4.2 px), the halo (2.1-3.7 degrees:
  // 88-155 px), the far field and a pixel far off axis.
  const int offsets[][2] = {{0, 0}, {1, 0}, {1, 1}, {3, 2}, {4, 1}, {6, 5}, {13, 0}, {30, 17},
                            {90, 60}, {125, 0}, {100, 80}, {400, 300}, {1500, 900}};
  for (const auto& o : offsets) {
    for (int c : {0, 2}) {
      const double fast = pixel_energy(scotopic, c, o[0], o[1], geometry);
      EXPECT_NEAR(fast, reference_pixel_energy(scotopic, c, o[0], o[1], geometry), 1e-5 * fast)
          << "Spencer scotopic channel " << c << " at " << o[0] << ", " << o[1];
    }
    const double fast = pixel_energy(cie, 0, o[0], o[1], geometry);
    EXPECT_NEAR(fast, reference_pixel_energy(cie, 0, o[0], o[1], geometry), 1e-5 * fast)
        << "CIE at " << o[0] << ", " << o[1];
  }
  // A coarse display (0.19 degrees per pixel): the halo is 1-2 pixels wide there.
  const DisplayGeometry coarse{300.0, 1.0};
  for (const auto& o : {std::pair{0, 0}, std::pair{1, 0}, std::pair{16, 0}, std::pair{12, 9}}) {
    const double fast = pixel_energy(scotopic, 0, o.first, o.second, coarse);
    EXPECT_NEAR(fast, reference_pixel_energy(scotopic, 0, o.first, o.second, coarse), 1e-5 * fast)
        << "coarse at " << o.first << ", " << o.second;
  }
}

TEST(DisplayGlareKernel, KernelHoldsThePsfEnergyThatFallsOnTheDisplay) {
  const DisplayGeometry geometry{600.0, 0.25};
  for (const AnalyticPsf& psf : {AnalyticPsf::spencer(SpencerRegime::mesopic, 1.0, ObserverEye{25.0, 0.5}),
                                 AnalyticPsf::cie(ObserverEye{40.0, 0.5})}) {
    const DisplayKernel kernel = analytic_display_kernel(psf, geometry, 200, 120, 2);
    for (int c = 0; c < kernel.channels; ++c) {
      const double expected = energy_within_rectangle(psf, c, geometry, 200.5 * 0.25, 120.5 * 0.25);
      EXPECT_NEAR(kernel.energy(c), expected, 1e-6) << to_string(psf.model()) << " channel " << c;
      EXPECT_LT(expected, 1.0);  // some light falls beyond a 10 x 6 degree display
      EXPECT_GT(expected, 0.9);
    }
    // Radial symmetry on square pixels.
    EXPECT_EQ(kernel.at(0, 37, 11), kernel.at(0, -37, -11));
    EXPECT_NEAR(kernel.at(0, 37, 11), kernel.at(0, 11, 37), 1e-7 * kernel.at(0, 37, 11));
  }
}

TEST(DisplayGlareKernel, ResultDoesNotDependOnTheThreadCount) {
  const AnalyticPsf psf = AnalyticPsf::spencer(SpencerRegime::scotopic, 0.001, ObserverEye{});
  const DisplayKernel one = analytic_display_kernel(psf, DisplayGeometry{}, 40, 30, 1);
  const DisplayKernel three = analytic_display_kernel(psf, DisplayGeometry{}, 40, 30, 3);
  EXPECT_EQ(one.values, three.values);
}

}  // namespace
}  // namespace glarelab
