// The aperture coverage rule (glare/eye/aperture_raster.h) on hand-checked cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "glare/eye/aperture_raster.h"
#include "glare/eye/eye_model.h"
#include "tests/aperture_rule.h"

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

// The rasteriser against the rule sub-sample by sub-sample (tests/aperture_rule.h), which it must
// equal bit for bit: its row spans only skip sub-samples that cannot pass a test.
void expect_bit_identical(const ApertureGrid& fast, const std::vector<double>& reference, const char* what) {
  ASSERT_EQ(fast.transmittance.size(), reference.size());
  std::size_t differing = 0, covered = 0;
  for (std::size_t k = 0; k < reference.size(); ++k) {
    if (fast.transmittance[k] != reference[k]) ++differing;
    if (reference[k] > 0.0 && reference[k] < 1.0) ++covered;
  }
  EXPECT_EQ(differing, 0u) << what;
  EXPECT_GT(covered, 100u) << what << ": the case must have partly covered pixels to be a test";
}

// Long thin lines at every angle (horizontal, vertical, near-horizontal, zero length), lines and
// discs whose edges fall on sub-sample centres, and particles straddling the pupil's edge.
TEST(GlareApertureRaster, RowSpansGiveTheGridOfEverySubSampleOnHardCases) {
  const int n = 64, s = 3;
  const double width_mm = 8.0, sub = width_mm / n / s;
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 7.0;
  std::mt19937_64 random(12345);  // a fixed test case, not a random choice of the product
  std::uniform_real_distribution<double> position(-4.0, 4.0), unit(0.0, 1.0);
  for (int k = 0; k < 60; ++k) {
    const double angle = std::numbers::pi * unit(random), length = 6.0 * unit(random);
    const double cx = position(random), cy = position(random);
    geometry.lines.push_back({cx - 0.5 * length * std::cos(angle), cy - 0.5 * length * std::sin(angle),
                              cx + 0.5 * length * std::cos(angle), cy + 0.5 * length * std::sin(angle),
                              0.4 * sub + 0.3 * unit(random), 0.9 * unit(random)});
  }
  geometry.lines.push_back({-3.0, 0.5 * sub, 3.0, 0.5 * sub, 2.0 * sub, 0.5});     // horizontal, edge on samples
  geometry.lines.push_back({1.5 * sub, -3.0, 1.5 * sub, 3.0, 1.0 * sub, 0.25});    // vertical
  geometry.lines.push_back({-3.0, 0.2, 3.0, 0.2 + 1e-9, 0.05, 0.0});              // nearly horizontal
  geometry.lines.push_back({0.7, 0.7, 0.7, 0.7, 0.3, 0.0});                       // zero length: a disc
  for (int k = 0; k < 80; ++k)
    geometry.discs.push_back({position(random), position(random), 0.5 * unit(random), 0.8 * unit(random)});
  geometry.discs.push_back({0.5 * sub, 0.5 * sub, 2.0 * sub, 0.5});  // edge through sample centres
  geometry.discs.push_back({3.5, 0.0, 0.4, 0.0});                    // across the pupil's edge
  // The rasteriser lists the discs per pixel row: one far off the grid (on no row), one over the
  // whole pupil (on every row), one whose top edge meets the pupil's first sub-row.
  geometry.discs.push_back({0.0, 1e12, 1.0, 0.5});
  geometry.discs.push_back({0.0, 0.0, 100.0, 0.9});
  geometry.discs.push_back({0.0, -3.6, 0.1 + 0.5 * sub, 0.3});
  geometry.polygons.push_back({{-4.0, 2.5, 4.0, 2.0, 4.0, 4.0, -4.0, 4.0}, 0.0});
  for (const int threads : {1, 3}) {
    const ApertureGrid fast = rasterise_aperture(geometry, {n, width_mm, s, threads});
    expect_bit_identical(fast, test::rasterise_by_the_rule(geometry, n, width_mm, s), "hard cases");
  }
}

// The eye model's own aperture (particles, fibre gratings reaching into a wide pupil, lids).
TEST(GlareApertureRaster, RowSpansGiveTheGridOfEverySubSampleForTheEyeModel) {
  EyeParameters parameters;
  parameters.initial_field_luminance_cd_m2 = 0.01;  // a wide pupil, so the gratings reach into it
  const ApertureGeometry geometry = EyeModel(parameters, 7).geometry_at(1.0);
  ASSERT_GT(geometry.lines.size(), 10u);
  ASSERT_GT(geometry.discs.size(), 10u);
  const ApertureGrid fast = rasterise_aperture(geometry, {128, 10.0, 2, 2});
  expect_bit_identical(fast, test::rasterise_by_the_rule(geometry, 128, 10.0, 2), "eye model");
}

TEST(GlareApertureRaster, AReusedGridHoldsOnlyTheNewAperture) {
  // A reused grid is cleared only where the last call wrote: a wide pupil, then a narrow one, then
  // none, then one again, each compared with a fresh grid (and with the rule) bit for bit.
  const EyeModel eye(EyeParameters{}, 3);
  ApertureRasterOptions options;
  options.grid_px = 128;
  options.aperture_width_mm = 10.0;
  ApertureGrid reused;
  for (const double pupil_mm : {8.0, 4.0, 0.0, 6.0}) {
    ApertureGeometry geometry = eye.geometry_at(2.0);
    geometry.pupil_diameter_mm = pupil_mm;
    rasterise_aperture(geometry, options, reused);
    const ApertureGrid fresh = rasterise_aperture(geometry, options);
    EXPECT_EQ(reused.transmittance, fresh.transmittance) << pupil_mm << " mm";
    if (pupil_mm > 0.0) expect_bit_identical(reused, test::rasterise_by_the_rule(geometry, 128, 10.0, 2), "reused grid");
  }
  // A grid written by hand is marked whole, and cleared whole.
  ApertureGrid by_hand;
  by_hand.grid_px = 128;
  by_hand.aperture_width_mm = 10.0;
  by_hand.transmittance.assign(128 * 128, 1.0);
  ApertureGeometry narrow = eye.geometry_at(2.0);
  narrow.pupil_diameter_mm = 2.0;
  rasterise_aperture(narrow, options, by_hand);
  EXPECT_EQ(by_hand.transmittance, rasterise_aperture(narrow, options).transmittance);
}

}  // namespace
}  // namespace glarelab
