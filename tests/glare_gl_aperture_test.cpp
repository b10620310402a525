// The GPU aperture rasteriser against an independent CPU double implementation of the same coverage
// rule (written here from the rule's statement in glare/eye/aperture_raster.h): every subsample must
// agree, except subsamples whose point lies within a hair of some edge, where float and double
// coordinates may round to different sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "glare/eye/aperture_raster.h"
#include "glare/gl/aperture.h"
#include "runner/display/compute_context.h"
#include "core/random.h"

namespace glarelab {
namespace {

// Float coordinates of points up to 5 mm from the axis carry about 5 mm * 2^-24 = 3e-7 mm of
// rounding; the squared-distance tests add a few ulps more. 1e-6 mm is the band where the GPU may
// legitimately disagree with double precision.
constexpr double kEdgeBandMm = 1e-6;

struct CpuSample {
  double transmittance;
  double edge_distance_mm;  // distance from the point to the nearest primitive boundary
};

double distance_to_segment(double px, double py, double ax, double ay, double bx, double by) {
  const double abx = bx - ax, aby = by - ay;
  const double length_squared = abx * abx + aby * aby;
  const double t = length_squared > 0.0 ? std::clamp(((px - ax) * abx + (py - ay) * aby) / length_squared, 0.0, 1.0) : 0.0;
  return std::hypot(px - (ax + t * abx), py - (ay + t * aby));
}

CpuSample cpu_sample(const ApertureGeometry& g, double x, double y) {
  CpuSample sample{1.0, 1e300};
  const double r = std::hypot(x, y);
  sample.edge_distance_mm = std::abs(r - 0.5 * g.pupil_diameter_mm);
  if (r > 0.5 * g.pupil_diameter_mm) sample.transmittance = 0.0;
  for (const ApertureDisc& d : g.discs) {
    const double distance = std::hypot(x - d.centre_x_mm, y - d.centre_y_mm);
    sample.edge_distance_mm = std::min(sample.edge_distance_mm, std::abs(distance - d.radius_mm));
    if (distance <= d.radius_mm) sample.transmittance *= d.transmittance;
  }
  for (const ApertureLine& l : g.lines) {
    const double distance = distance_to_segment(x, y, l.x0_mm, l.y0_mm, l.x1_mm, l.y1_mm);
    sample.edge_distance_mm = std::min(sample.edge_distance_mm, std::abs(distance - 0.5 * l.width_mm));
    if (distance <= 0.5 * l.width_mm) sample.transmittance *= l.transmittance;
  }
  for (const AperturePolygon& polygon : g.polygons) {
    const auto& v = polygon.vertices_mm;
    const std::size_t count = v.size() / 2;
    bool inside = false;
    for (std::size_t i = 0, j = count - 1; i < count; j = i++) {
      const double xi = v[2 * i], yi = v[2 * i + 1], xj = v[2 * j], yj = v[2 * j + 1];
      sample.edge_distance_mm = std::min(sample.edge_distance_mm, distance_to_segment(x, y, xi, yi, xj, yj));
      if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) inside = !inside;
    }
    if (inside) sample.transmittance *= polygon.transmittance;
  }
  return sample;
}

ApertureGeometry busy_geometry() {
  const CounterRandom random(3, RandomStream::glare_gl_test_input);
  ApertureGeometry g;
  g.pupil_diameter_mm = 6.0;
  for (std::uint64_t i = 0; i < 150; ++i)  // more than one 64-primitive culling chunk
    g.discs.push_back({6.0 * random.uniform(i, 0) - 3.0, 6.0 * random.uniform(i, 1) - 3.0,
                       0.05 + 0.25 * random.uniform(i, 2), random.uniform(i, 3)});
  for (std::uint64_t i = 0; i < 70; ++i)
    g.lines.push_back({6.0 * random.uniform(300 + i, 0) - 3.0, 6.0 * random.uniform(300 + i, 1) - 3.0,
                       6.0 * random.uniform(300 + i, 2) - 3.0, 6.0 * random.uniform(300 + i, 3) - 3.0,
                       0.02 + 0.15 * random.uniform(400 + i, 0), 0.2 + 0.5 * random.uniform(400 + i, 1)});
  g.lines.push_back({1.0, 1.0, 1.0, 1.0, 0.6, 0.5});  // a degenerate segment: a disc of radius width/2
  // A pentagram: under the even-odd rule its central pentagon is outside.
  AperturePolygon star;
  for (int k = 0; k < 5; ++k) {
    const double angle = std::numbers::pi / 2 + 2.0 * std::numbers::pi * (2 * k % 5) / 5.0;
    star.vertices_mm.push_back(-1.2 + 1.4 * std::cos(angle));
    star.vertices_mm.push_back(0.8 + 1.4 * std::sin(angle));
  }
  star.transmittance = 0.25;
  g.polygons.push_back(star);
  // An eyelid-like concave polygon across the top of the pupil.
  g.polygons.push_back({{-4.0, 4.0, 4.0, 4.0, 4.0, 2.0, 0.0, 2.6, -4.0, 1.8}, 0.0});
  return g;
}

class GlApertureTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = gl::create_compute_context(); }
  static void TearDownTestSuite() { context_.reset(); }
  static std::unique_ptr<DisplayBackend> context_;
};
std::unique_ptr<DisplayBackend> GlApertureTest::context_;

TEST_F(GlApertureTest, EverySubsampleMatchesTheCpuCoverageRule) {
  const int n = 128, s = 3;
  const double width_mm = 10.0;
  const ApertureGeometry geometry = busy_geometry();
  gl::GlAperture aperture(n, width_mm, s);
  aperture.draw(geometry);
  const std::vector<float> samples = aperture.read_supersampled();
  const std::vector<float> pixels = aperture.read();
  const int across = n * s;
  const double h = width_mm / across;
  std::vector<double> cpu(samples.size());
  int mismatches = 0, near_edge_mismatches = 0, partially_covered = 0;
  for (int b = 0; b < across; ++b)
    for (int a = 0; a < across; ++a) {
      // glare/eye/aperture_raster.h: sub-sample a' of pixel i at x = (i - N/2 - 1/2 + (a' + 1/2) / s) dx, so with
      // a = s i + a' the point is (a + 1/2 - (S + s) / 2) h; rows alike, y pointing up.
      const double axis = (across + s) / 2.0;
      const double x = (a + 0.5 - axis) * h, y = (axis - b - 0.5) * h;
      const CpuSample expected = cpu_sample(geometry, x, y);
      const std::size_t index = static_cast<std::size_t>(b) * across + a;
      cpu[index] = expected.transmittance;
      if (std::abs(samples[index] - expected.transmittance) > 1e-6) {
        ++mismatches;
        if (expected.edge_distance_mm <= kEdgeBandMm) ++near_edge_mismatches;
        else
          ADD_FAILURE() << "subsample " << a << "," << b << " at (" << x << ", " << y << ") mm: GPU " << samples[index]
                        << ", CPU " << expected.transmittance << ", " << expected.edge_distance_mm << " mm from an edge";
      }
      if (expected.transmittance > 0.0 && expected.transmittance < 1.0) ++partially_covered;
    }
  std::ostringstream figures;
  figures << mismatches << " of " << samples.size() << " (" << near_edge_mismatches << " within 1e-6 mm of an edge)";
  RecordProperty("subsample_mismatches", figures.str());
  EXPECT_GT(partially_covered, 10000) << "the geometry must exercise the primitives";

  // The downsampled texels are box means of the subsamples.
  double worst = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      double mean = 0.0;
      for (int dy = 0; dy < s; ++dy)
        for (int dx = 0; dx < s; ++dx) mean += cpu[static_cast<std::size_t>(j * s + dy) * across + (i * s + dx)];
      mean /= s * s;
      worst = std::max(worst, std::abs(pixels[static_cast<std::size_t>(j) * n + i] - mean));
    }
  EXPECT_LE(worst, near_edge_mismatches > 0 ? 1.0 / (s * s) + 1e-6 : 1e-6);
}

TEST_F(GlApertureTest, PupilsMatchTheCpuRasteriserPixelForPixel) {
  // The CPU rasteriser (glare/eye/aperture_raster.cpp) is the other backend's aperture: the two must put
  // the optical axis on the same pixel centre, or the PSFs differ by a half-pixel shift (error ~1/N).
  for (const int n : {256, 1024})
    for (const double pupil_mm : {1.5, 2.42649, 9.0}) {
      ApertureGeometry geometry;
      geometry.pupil_diameter_mm = pupil_mm;
      geometry.discs.push_back({1.25, -0.5, 0.3, 0.25});
      gl::GlAperture aperture(n, 10.0, 2);
      aperture.draw(geometry);
      const std::vector<float> gpu = aperture.read();
      ApertureRasterOptions options;
      options.grid_px = n;
      const ApertureGrid cpu = rasterise_aperture(geometry, options);
      int differing = 0;
      for (std::size_t k = 0; k < gpu.size(); ++k) differing += std::abs(gpu[k] - cpu.transmittance[k]) > 1e-6;
      EXPECT_EQ(differing, 0) << n << " px, pupil " << pupil_mm << " mm";
    }
}

TEST_F(GlApertureTest, PupilAreaAndOrientation) {
  const int n = 256;
  const double width_mm = 8.0;
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 5.0;
  // An opaque disc in the upper right quadrant: it must land right of centre and in the top half.
  geometry.discs.push_back({1.5, 1.0, 0.5, 0.0});
  gl::GlAperture aperture(n, width_mm, 2);
  aperture.draw(geometry);
  const std::vector<float> pixels = aperture.read();
  double area_mm2 = 0.0;
  for (const float value : pixels) area_mm2 += value * aperture.pixel_size_mm() * aperture.pixel_size_mm();
  const double expected_mm2 = std::numbers::pi * (2.5 * 2.5 - 0.5 * 0.5);
  EXPECT_NEAR(area_mm2 / expected_mm2, 1.0, 2e-3);
  const auto at = [&](double x_mm, double y_mm) {
    const int i = static_cast<int>(std::floor(x_mm / aperture.pixel_size_mm() + n / 2.0));
    const int j = static_cast<int>(std::floor(n / 2.0 - y_mm / aperture.pixel_size_mm()));
    return pixels[static_cast<std::size_t>(j) * n + i];
  };
  EXPECT_EQ(at(1.5, 1.0), 0.0f);
  EXPECT_EQ(at(-1.5, 1.0), 1.0f);
  EXPECT_EQ(at(1.5, -1.0), 1.0f);
  EXPECT_EQ(at(3.0, 0.0), 0.0f);
}

TEST_F(GlApertureTest, RefusesBadGrids) {
  EXPECT_THROW(gl::GlAperture(256, 8.0, 1), std::invalid_argument);
  EXPECT_THROW(gl::GlAperture(8, 8.0, 2), std::invalid_argument);
  EXPECT_THROW(gl::GlAperture(256, 0.0, 2), std::invalid_argument);
  gl::GlAperture aperture(64, 8.0, 2);
  ApertureGeometry odd;
  odd.polygons.push_back({{0.0, 0.0, 1.0}, 0.5});
  EXPECT_THROW(aperture.draw(odd), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
