// The aperture coverage rule (aperture_raster.h) on hand-checked cases.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "glare/aperture_raster.h"

namespace glarelab {
namespace {

double total(const ApertureGrid& grid) {
  double sum = 0.0;
  for (double v : grid.transmittance) sum += v;
  return sum * grid.pixel_mm() * grid.pixel_mm();
}

TEST(GlareApertureRaster, PupilAreaConvergesToPiR2) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  ApertureRasterOptions options;
  options.grid_px = 256;
  options.aperture_width_mm = 8.0;
  options.supersampling = 4;
  const double area = total(rasterise_aperture(geometry, options));
  EXPECT_NEAR(area / (std::numbers::pi * 4.0), 1.0, 2e-3);
}

TEST(GlareApertureRaster, SubSampleRuleOnHandCheckedPixels) {
  // 4 x 4 grid over 4 mm (dx = 1 mm), s = 2: pixel (2, 2) has centre (0, 0) and sub-samples at
  // (+-0.25, +-0.25) mm. Pupil of diameter 0.8 mm: radius 0.4 > 0.354, so all four are inside.
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 0.8;
  ApertureRasterOptions options;
  options.grid_px = 4;
  options.aperture_width_mm = 4.0;
  auto grid = rasterise_aperture(geometry, options);
  EXPECT_DOUBLE_EQ(grid.transmittance[2 * 4 + 2], 1.0);
  EXPECT_DOUBLE_EQ(grid.transmittance[1 * 4 + 2], 0.0);  // pixel above: centre (0, 1)
  // Diameter 0.7 mm: radius 0.35 < 0.3536: no sub-sample inside.
  geometry.pupil_diameter_mm = 0.7;
  grid = rasterise_aperture(geometry, options);
  EXPECT_DOUBLE_EQ(grid.transmittance[2 * 4 + 2], 0.0);

  // Big pupil; a disc of radius 0.3 at (0.25, 0.25) with T = 0.5 contains sub-samples
  // (0.25, 0.25) [d=0], (-0.25, 0.25) and (0.25, -0.25) [d=0.5 > 0.3: no]: one of four.
  geometry.pupil_diameter_mm = 10.0;
  geometry.discs.push_back({0.25, 0.25, 0.3, 0.5});
  grid = rasterise_aperture(geometry, options);
  EXPECT_NEAR(grid.transmittance[2 * 4 + 2], (0.5 + 3.0) / 4.0, 1e-15);
  // Two overlapping discs multiply: T = 0.5 * 0.4 at that sub-sample.
  geometry.discs.push_back({0.25, 0.25, 0.1, 0.4});
  grid = rasterise_aperture(geometry, options);
  EXPECT_NEAR(grid.transmittance[2 * 4 + 2], (0.2 + 3.0) / 4.0, 1e-15);

  // A horizontal line y = -0.25 from x = -3 to 3, width 0.2 (half-width 0.1): covers the lower
  // two sub-samples of pixel (2, 2) (distance 0); opaque.
  geometry.discs.clear();
  geometry.lines.push_back({-3.0, -0.25, 3.0, -0.25, 0.2, 0.0});
  grid = rasterise_aperture(geometry, options);
  EXPECT_DOUBLE_EQ(grid.transmittance[2 * 4 + 2], 0.5);
  // Distance exactly half the width counts as inside (<=): width 1.0 about y = 0.25 reaches -0.25.
  geometry.lines[0] = {-3.0, 0.25, 3.0, 0.25, 1.0, 0.0};
  grid = rasterise_aperture(geometry, options);
  EXPECT_DOUBLE_EQ(grid.transmittance[2 * 4 + 2], 0.0);
}

TEST(GlareApertureRaster, PolygonEvenOdd) {
  // A self-overlapping "bow" that covers the square [-1, 1]^2 twice cancels there (even-odd):
  // two triangles sharing the centre region drawn as one polygon with a loop.
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 100.0;
  // Outer square [-1.5,1.5]^2 then inner square [-0.5,0.5]^2 traversed in the same polygon via a
  // slit: points inside the inner square are crossed twice -> outside by even-odd.
  geometry.polygons.push_back({{-1.5, -1.5, 1.5, -1.5, 1.5, 1.5, -1.5, 1.5, -1.5, -0.5, -0.5, -0.5, -0.5, 0.5, 0.5, 0.5, 0.5,
                                -0.5, -1.5, -0.5},
                               0.0});
  ApertureRasterOptions options;
  options.grid_px = 8;
  options.aperture_width_mm = 4.0;  // dx = 0.5, pixel (4, 4) centre (0, 0) inside the hole
  const auto grid = rasterise_aperture(geometry, options);
  EXPECT_DOUBLE_EQ(grid.transmittance[4 * 8 + 4], 1.0);  // hole: transmits
  EXPECT_DOUBLE_EQ(grid.transmittance[2 * 8 + 2], 0.0);  // centre (-1, 1): inside the ring: opaque
  EXPECT_DOUBLE_EQ(grid.transmittance[0], 1.0);           // centre (-2, 2): outside the polygon
  EXPECT_THROW(rasterise_aperture(geometry, {8, 4.0, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
