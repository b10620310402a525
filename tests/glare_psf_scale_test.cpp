// PSF mapped onto display pixels: sum conserved, angles kept, refusals.
#include <gtest/gtest.h>

#include <cmath>

#include "glare/wave/psf_scale.h"
#include "glare_psf_test_support.h"

namespace glarelab {
namespace {

Psf gaussian_psf(int n, double degrees_per_pixel, double sigma_deg, double offset_deg) {
  Psf psf;
  psf.size_px = n;
  psf.degrees_per_pixel = degrees_per_pixel;
  psf.values.resize(static_cast<std::size_t>(n) * n);
  double sum = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double ax = (x - n / 2) * degrees_per_pixel - offset_deg, ay = (y - n / 2) * degrees_per_pixel;
      psf.at(0, x, y) = std::exp(-0.5 * (ax * ax + ay * ay) / (sigma_deg * sigma_deg));
      sum += psf.at(0, x, y);
    }
  for (double& v : psf.values) v /= sum;
  return psf;
}

TEST(GlarePsfScale, ConservesSumAndKeepsTheCentroidInDegrees) {
  // A Gaussian displaced by 0.3 deg, PSF pixels of 0.004 deg onto display pixels of 0.0237 deg
  // (0.248 mm pitch at 600 mm): the sum stays 1 and the centroid stays at 0.3 deg (box
  // integration conserves the first moment up to the half-pixel offsets, which the grid centring
  // makes zero).
  const Psf psf = gaussian_psf(512, 0.004, 0.1, 0.3);
  const Psf display = resample_psf_to_display(psf, 0.0237);
  EXPECT_NEAR(test::channel_sum(display, 0), 1.0, 1e-12);
  EXPECT_NEAR(display.degrees_per_pixel, 0.0237, 0.0);
  double mx = 0.0;
  for (int y = 0; y < display.size_px; ++y)
    for (int x = 0; x < display.size_px; ++x) mx += display.at(0, x, y) * (x - display.size_px / 2) * 0.0237;
  EXPECT_NEAR(mx, 0.3, 1e-6);
  EXPECT_EQ(display.size_px % 2, 0);
}

TEST(GlarePsfScale, RefusesTinyExtentAndCoarserPsfPixels) {
  const Psf psf = gaussian_psf(64, 0.001, 0.01, 0.0);  // spans 0.064 deg
  try {
    resample_psf_to_display(psf, 0.05);  // 1.28 display pixels
    FAIL() << "expected PsfScaleError";
  } catch (const PsfScaleError& error) {
    EXPECT_NE(std::string(error.what()).find("fewer than 2"), std::string::npos) << error.what();
  }
  try {
    resample_psf_to_display(psf, 0.0005);  // PSF pixels twice the display's
    FAIL() << "expected PsfScaleError";
  } catch (const PsfScaleError& error) {
    EXPECT_NE(std::string(error.what()).find("alias"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace glarelab
