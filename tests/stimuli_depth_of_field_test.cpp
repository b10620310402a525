// The depth-of-field stage (Kakimoto et al. 2007, Eqs. 8-9): each pixel blurred by the geometric
// blur of its own depth, by depth layers composited far to near. Checked against closed forms (the
// ellipse's area, second moments and orientation), a direct convolution written out here, the
// layer rule worked by hand and the per-pixel reference.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>

#include "core/exr_io.h"
#include "stimuli/depth_layers.h"
#include "stimuli/depth_of_field.h"
#include "stimuli/depth_of_field_blur.h"
#include "stimuli/depth_of_field_reference.h"
#include "stimuli/depth_of_field_rows.h"
#include "stimuli/depth_of_field_tiles.h"
#include "stimuli/display_model.h"
#include "stimuli/elliptical_kernel.h"
#include "stimuli/scene_depth.h"

namespace glarelab {
namespace {

using ::testing::HasSubstr;

constexpr double kPupilRadiusM = 0.002;
// 1 mrad a pixel: with a 2 mm pupil radius a dioptre of error moves a ray by 2 px.
const double kDegreesPerPixel = 1e-3 * 180.0 / std::numbers::pi;
constexpr double kPixelsPerDioptre = 2.0;

// An emmetrope accommodated at accommodated_m, plus a constant astigmatism.
EyeErrorAtDistance emmetrope(double accommodated_m, const DioptricPower& astigmatism = {}) {
  return [=](double distance_m) {
    return DioptricPower::spherical(1.0 / accommodated_m - 1.0 / distance_m) + astigmatism;
  };
}

DepthOfFieldSettings settings_for(const EyeErrorAtDistance& error, int threads = 1) {
  DepthOfFieldSettings settings;
  settings.degrees_per_pixel = kDegreesPerPixel;
  settings.pupil_radius_m = kPupilRadiusM;
  settings.residual_error = error;
  settings.threads = threads;
  return settings;
}

// A texture with detail at every scale the kernels reach, different in each channel.
ImageRGBA textured(int width, int height) {
  ImageRGBA image(width, height, 1.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      const double checker = ((x / 5 + y / 3) % 2 == 0) ? 40.0 : 5.0;
      p[0] = static_cast<float>(checker + 10.0 * std::sin(0.7 * x) * std::cos(0.45 * y) + 12.0);
      p[1] = static_cast<float>(0.5 * checker + 3.0 * std::sin(0.23 * x + 0.31 * y) + 4.0);
      p[2] = static_cast<float>(((x * 7 + y * 13) % 11) * 2.0);
    }
  return image;
}

std::vector<float> flat_depth(int width, int height, float depth_m) {
  return std::vector<float>(static_cast<std::size_t>(width) * height, depth_m);
}

// The image's R, G, B where `keep` holds, zero elsewhere, convolved with the kernel (double).
template <typename Keep>
std::vector<double> convolve_masked(const ImageRGBA& image, const EllipticalKernel& kernel, Keep keep) {
  std::vector<double> out(3 * static_cast<std::size_t>(image.width_px) * image.height_px, 0.0);
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x)
      for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy)
        for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx) {
          const int sx = x - dx, sy = y - dy;
          if (sx < 0 || sy < 0 || sx >= image.width_px || sy >= image.height_px || !keep(sx, sy)) continue;
          for (int c = 0; c < 3; ++c)
            out[3 * (static_cast<std::size_t>(y) * image.width_px + x) + c] +=
                kernel.at(dx, dy) * image.pixel(sx, sy)[c];
        }
  return out;
}

// Second moments of an image's R about its centroid, in image coordinates (y down).
struct Moments {
  double sum = 0, mean_x = 0, mean_y = 0, xx = 0, yy = 0, xy = 0;
};
Moments moments_of(const ImageRGBA& image) {
  Moments m;
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x) {
      const double v = image.pixel(x, y)[0];
      m.sum += v;
      m.mean_x += v * x;
      m.mean_y += v * y;
    }
  m.mean_x /= m.sum;
  m.mean_y /= m.sum;
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x) {
      const double v = image.pixel(x, y)[0] / m.sum;
      m.xx += v * (x - m.mean_x) * (x - m.mean_x);
      m.yy += v * (y - m.mean_y) * (y - m.mean_y);
      m.xy += v * (x - m.mean_x) * (y - m.mean_y);
    }
  return m;
}

// ---- The kernel ----------------------------------------------------------------------------

TEST(DepthOfFieldKernelTest, EllipseInPixelsIsGeometricBlurOverTheRadiansOfAPixel) {
  // 2 D of myopic defocus with -1 D cylinder: principal errors 2 and 1 D -> 4 and 2 px.
  const DioptricPower error = DioptricPower::spherical(2.0) + DioptricPower::from_prescription({0.0, -1.0, 90.0});
  const PixelBlurEllipse ellipse = pixel_blur_ellipse(error, kPupilRadiusM, kDegreesPerPixel);
  EXPECT_NEAR(ellipse.semi_major_px, 2.0 * kPixelsPerDioptre, 1e-9);
  EXPECT_NEAR(ellipse.semi_minor_px, 1.0 * kPixelsPerDioptre, 1e-9);
  // TABO 90: the cylinder axis is vertical; the cylinder's -1 D acts across it (horizontally), so
  // the larger error (2 D) is along the vertical.
  EXPECT_NEAR(ellipse.major_axis_angle_deg, 90.0, 1e-9);
}

TEST(DepthOfFieldKernelTest, KernelCoversTheClosedFormAreaAndSumsToOne) {
  for (const PixelBlurEllipse& ellipse :
       {PixelBlurEllipse{6.0, 2.0, 45.0}, PixelBlurEllipse{9.5, 9.5, 0.0}, PixelBlurEllipse{7.0, 3.0, 120.0}}) {
    const EllipticalKernel kernel = elliptical_kernel(ellipse);
    const double area = std::numbers::pi * ellipse.semi_major_px * ellipse.semi_minor_px;
    EXPECT_NEAR(kernel.covered_area_px2, area, 0.01 * area) << ellipse.semi_major_px;
    double sum = 0;
    for (double w : kernel.weights) sum += w;
    EXPECT_NEAR(sum, 1.0, 1e-12);
    // Point symmetric, as an ellipse about its centre is.
    for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy)
      for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx)
        ASSERT_DOUBLE_EQ(kernel.at(dx, dy), kernel.at(-dx, -dy));
  }
}

TEST(DepthOfFieldKernelTest, ObserverUpIsImageRowsUpward) {
  // A line focus along 30 degrees in the observer frame (up and to the right): on the image it
  // runs to the right and to rows ABOVE the centre (dy < 0).
  const EllipticalKernel kernel = elliptical_kernel(PixelBlurEllipse{8.0, 0.0, 30.0});
  EXPECT_GT(kernel.at(6, -3), 0.0);  // (6.9, 4) * 0.87 along the line, 30 degrees up
  EXPECT_EQ(kernel.at(6, 3), 0.0);   // its mirror image below is dark
  EXPECT_GT(kernel.at(-6, 3), 0.0);  // the other half of the line
  EXPECT_EQ(kernel.at(-6, -3), 0.0);
  // The light stays on the line: no tap more than a pixel from it.
  for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy)
    for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx)
      if (kernel.at(dx, dy) > 0.0) {
        EXPECT_LT(std::abs(-dx * std::sin(std::numbers::pi / 6) - dy * std::cos(std::numbers::pi / 6)), 1.0);
      }
}

TEST(DepthOfFieldKernelTest, EllipseInsideItsPixelIsTheIdentity) {
  const EllipticalKernel kernel = elliptical_kernel(PixelBlurEllipse{0.4, 0.1, 60.0});
  EXPECT_EQ(kernel.width(), 1);
  EXPECT_EQ(kernel.height(), 1);
  EXPECT_EQ(kernel.at(0, 0), 1.0);
}

// ---- Layers ----------------------------------------------------------------------------------

TEST(DepthOfFieldLayersTest, FlatSceneIsOneLayer) {
  const DepthLayerPlan plan =
      plan_depth_layers(flat_depth(40, 30, 0.8f), BlurGeometry{kDegreesPerPixel, kPupilRadiusM}, emmetrope(0.5));
  ASSERT_EQ(plan.layers.size(), 1u);
  EXPECT_EQ(plan.layers[0].pixel_count, 1200u);
  EXPECT_EQ(plan.layers[0].max_blur_error_px, 0.0);
  // 1 / 0.5 - 1 / 0.8 = 0.75 D -> 1.5 px.
  EXPECT_NEAR(plan.layers[0].ellipse.semi_major_px, 0.75 * kPixelsPerDioptre, 1e-6);
  EXPECT_TRUE(plan.layers[0].blurred);
}

TEST(DepthOfFieldLayersTest, RampNeedsTheLayersTheRulePredicts) {
  // Row y at vergence 1 + y delta, with delta so that 3 steps stay within the rule's span of
  // 2 x 0.25 px = 0.25 D (at 2 px/D) and 4 steps do not: 4 rows a layer, ceil(30 / 4) = 8 layers.
  // The middle of a 4-row layer is 1.5 delta from its ends: a blur error of 1.5 delta 2 px/D.
  const int width = 10, height = 30;
  const double delta = 0.25 / 3.5;
  std::vector<float> depth(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      depth[static_cast<std::size_t>(y) * width + x] = static_cast<float>(1.0 / (1.0 + y * delta));
  const DepthLayerPlan plan = plan_depth_layers(depth, BlurGeometry{kDegreesPerPixel, kPupilRadiusM}, emmetrope(0.4));
  ASSERT_EQ(plan.layers.size(), 8u);
  double largest_error = 0.0;
  for (std::size_t k = 0; k < plan.layers.size(); ++k) {
    EXPECT_EQ(plan.layers[k].pixel_count, k + 1 < plan.layers.size() ? 40u : 20u) << k;
    largest_error = std::max(largest_error, plan.layers[k].max_blur_error_px);
    if (k > 0) {
      EXPECT_GT(plan.layers[k].far_vergence_dioptres, plan.layers[k - 1].near_vergence_dioptres);
    }
  }
  EXPECT_NEAR(largest_error, 1.5 * delta * kPixelsPerDioptre, 1e-5);
  EXPECT_LE(largest_error, kDefaultLayerTolerancePx);
  // Rows 0-3 are the farthest layer (vergence ascends down the image); row 29 the nearest.
  EXPECT_EQ(plan.layer_of_pixel[3 * width], 0u);
  EXPECT_EQ(plan.layer_of_pixel[4 * width], 1u);
  EXPECT_EQ(plan.layer_of_pixel[29 * width + 9], 7u);
  // Blending: the middles of neighbouring 4-row layers are 4 delta = 0.57 px apart (<= 4 x 0.25 px),
  // so each pixel shares its light with the layer on its side of its own layer's middle, by the
  // fraction of the way to that middle: row 2 (2 delta, middle 1.5 delta, next 5.5 delta) gives
  // 0.5 / 4 = 0.125 to layer 1, row 3 gives 1.5 / 4 = 0.375, row 4 (layer 1) gives 0.375 to layer 0;
  // rows 0 and 1 lie beyond the first middle with no layer farther away, and keep all of it.
  const auto share = [&](int row) { return plan.blend_weight[static_cast<std::size_t>(row) * width + 5]; };
  const auto partner = [&](int row) { return plan.blend_layer_of_pixel[static_cast<std::size_t>(row) * width + 5]; };
  EXPECT_EQ(share(0), 0.0f);
  EXPECT_EQ(partner(0), 0u);
  EXPECT_EQ(share(1), 0.0f);
  EXPECT_NEAR(share(2), 0.125, 1e-5);
  EXPECT_EQ(partner(2), 1u);
  EXPECT_NEAR(share(3), 0.375, 1e-5);
  EXPECT_NEAR(share(4), 0.375, 1e-5);
  EXPECT_EQ(partner(4), 0u);
  EXPECT_NEAR(share(5), 0.125, 1e-5);
  // Accommodated at 0.4 m (2.5 D): the layer whose middle is within 0.125 D of it (blur <= 0.25 px)
  // is passed through: rows 20-23 span 2.43-2.64 D, middle 2.536 D, 0.036 D -> 0.07 px.
  EXPECT_FALSE(plan.layers[5].blurred);
  EXPECT_TRUE(plan.layers[4].blurred);
  EXPECT_TRUE(plan.layers[6].blurred);
}

TEST(DepthOfFieldLayersTest, LayersDoNotDependOnWherePixelsLie) {
  // The same 1200 depths (each its own value, 0.3 to 3 m, some repeated) in row order and scattered
  // by a permutation: the layers (ranges, blurs, pixel counts) must be the same, and each pixel
  // must land in the layer whose range holds its vergence.
  const std::size_t count = 1200;
  std::vector<float> ordered(count), scattered(count);
  for (std::size_t k = 0; k < count; ++k)
    ordered[k] = static_cast<float>(0.3 + 2.7 * static_cast<double>(k % 1000) / 999.0);
  for (std::size_t k = 0; k < count; ++k) scattered[(k * 7919) % count] = ordered[k];
  const BlurGeometry geometry{kDegreesPerPixel, kPupilRadiusM};
  const DepthLayerPlan a = plan_depth_layers(ordered, geometry, emmetrope(0.7));
  const DepthLayerPlan b = plan_depth_layers(scattered, geometry, emmetrope(0.7), kDefaultLayerTolerancePx, 3);
  ASSERT_EQ(a.layers.size(), b.layers.size());
  for (std::size_t k = 0; k < a.layers.size(); ++k) {
    EXPECT_EQ(a.layers[k].far_vergence_dioptres, b.layers[k].far_vergence_dioptres);
    EXPECT_EQ(a.layers[k].near_vergence_dioptres, b.layers[k].near_vergence_dioptres);
    EXPECT_EQ(a.layers[k].pixel_count, b.layers[k].pixel_count);
  }
  for (std::size_t k = 0; k < count; ++k) {
    const DepthLayer& layer = b.layers[b.layer_of_pixel[k]];
    const double v = 1.0 / static_cast<double>(scattered[k]);
    EXPECT_GE(v, layer.far_vergence_dioptres);
    EXPECT_LE(v, layer.near_vergence_dioptres);
  }
}

TEST(DepthOfFieldLayersTest, RowRunsHoldEachPixelsPlanValues) {
  // Rows of a receding ramp with repeated depths, a board of one depth across some of them and runs
  // of depths that blend: the runs' form must give every pixel the per-pixel plan's layer, blend
  // layer and weight, with the same layers and counts, on 1 and 3 threads; runs cover each row in
  // order and two neighbours never hold the same values.
  const int width = 37, height = 23;
  std::vector<float> depth(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const bool board = x >= 9 && x < 20 && y >= 5 && y < 15;
      depth[static_cast<std::size_t>(y) * width + x] =
          board ? 0.45f : static_cast<float>(1.0 / (0.3 + 0.05 * y + 0.01 * (x / 4)));
    }
  const BlurGeometry geometry{kDegreesPerPixel, kPupilRadiusM};
  const DepthLayerPlan plan = plan_depth_layers(depth, geometry, emmetrope(0.6));
  bool blends = false;
  for (const float w : plan.blend_weight) blends = blends || w != 0.0f;
  ASSERT_TRUE(blends);
  for (const int threads : {1, 3}) {
    DepthLayerPlan run_plan;
    std::vector<std::vector<PixelRun>> runs;
    plan_depth_layer_runs(depth, width, height, geometry, emmetrope(0.6), kDefaultLayerTolerancePx, threads, run_plan,
                          runs);
    ASSERT_EQ(run_plan.layers.size(), plan.layers.size());
    for (std::size_t k = 0; k < plan.layers.size(); ++k)
      EXPECT_EQ(run_plan.layers[k].pixel_count, plan.layers[k].pixel_count) << k;
    EXPECT_TRUE(run_plan.layer_of_pixel.empty());
    ASSERT_EQ(runs.size(), static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y) {
      int x = 0;
      for (std::size_t r = 0; r < runs[static_cast<std::size_t>(y)].size(); ++r) {
        const PixelRun& run = runs[static_cast<std::size_t>(y)][r];
        ASSERT_EQ(run.first, x) << y;
        ASSERT_GT(run.end, run.first) << y;
        if (r > 0) {
          const PixelRun& before = runs[static_cast<std::size_t>(y)][r - 1];
          EXPECT_FALSE(before.own == run.own && before.blended == run.blended && before.blend_weight == run.blend_weight);
        }
        for (; x < run.end; ++x) {
          const std::size_t k = static_cast<std::size_t>(y) * width + x;
          ASSERT_EQ(run.own, plan.layer_of_pixel[k]) << x << " " << y;
          ASSERT_EQ(run.blended, plan.blend_layer_of_pixel[k]) << x << " " << y;
          ASSERT_EQ(run.blend_weight, plan.blend_weight[k]) << x << " " << y;
        }
      }
      EXPECT_EQ(x, width) << y;
    }
  }
  DepthLayerPlan run_plan;
  std::vector<std::vector<PixelRun>> runs;
  EXPECT_THROW(plan_depth_layer_runs(depth, width + 1, height, geometry, emmetrope(0.6), kDefaultLayerTolerancePx, 1,
                                     run_plan, runs),
               std::invalid_argument);
  // A bad depth is refused with the per-pixel plan's message, naming the first one in row order.
  const auto message = [](const auto& plan_it) -> std::string {
    try {
      plan_it();
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "(accepted)";
  };
  for (const float bad : {std::nanf(""), -1.0f, 0.0f, -std::numeric_limits<float>::infinity()}) {
    std::vector<float> bad_depth = depth;
    bad_depth[static_cast<std::size_t>(17) * width + 30] = bad;
    bad_depth[static_cast<std::size_t>(6) * width + 12] = bad;  // on the board: the first
    const std::string expected = message([&] { plan_depth_layers(bad_depth, geometry, emmetrope(0.6)); });
    EXPECT_THAT(expected, HasSubstr("at index " + std::to_string(6 * width + 12) + " "));
    for (const int threads : {1, 3})
      EXPECT_EQ(message([&] {
                  plan_depth_layer_runs(bad_depth, width, height, geometry, emmetrope(0.6), kDefaultLayerTolerancePx,
                                        threads, run_plan, runs);
                }),
                expected);
  }
}

TEST(DepthOfFieldLayersTest, PlanesFarApartInBlurDoNotBlend) {
  // 0.25 m and 1 m: 3 D, 6 px of blur apart (> 4 x 0.25 px): each plane keeps its own kernel.
  std::vector<float> depth = flat_depth(10, 4, 1.0f);
  for (std::size_t k = 0; k < 20; ++k) depth[k] = 0.25f;
  const DepthLayerPlan plan = plan_depth_layers(depth, BlurGeometry{kDegreesPerPixel, kPupilRadiusM}, emmetrope(0.5));
  ASSERT_EQ(plan.layers.size(), 2u);
  for (std::size_t k = 0; k < depth.size(); ++k) {
    EXPECT_EQ(plan.blend_weight[k], 0.0f);
    EXPECT_EQ(plan.blend_layer_of_pixel[k], plan.layer_of_pixel[k]);
  }
}

TEST(DepthOfFieldLayersTest, InfinityIsTheFarthestVergence) {
  std::vector<float> depth = flat_depth(4, 1, 2.0f);
  depth[2] = std::numeric_limits<float>::infinity();
  const DepthLayerPlan plan = plan_depth_layers(depth, BlurGeometry{kDegreesPerPixel, kPupilRadiusM}, emmetrope(2.0));
  ASSERT_EQ(plan.layers.size(), 2u);  // 0 D and 0.5 D: 1 px apart
  EXPECT_EQ(plan.layers[0].far_vergence_dioptres, 0.0);
  EXPECT_EQ(plan.layer_of_pixel[2], 0u);
  EXPECT_NEAR(plan.layers[0].ellipse.semi_major_px, 0.5 * kPixelsPerDioptre, 1e-12);  // 1/2 - 0 D
  EXPECT_FALSE(plan.layers[1].blurred);                                               // in focus
}

// ---- The stage -------------------------------------------------------------------------------

TEST(DepthOfFieldTest, PlaneAtTheAccommodatedDistanceStaysSharp) {
  const ImageRGBA image = textured(50, 40);
  DepthOfFieldReport report;
  const ImageRGBA result = apply_depth_of_field(image, flat_depth(50, 40, 0.6f), settings_for(emmetrope(0.6)), &report);
  EXPECT_EQ(report.layers, 1);
  EXPECT_EQ(report.blurred_layers, 0);
  EXPECT_EQ(result.rgba, image.rgba);
}

TEST(DepthOfFieldTest, SceneWithoutZIsAPictureAtTheViewingDistance) {
  // A scene file without Z sits on the display, 600 mm away: an eye focused on the display sees it
  // sharp; one focused at 0.4 m has 1/0.4 - 1/0.6 = 0.83 D of error on all of it: one layer.
  DisplaySpec display;
  display.viewing_distance_mm = 600.0;
  const ImageRGBA image = textured(40, 30);
  const std::vector<float> depth = scene_depth_m(image, "picture.exr", display);
  DepthOfFieldSettings settings = settings_for(emmetrope(0.6));
  settings.degrees_per_pixel = DisplayModel(display).degrees_per_pixel_at_centre();
  EXPECT_EQ(apply_depth_of_field(image, depth, settings).rgba, image.rgba);
  settings.residual_error = emmetrope(0.4);
  DepthOfFieldReport report;
  const ImageRGBA blurred = apply_depth_of_field(image, depth, settings, &report);
  EXPECT_EQ(report.layers, 1);
  EXPECT_EQ(report.blurred_layers, 1);
  EXPECT_NE(blurred.rgba, image.rgba);
}

TEST(DepthOfFieldTest, PointSpreadsIntoTheClosedFormEllipse) {
  // Accommodated at 0.5 m (2 D), the point at 1 m (1 D): 1 D of myopic defocus, plus -4 D
  // cylinder at TABO 45. The axis runs at 180 - 45 = 135 degrees in the observer frame, the
  // cylinder's power across it, along n at 45 degrees: E = I - 4 n n^T, errors -3 D along n and
  // 1 D across. Semi-axes 3 and 1 D x r_p / (1 mrad) = 6 and 2 px, major axis at 45 degrees up
  // and to the right: on the image, to the right and up (rows decreasing).
  const double a = 6.0, b = 2.0;
  const int size = 41, centre = 20;
  ImageRGBA image(size, size, 0.0f);
  image.pixel(centre, centre)[0] = 1000.0f;
  image.pixel(centre, centre)[1] = 500.0f;
  const DioptricPower cylinder = DioptricPower::from_prescription({0.0, -4.0, 45.0});
  DepthOfFieldReport report;
  const ImageRGBA result =
      apply_depth_of_field(image, flat_depth(size, size, 1.0f), settings_for(emmetrope(0.5, cylinder)), &report);
  EXPECT_EQ(report.layers, 1);
  EXPECT_EQ(report.blurred_layers, 1);
  const Moments m = moments_of(result);
  EXPECT_NEAR(m.sum, 1000.0, 1000.0 * 1e-5);  // energy conserved
  EXPECT_NEAR(m.mean_x, centre, 1e-4);
  EXPECT_NEAR(m.mean_y, centre, 1e-4);
  // A uniform ellipse has covariance R diag(a^2, b^2) R^T / 4; R at -45 degrees on the image.
  // Pixel coverage moves light to pixel centres, which adds the variance of the rounding, 1/12 px^2,
  // to each variance and nothing to the covariance (Sheppard's correction).
  EXPECT_NEAR(m.xx, (a * a + b * b) / 8.0 + 1.0 / 12.0, 0.1);
  EXPECT_NEAR(m.yy, (a * a + b * b) / 8.0 + 1.0 / 12.0, 0.1);
  EXPECT_NEAR(m.xy, -(a * a - b * b) / 8.0, 0.1);
  const double orientation_deg = 0.5 * std::atan2(2.0 * m.xy, m.xx - m.yy) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(orientation_deg, -45.0, 0.5);  // image frame: -45 is up and to the right
  // Axes: the covariance's eigenvalues, less the rounding variance, are a^2 / 4 and b^2 / 4.
  const double mean_variance = 0.5 * (m.xx + m.yy) - 1.0 / 12.0;
  const double spread = std::hypot(0.5 * (m.xx - m.yy), m.xy);
  EXPECT_NEAR(2.0 * std::sqrt(mean_variance + spread), a, 0.05 * a);
  EXPECT_NEAR(2.0 * std::sqrt(mean_variance - spread), b, 0.05 * b);
  // Area: a uniform ellipse's covariance has determinant (a b / 4)^2, so pi a b = 4 pi sqrt(det).
  const double det = (m.xx - 1.0 / 12.0) * (m.yy - 1.0 / 12.0) - m.xy * m.xy;
  EXPECT_NEAR(4.0 * std::numbers::pi * std::sqrt(det), std::numbers::pi * a * b, 0.03 * std::numbers::pi * a * b);
  // Green spreads the same way.
  double green = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) green += result.pixel(x, y)[1];
  EXPECT_NEAR(green, 500.0, 500.0 * 1e-5);
}

TEST(DepthOfFieldTest, TwoPlanesAreEachBlurredByTheirOwnEllipse) {
  // Left half at 0.25 m (4 D), right half at 1 m (1 D), accommodated at 0.5 m (2 D), with -1 D
  // cylinder at TABO 30: near error -2 I + C (-2 and -3 D: 6 x 4 px), far error I + C (1 and 0 D:
  // a 2 px line). Away from the boundary (and the frame's border) each half must equal its own
  // masked convolution.
  const int width = 96, height = 64, half = 48;
  const ImageRGBA image = textured(width, height);
  std::vector<float> depth(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) depth[static_cast<std::size_t>(y) * width + x] = x < half ? 0.25f : 1.0f;
  const DioptricPower cylinder = DioptricPower::from_prescription({0.0, -1.0, 30.0});
  const EyeErrorAtDistance error = emmetrope(0.5, cylinder);
  DepthOfFieldReport report;
  const ImageRGBA result = apply_depth_of_field(image, depth, settings_for(error), &report);
  EXPECT_EQ(report.layers, 2);
  EXPECT_EQ(report.blurred_layers, 2);

  const EllipticalKernel near_kernel =
      elliptical_kernel(pixel_blur_ellipse(error(0.25), kPupilRadiusM, kDegreesPerPixel));
  const EllipticalKernel far_kernel =
      elliptical_kernel(pixel_blur_ellipse(error(1.0), kPupilRadiusM, kDegreesPerPixel));
  EXPECT_NEAR(pixel_blur_ellipse(error(0.25), kPupilRadiusM, kDegreesPerPixel).semi_major_px, 6.0, 1e-9);
  EXPECT_NEAR(pixel_blur_ellipse(error(1.0), kPupilRadiusM, kDegreesPerPixel).semi_minor_px, 0.0, 1e-9);
  const std::vector<double> near = convolve_masked(image, near_kernel, [&](int x, int) { return x < half; });
  const std::vector<double> far = convolve_masked(image, far_kernel, [&](int x, int) { return x >= half; });
  const int margin = near_kernel.radius_x_px + far_kernel.radius_x_px + 1;
  const int border =
      std::max({near_kernel.radius_x_px, near_kernel.radius_y_px, far_kernel.radius_x_px, far_kernel.radius_y_px}) + 1;
  int checked = 0;
  for (int y = border; y < height - border; ++y)
    for (int x = border; x < width - border; ++x) {
      if (std::abs(x - half) < margin) continue;
      const std::vector<double>& expected = x < half ? near : far;
      for (int c = 0; c < 3; ++c) {
        const double want = expected[3 * (static_cast<std::size_t>(y) * width + x) + c];
        ASSERT_NEAR(result.pixel(x, y)[c], want, 1e-4 * (1.0 + want)) << x << ", " << y << " channel " << c;
      }
      ++checked;
    }
  EXPECT_GT(checked, 1500);
  // The near half really is blurred more than the far one: its texture lost more contrast.
  EXPECT_NE(near_kernel.width(), far_kernel.width());
}

TEST(DepthOfFieldTest, BlurredNearObjectSpreadsOverTheFarOne) {
  // A bright near square (4 D, 4 px of blur at 2 D of error) on a dark, sharp far wall (2 D, in
  // focus): light from the square reaches wall pixels outside its edge, and nothing of the wall
  // darkens the square's inside.
  const int size = 60;
  ImageRGBA image(size, size, 1.0f);
  std::vector<float> depth = flat_depth(size, size, 0.5f);
  for (int y = 20; y < 40; ++y)
    for (int x = 20; x < 40; ++x) {
      image.pixel(x, y)[0] = image.pixel(x, y)[1] = image.pixel(x, y)[2] = 100.0f;
      depth[static_cast<std::size_t>(y) * size + x] = 0.25f;
    }
  const ImageRGBA result = apply_depth_of_field(image, depth, settings_for(emmetrope(0.5)));
  EXPECT_GT(result.pixel(41, 30)[0], 10.0f);          // a pixel of wall, 2 px outside the square
  EXPECT_NEAR(result.pixel(10, 30)[0], 1.0f, 1e-5f);  // the wall far from it is untouched
  EXPECT_NEAR(result.pixel(30, 30)[0], 100.0f, 1e-3f);
  // Just inside the edge, the wall is not behind the blurred square (it cannot be seen there):
  // the pixel stays the square's own colour.
  EXPECT_NEAR(result.pixel(21, 30)[0], 100.0f, 1e-3f);
}

TEST(DepthOfFieldTest, LayeredStageAgreesWithThePerPixelReference) {
  const int width = 96, height = 64;
  const ImageRGBA image = textured(width, height);
  const EyeErrorAtDistance error = emmetrope(0.5, DioptricPower::from_prescription({0.0, -0.5, 160.0}));
  // Two planes: the layering is exact on each plane; it differs only at the edge, where the far
  // plane's light is hidden by the near one here and not in the reference.
  std::vector<float> planes(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) planes[static_cast<std::size_t>(y) * width + x] = x < width / 2 ? 0.3f : 1.5f;
  const DepthOfFieldError plane_error =
      depth_of_field_error(apply_depth_of_field(image, planes, settings_for(error)),
                           depth_of_field_reference(image, planes, settings_for(error)));
  // A ramp from 0.3 m at the top to 3 m at the bottom: no occluding edge, only the blur quantised
  // (and blended between neighbouring layers).
  std::vector<float> ramp(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      ramp[static_cast<std::size_t>(y) * width + x] =
          static_cast<float>(1.0 / (1.0 / 0.3 + y * (1.0 / 3.0 - 1.0 / 0.3) / (height - 1)));
  DepthOfFieldReport report;
  const DepthOfFieldError ramp_error =
      depth_of_field_error(apply_depth_of_field(image, ramp, settings_for(error), &report),
                           depth_of_field_reference(image, ramp, settings_for(error)));
  EXPECT_GT(report.layers, 5);
  EXPECT_LE(report.max_blur_error_px, kDefaultLayerTolerancePx + 1e-9);
  std::printf(
      "two planes: mean |error| %.4g (%.3g%%), max %.4g cd/m2; ramp (%d layers): mean %.4g (%.3g%%), max %.4g\n",
      plane_error.mean_abs_cd_m2, 100 * plane_error.mean_relative, plane_error.max_abs_cd_m2, report.layers,
      ramp_error.mean_abs_cd_m2, 100 * ramp_error.mean_relative, ramp_error.max_abs_cd_m2);
  EXPECT_LT(plane_error.mean_relative, 0.005);
  EXPECT_LT(ramp_error.mean_relative, 0.02);
  EXPECT_LT(ramp_error.max_abs_cd_m2, 5.0);
}

TEST(DepthOfFieldTest, OneLayerARowOfARampIsThePerPixelReference) {
  // With a tolerance below the blur step between rows (3 D over 63 rows at 2 px/D: 0.095 px), every
  // row is its own layer, neighbouring rows add (no occlusion within 1 px), and the stage must be
  // the reference to float precision: what remains in the default run is the blur quantisation.
  const int width = 96, height = 64;
  const ImageRGBA image = textured(width, height);
  const EyeErrorAtDistance error = emmetrope(0.5, DioptricPower::from_prescription({0.0, -0.5, 160.0}));
  std::vector<float> ramp(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      ramp[static_cast<std::size_t>(y) * width + x] =
          static_cast<float>(1.0 / (1.0 / 0.3 + y * (1.0 / 3.0 - 1.0 / 0.3) / (height - 1)));
  DepthOfFieldSettings settings = settings_for(error);
  settings.tolerance_px = 0.02;
  DepthOfFieldReport report;
  const DepthOfFieldError difference = depth_of_field_error(apply_depth_of_field(image, ramp, settings, &report),
                                                            depth_of_field_reference(image, ramp, settings));
  EXPECT_EQ(report.layers, height);
  EXPECT_LT(difference.mean_relative, 1e-6);
  EXPECT_LT(difference.max_abs_cd_m2, 1e-4);
}

TEST(DepthOfFieldTest, TilesMeetWithoutSeams) {
  // One depth makes one layer, so the stage is that layer's blur divided by its blurred coverage:
  // on a frame of five tiles and a part (stimuli/depth_of_field_tiles.h), whose kernel reaches
  // across each tile's edge, every pixel must be the bits of blur_layer's direct sum of the whole
  // layer (the same form, the same operations) divided by its coverage, whatever the thread count.
  const EyeErrorAtDistance error = emmetrope(1.0, DioptricPower::from_prescription({0.0, -0.75, 20.0}));
  const int width = 70, height = 5 * kDepthOfFieldTileRows + 7;
  const ImageRGBA image = textured(width, height);
  const std::vector<float> depth(static_cast<std::size_t>(width) * height, 0.3f);
  for (const VectorIsa isa : {VectorIsa::sse2, widest_vector_isa_with_avx512()}) {
    LayerImage layer;
    layer.width_px = width;
    layer.height_px = height;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float* p = image.pixel(x, y);
        layer.rgba.insert(layer.rgba.end(), {p[0], p[1], p[2], 1.0f});
      }
    for (const int threads : {1, 2, 3}) {
      DepthOfFieldSettings settings = settings_for(error, threads);
      settings.vector_isa = isa;
      DepthOfFieldBuffers buffers;
      ImageRGBA result;
      DepthOfFieldReport report;
      apply_depth_of_field(image, depth, settings, buffers, result, &report);
      ASSERT_EQ(report.layers, 1);
      ASSERT_EQ(report.direct_layers, 1);
      const EllipticalKernel kernel = elliptical_kernel(buffers.plan.layers[0].ellipse);
      ASSERT_GE(kernel.radius_y_px, 2);  // the kernel reaches across the tiles' edges
      const LayerImage blurred = blur_layer(layer, kernel, LayerConvolution::direct, 1, isa);
      int differing = 0;
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          const float* sum = blurred.pixel(x + kernel.radius_x_px, y + kernel.radius_y_px);
          const float coverage = sum[3] > 0.0f ? sum[3] : 1.0f;
          for (int c = 0; c < 3; ++c)
            if (result.pixel(x, y)[c] != std::max(0.0f, sum[c] / coverage)) ++differing;
          if (result.pixel(x, y)[3] != image.pixel(x, y)[3]) ++differing;
        }
      EXPECT_EQ(differing, 0) << static_cast<int>(isa) << " " << threads;
    }
  }
}

TEST(DepthOfFieldTest, ResultDoesNotDependOnTheThreadCount) {
  const int width = 80, height = 50;
  const ImageRGBA image = textured(width, height);
  std::vector<float> depth(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      depth[static_cast<std::size_t>(y) * width + x] = x < 30 ? 0.3f : static_cast<float>(0.6 + 0.05 * y);
  const EyeErrorAtDistance error = emmetrope(1.0, DioptricPower::from_prescription({0.0, -0.75, 20.0}));
  const ImageRGBA one = apply_depth_of_field(image, depth, settings_for(error, 1));
  for (int threads : {2, 3, 5})
    EXPECT_EQ(apply_depth_of_field(image, depth, settings_for(error, threads)).rgba, one.rgba) << threads;
}

TEST(DepthOfFieldTest, KeptBuffersGiveTheFramesOfFreshOnes) {
  // Buffers and an output kept from frame to frame (DepthOfFieldBuffers) reuse memory whatever it
  // held: frames of other sizes, other layers and both convolutions in turn must each be the bits of
  // a call with fresh buffers, alpha and depth channel included.
  const EyeErrorAtDistance error = emmetrope(1.0, DioptricPower::from_prescription({0.0, -0.75, 20.0}));
  struct Frame {
    ImageRGBA image;
    std::vector<float> depth;
  };
  const auto frame = [](int width, int height, float near_m, float far_m) {
    Frame f{textured(width, height), {}};
    f.depth.resize(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        f.image.pixel(x, y)[3] = 0.25f + 0.01f * static_cast<float>(x % 7);
        f.depth[static_cast<std::size_t>(y) * width + x] =
            x < width / 3 ? near_m : static_cast<float>(far_m + 0.05 * y);
      }
    f.image.depth = f.depth;
    return f;
  };
  // The second has a 0.05 m board 19 D from focus (38 px of blur: the FFT, whichever form's cost
  // constant rules), the others only the direct sum.
  const std::vector<Frame> frames = {frame(80, 50, 0.3f, 0.6f), frame(140, 90, 0.05f, 0.8f), frame(61, 37, 0.5f, 1.5f),
                                     frame(80, 50, 0.3f, 0.6f)};
  for (int threads : {1, 2}) {
    DepthOfFieldBuffers buffers;
    ImageRGBA kept(3, 2, 7.0f);  // the wrong size: made again
    bool took_fft = false;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      DepthOfFieldReport kept_report, fresh_report;
      apply_depth_of_field(frames[k].image, frames[k].depth, settings_for(error, threads), buffers, kept, &kept_report);
      const ImageRGBA fresh =
          apply_depth_of_field(frames[k].image, frames[k].depth, settings_for(error, threads), &fresh_report);
      ASSERT_EQ(kept.width_px, fresh.width_px);
      EXPECT_EQ(kept.rgba, fresh.rgba) << k << " " << threads;
      EXPECT_EQ(kept.depth, frames[k].depth) << k;
      EXPECT_EQ(kept_report.layers, fresh_report.layers);
      EXPECT_EQ(kept_report.fft_layers, fresh_report.fft_layers);
      took_fft = took_fft || kept_report.fft_layers > 0;
      // The alpha is the input's, untouched by the blur.
      EXPECT_EQ(kept.pixel(6, 3)[3], frames[k].image.pixel(6, 3)[3]);
    }
    EXPECT_TRUE(took_fft);
  }
  // The output cannot be its own input.
  DepthOfFieldBuffers buffers;
  ImageRGBA same = frames[0].image;
  EXPECT_THROW(apply_depth_of_field(same, frames[0].depth, settings_for(error), buffers, same), std::invalid_argument);
}

TEST(DepthOfFieldTest, DirectAndFftConvolutionAgreeAndAreThreadInvariant) {
  LayerImage layer;
  layer.x0_px = 5;
  layer.y0_px = -3;
  layer.width_px = 37;
  layer.height_px = 23;
  const ImageRGBA image = textured(layer.width_px, layer.height_px);
  layer.rgba = image.rgba;
  // Zeros around the content in some rows (as a layer's own pixels leave them), which the direct
  // sum skips.
  for (int y = 0; y < layer.height_px; y += 3)
    for (int x = 0; x < layer.width_px; ++x)
      if (x < y || x > y + 12) std::fill_n(layer.pixel(x, y), 4, 0.0f);
  const EllipticalKernel kernel = elliptical_kernel(PixelBlurEllipse{7.0, 3.0, 110.0});
  const LayerImage direct = blur_layer(layer, kernel, LayerConvolution::direct, 1);
  const LayerImage fft = blur_layer(layer, kernel, LayerConvolution::fft, 1);
  ASSERT_EQ(direct.x0_px, 5 - kernel.radius_x_px);
  ASSERT_EQ(direct.y0_px, -3 - kernel.radius_y_px);
  ASSERT_EQ(fft.rgba.size(), direct.rgba.size());
  for (std::size_t k = 0; k < direct.rgba.size(); ++k)
    ASSERT_NEAR(fft.rgba[k], direct.rgba[k], 1e-4 * (1.0 + std::abs(direct.rgba[k]))) << k;
  EXPECT_EQ(blur_layer(layer, kernel, LayerConvolution::direct, 2).rgba, direct.rgba);
  EXPECT_EQ(blur_layer(layer, kernel, LayerConvolution::fft, 3).rgba, fft.rgba);
  // Each form of the direct sum this CPU runs (odd spans: a last block alone) gives the same bits
  // on 1, 2 and 3 threads, and stays within the bound between forms (depth_of_field_rows.h) of the
  // SSE2 form: every output is a sum of at most T non-negative products w x, each form's within
  // gamma_T = T u / (1 - T u) (u = 2^-24) of the exact S, so two forms differ by at most
  // 2 gamma_T S <= 2 gamma_T s / (1 - gamma_T), s the SSE2 form's value.
  const LayerImage sse2 = blur_layer(layer, kernel, LayerConvolution::direct, 1, VectorIsa::sse2);
  std::size_t taps = 0;
  for (const double w : kernel.weights) taps += w != 0.0 ? 1 : 0;
  const double u = std::ldexp(1.0, -24), gamma = static_cast<double>(taps) * u / (1.0 - static_cast<double>(taps) * u);
  for (const VectorIsa isa : {VectorIsa::sse2, VectorIsa::avx2_fma, VectorIsa::avx512}) {
    if (!vector_isa_available(isa)) continue;
    const LayerImage one = blur_layer(layer, kernel, LayerConvolution::direct, 1, isa);
    EXPECT_EQ(blur_layer(layer, kernel, LayerConvolution::direct, 2, isa).rgba, one.rgba) << static_cast<int>(isa);
    EXPECT_EQ(blur_layer(layer, kernel, LayerConvolution::direct, 3, isa).rgba, one.rgba) << static_cast<int>(isa);
    ASSERT_EQ(one.rgba.size(), sse2.rgba.size());
    for (std::size_t k = 0; k < one.rgba.size(); ++k)
      ASSERT_LE(std::abs(static_cast<double>(one.rgba[k]) - sse2.rgba[k]), 2.0 * gamma * sse2.rgba[k] / (1.0 - gamma))
          << k << " " << static_cast<int>(isa);
  }
}

TEST(DepthOfFieldTest, RowSegmentsGiveTheBitsOfOneSpanWithZerosBetween) {
  // Two boards in the same rows, far enough apart to be stored as two segments a row: the direct
  // sum must give every output the bits it has when each row is one span with zeros in the gap
  // (the gap at least min_segment_gap_px, so no block reads both), on 1 and 3 threads and in each
  // vector form.
  const EllipticalKernel kernel = elliptical_kernel(PixelBlurEllipse{5.0, 2.5, 30.0});
  const int gap = min_segment_gap_px(kernel);
  const int width = 12 + gap + 17, height = 19;
  const ImageRGBA texture = textured(width, height);
  LayerImage layer;
  layer.x0_px = -4;
  layer.y0_px = 7;
  layer.width_px = width;
  layer.height_px = height;
  layer.rgba.assign(4 * static_cast<std::size_t>(width) * height, 0.0f);
  std::vector<std::size_t> row_first(static_cast<std::size_t>(height) + 1, 0);
  std::vector<RowSpan> segments, hulls(static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    // Row 5 has only the left board, row 9 only the right one, row 13 none.
    const bool left = y != 9 && y != 13, right = y != 5 && y != 13;
    const int right_first = 12 + gap + (y % 3);  // the gap never below the least
    if (left) segments.push_back({1, 12});
    if (right) segments.push_back({right_first, width - (y % 2)});
    row_first[static_cast<std::size_t>(y) + 1] = segments.size();
    for (std::size_t s = row_first[static_cast<std::size_t>(y)]; s < segments.size(); ++s)
      for (int x = segments[s].first; x < segments[s].last; ++x)
        std::copy_n(texture.pixel(x, y), 4, layer.pixel(x, y));
    if (left || right) hulls[static_cast<std::size_t>(y)] = {left ? 1 : right_first, right ? width - (y % 2) : 12};
  }
  LayerRows split;
  split.lay_out_segments(layer.x0_px, layer.y0_px, width, height, row_first, segments, kernel);
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const int y = static_cast<int>(std::upper_bound(row_first.begin(), row_first.end(), s) - row_first.begin()) - 1;
    std::copy_n(layer.pixel(segments[s].first, y), 4 * static_cast<std::size_t>(segments[s].last - segments[s].first),
                split.segment_pixels(s));
  }
  ASSERT_EQ(split.spans.size(), hulls.size());
  for (std::size_t y = 0; y < hulls.size(); ++y) {
    EXPECT_EQ(split.spans[y].first, hulls[y].first) << y;
    EXPECT_EQ(split.spans[y].last, hulls[y].last) << y;
  }
  for (const int threads : {1, 3})
    for (const VectorIsa isa : {VectorIsa::sse2, VectorIsa::avx2_fma, VectorIsa::avx512}) {
      if (!vector_isa_available(isa)) continue;
      const LayerImage whole = blur_layer(layer, hulls, kernel, LayerConvolution::direct, 1, isa);
      LayerImage out = whole;
      std::fill(out.rgba.begin(), out.rgba.end(), -1.0f);
      blur_rows_direct(split, kernel, threads, isa, [&](int row, int first, int count, const float* rgba) {
        std::copy_n(rgba, 4 * static_cast<std::size_t>(count), out.pixel(first, row));
      });
      const std::vector<RowSpan> blurred = blurred_row_spans(hulls, kernel);
      for (int y = 0; y < out.height_px; ++y)
        for (int x = blurred[static_cast<std::size_t>(y)].first; x < blurred[static_cast<std::size_t>(y)].last; ++x)
          for (int c = 0; c < 4; ++c)
            ASSERT_EQ(out.pixel(x, y)[c], whole.pixel(x, y)[c]) << x << " " << y << " " << threads;
    }
}

TEST(DepthOfFieldTest, BlurredSpansHoldEveryNonzeroValueOfTheBlurredLayer) {
  // A diagonal band with gaps: the spans worked out from the input's must contain all the light of
  // the blurred layer, and be no wider than the band plus the kernel's width.
  LayerImage layer;
  layer.width_px = 60;
  layer.height_px = 40;
  layer.rgba.assign(4 * static_cast<std::size_t>(60) * 40, 0.0f);
  for (int y = 0; y < 40; ++y)
    if (y % 7 != 3)
      for (int x = y; x < y + 5; ++x) std::fill_n(layer.pixel(x, y), 4, 1.0f + static_cast<float>(x));
  const EllipticalKernel kernel = elliptical_kernel(PixelBlurEllipse{4.0, 1.5, 70.0});
  const std::vector<RowSpan> spans = nonzero_row_spans(layer);
  const LayerImage blurred = blur_layer(layer, spans, kernel, LayerConvolution::direct, 1);
  const std::vector<RowSpan> grown = blurred_row_spans(spans, kernel);
  ASSERT_EQ(grown.size(), static_cast<std::size_t>(blurred.height_px));
  const std::vector<RowSpan> actual = nonzero_row_spans(blurred);
  for (std::size_t y = 0; y < grown.size(); ++y) {
    if (actual[y].first >= actual[y].last) continue;
    EXPECT_LE(grown[y].first, actual[y].first) << y;
    EXPECT_GE(grown[y].last, actual[y].last) << y;
    EXPECT_LE(grown[y].last - grown[y].first, 5 + 2 * kernel.radius_y_px + 2 * kernel.radius_x_px) << y;
  }
}

TEST(DepthOfFieldTest, CostModelPicksTheMeasuredFasterConvolution) {
  // blur_layer both ways on a 1024 x 768 layer, 2 threads (the process' CPU time, the direct sum's
  // outputs held in registers; docs/DEPTH_OF_FIELD.md, section 4), the AVX2 form: direct 27 ms
  // against FFT 40 ms for an 8 px circle, 99 against 41 ms for a 16 px one; on a 32-row band direct
  // 1.0 against 2.0 ms at 8 px, 3.8 against 2.0 ms at 16 px.
  const auto pick = [](int width, int height, double radius_px, VectorIsa isa = VectorIsa::avx2_fma) {
    LayerImage layer;
    layer.width_px = width;
    layer.height_px = height;
    layer.rgba.assign(4 * static_cast<std::size_t>(width) * height, 1.0f);
    return cheaper_layer_convolution(layer, elliptical_kernel(PixelBlurEllipse{radius_px, radius_px, 0.0}), isa);
  };
  EXPECT_EQ(pick(1024, 768, 4.0), LayerConvolution::direct);
  EXPECT_EQ(pick(1024, 768, 8.0), LayerConvolution::direct);
  EXPECT_EQ(pick(1024, 768, 16.0), LayerConvolution::fft);
  EXPECT_EQ(pick(1024, 32, 8.0), LayerConvolution::direct);
  EXPECT_EQ(pick(1024, 32, 16.0), LayerConvolution::fft);
  // The AVX-512 form, where this CPU runs it (elsewhere its rule is the AVX2 form's, as above):
  // direct 24.9 against FFT 38.2 ms at 12 px, 83.4 against 41.4 ms at 24 px; on the band 1.69
  // against 2.03 ms at 16 px, 5.56 against 4.28 ms at 32 px.
  if (vector_isa_available(VectorIsa::avx512)) {
    EXPECT_EQ(pick(1024, 768, 12.0, VectorIsa::avx512), LayerConvolution::direct);
    EXPECT_EQ(pick(1024, 768, 24.0, VectorIsa::avx512), LayerConvolution::fft);
    EXPECT_EQ(pick(1024, 32, 16.0, VectorIsa::avx512), LayerConvolution::direct);
    EXPECT_EQ(pick(1024, 32, 32.0, VectorIsa::avx512), LayerConvolution::fft);
  } else {
    EXPECT_EQ(pick(1024, 32, 16.0, VectorIsa::avx512), LayerConvolution::fft);
  }
  EXPECT_EQ(pick(1024, 768, 0.4), LayerConvolution::direct);  // the identity kernel
  // A thin diagonal band (a slice of a tilted plane) in a full-frame rectangle: the direct sum only
  // visits its 8 px a row, so it stays cheaper at 16 px of blur.
  LayerImage band;
  band.width_px = 1024;
  band.height_px = 768;
  band.rgba.assign(4 * static_cast<std::size_t>(1024) * 768, 0.0f);
  for (int y = 0; y < 768; ++y)
    for (int x = y; x < y + 8; ++x) band.pixel(x, y)[3] = 1.0f;
  EXPECT_EQ(cheaper_layer_convolution(band, elliptical_kernel(PixelBlurEllipse{16.0, 16.0, 0.0})),
            LayerConvolution::direct);
}

TEST(DepthOfFieldTest, BadInputIsRefusedWithItsMessage) {
  const ImageRGBA image = textured(8, 6);
  const std::vector<float> depth = flat_depth(8, 6, 1.0f);
  const auto refusal = [](const ImageRGBA& in, const std::vector<float>& d,
                          const DepthOfFieldSettings& s) -> std::string {
    try {
      apply_depth_of_field(in, d, s);
    } catch (const std::exception& error) {
      return error.what();
    }
    return "(accepted)";
  };
  DepthOfFieldSettings settings = settings_for(emmetrope(0.5));
  std::vector<float> bad_depth = depth;
  bad_depth[2 * 8 + 5] = -1.0f;
  EXPECT_THAT(refusal(image, bad_depth, settings),
              HasSubstr("stimuli/scene_depth: the depth map: Z at pixel (5, 2) is negative"));
  EXPECT_THAT(refusal(image, flat_depth(8, 5, 1.0f), settings), HasSubstr("40 values for a 8 x 6 px image"));
  ImageRGBA nan_image = image;
  nan_image.pixel(1, 1)[2] = std::nanf("");
  EXPECT_THAT(refusal(nan_image, depth, settings), HasSubstr("stimuli/depth_of_field: the image has"));
  // The stage finds bad pixels as its layers read them: the same message as the check's, through
  // kept buffers too, on the last pixel and on two kinds at once.
  for (const auto& [x, y, value, message] :
       {std::tuple{7, 5, -2.0f, "the image has 1 negative pixel;"},
        std::tuple{0, 0, std::numeric_limits<float>::infinity(), "the image has 1 Inf pixel;"},
        std::tuple{3, 4, -std::numeric_limits<float>::infinity(), "the image has 1 Inf pixel, 1 negative pixel;"}}) {
    ImageRGBA bad = image;
    bad.pixel(x, y)[1] = value;
    EXPECT_THAT(refusal(bad, depth, settings), HasSubstr(message)) << x << " " << y;
    DepthOfFieldBuffers buffers;
    ImageRGBA out;
    apply_depth_of_field(image, depth, settings, buffers, out);
    EXPECT_THROW(apply_depth_of_field(bad, depth, settings, buffers, out), std::invalid_argument);
    try {
      check_depth_of_field_inputs(bad, depth, settings);
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_THAT(refusal(bad, depth, settings), HasSubstr(error.what()));
    }
  }
  // Rows of 7 pixels: a bad value among a row's last pixels (after the whole vectors of the fill).
  const ImageRGBA odd = textured(7, 5);
  for (const auto& [x, y, value, message] :
       {std::tuple{6, 4, std::nanf(""), "the image has 1 NaN pixel;"}, std::tuple{5, 2, -0.5f, "1 negative pixel;"}}) {
    ImageRGBA bad = odd;
    bad.pixel(x, y)[0] = value;
    EXPECT_THAT(refusal(bad, flat_depth(7, 5, 1.0f), settings), HasSubstr(message)) << x << " " << y;
  }
  ImageRGBA negative_zero = odd;
  negative_zero.pixel(6, 4)[2] = -0.0f;  // not negative
  EXPECT_EQ(refusal(negative_zero, flat_depth(7, 5, 1.0f), settings), "(accepted)");
  // Alpha is not a luminance: a NaN there is carried, not refused.
  ImageRGBA nan_alpha = image;
  nan_alpha.pixel(2, 2)[3] = std::nanf("");
  EXPECT_EQ(refusal(nan_alpha, depth, settings), "(accepted)");
  DepthOfFieldSettings s = settings;
  s.pupil_radius_m = 0.0;
  EXPECT_THAT(refusal(image, depth, s), HasSubstr("stimuli/depth_of_field: the pupil radius"));
  s = settings;
  s.degrees_per_pixel = -1.0;
  EXPECT_THAT(refusal(image, depth, s), HasSubstr("degrees per pixel"));
  s = settings;
  s.tolerance_px = 0.0;
  EXPECT_THAT(refusal(image, depth, s), HasSubstr("layer tolerance"));
  s = settings;
  s.threads = 0;
  EXPECT_THAT(refusal(image, depth, s), HasSubstr("threads 0"));
  s = settings;
  s.residual_error = nullptr;
  EXPECT_THAT(refusal(image, depth, s), HasSubstr("no eye error function"));
  s = settings;
  s.residual_error = [](double) { return DioptricPower::spherical(NAN); };
  EXPECT_THAT(refusal(image, depth, s), HasSubstr("stimuli/depth_layers: the eye's power error for a point at 1"));
  EXPECT_THAT(refusal(ImageRGBA{}, {}, settings), HasSubstr("the image is empty"));
}

}  // namespace
}  // namespace glarelab
