// Frames warped through spectacle lenses (stimuli/spectacle_warp.h), measured on rendered dots
// against the spectacle magnification formula, Prentice's rule and the Abbe number, and the grid's
// interpolation against a per-pixel trace.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "glare/refraction/spectacle_lens.h"
#include "stimuli/perception/stage_timing.h"
#include "stimuli/spectacle_warp.h"

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

SpectacleLensSpec lens_spec(double sphere_dioptres, double thickness_mm) {
  SpectacleLensSpec spec;
  spec.prescription = {sphere_dioptres, 0.0, 0.0};
  spec.centre_thickness_mm = thickness_mm;
  return spec;
}

// White Gaussian dots (peak 100 cd/m2) at the given continuous pixel positions. Resampling a
// narrow dot bilinearly biases its centroid (by about 0.1 px at sigma 2 px under a 1.14x
// magnification); at sigma 4 px the rendered red-blue separation equals the ray trace's to 1e-4 px.
ImageRGBA dots(const SpectacleFrame& frame, const std::vector<glm::dvec2>& centres, double sigma_px = 2.0) {
  ImageRGBA image(frame.width_px, frame.height_px, 0.0f);
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) {
      double value = 0.0;
      for (const glm::dvec2& c : centres) {
        const double r2 = (x - c.x) * (x - c.x) + (y - c.y) * (y - c.y);
        if (r2 < 100.0 * sigma_px * sigma_px) value += 100.0 * std::exp(-0.5 * r2 / (sigma_px * sigma_px));
      }
      float* p = image.pixel(x, y);
      p[0] = p[1] = p[2] = static_cast<float>(value);
      p[3] = 1.0f;
    }
  return image;
}

// The centroid of one channel within `radius` pixels of `guess`.
glm::dvec2 centroid(const ImageRGBA& image, int channel, glm::dvec2 guess, int radius) {
  double sum = 0.0, sx = 0.0, sy = 0.0;
  for (int y = static_cast<int>(guess.y) - radius; y <= static_cast<int>(guess.y) + radius; ++y)
    for (int x = static_cast<int>(guess.x) - radius; x <= static_cast<int>(guess.x) + radius; ++x) {
      if (x < 0 || y < 0 || x >= image.width_px || y >= image.height_px) continue;
      const double v = image.pixel(x, y)[channel];
      sum += v;
      sx += v * x;
      sy += v * y;
    }
  return glm::dvec2(sx, sy) / sum;
}

// Spectacle magnification for the turning eye (Bennett and Rabbetts' form),
//   SM = [1 / (1 - h F_v)] [1 / (1 - (t / n) F1)],
// h from the back vertex to the eye's centre of rotation (vertex distance 12 + 13.5 mm): the warp's
// visual directions are lines of sight from the centre of rotation.
TEST(SpectacleWarp, DotGridSpacingIsTheSpectacleMagnification) {
  const SpectacleFrame frame{401, 301, 0.02};
  const glm::dvec2 centre(200.0, 150.0);
  constexpr double kSpacing_px = 20.0;  // 0.4 deg
  std::vector<glm::dvec2> grid;
  for (int j = -3; j <= 3; ++j)
    for (int i = -3; i <= 3; ++i) grid.push_back(centre + kSpacing_px * glm::dvec2(i, j));
  const ImageRGBA scene = dots(frame, grid);
  for (const auto& [power, thickness_mm] : {std::pair{4.0, 4.0}, std::pair{-6.0, 2.0}}) {
    const SpectacleLens lens(lens_spec(power, thickness_mm));
    const double h_m = 0.0255;
    const double expected = 1.0 / (1.0 - h_m * power) / (1.0 - thickness_mm * 1e-3 / 1.498 * lens.front_power_dioptres());
    const ImageRGBA seen = warp_through_spectacles(scene, lens, frame);
    // Dots one spacing either side of the centre, horizontally and vertically (green: the d line).
    const glm::dvec2 left = centroid(seen, 1, centre - glm::dvec2(kSpacing_px * expected, 0.0), 6);
    const glm::dvec2 right = centroid(seen, 1, centre + glm::dvec2(kSpacing_px * expected, 0.0), 6);
    const glm::dvec2 up = centroid(seen, 1, centre - glm::dvec2(0.0, kSpacing_px * expected), 6);
    const glm::dvec2 down = centroid(seen, 1, centre + glm::dvec2(0.0, kSpacing_px * expected), 6);
    const double horizontal = (right.x - left.x) / (2.0 * kSpacing_px), vertical = (down.y - up.y) / (2.0 * kSpacing_px);
    std::printf("F_v %+.1f D: SM closed form %.5f, measured %.5f horizontal, %.5f vertical\n", power, expected, horizontal, vertical);
    EXPECT_NEAR(horizontal, expected, 1e-3 * expected) << power;
    EXPECT_NEAR(vertical, expected, 1e-3 * expected) << power;
  }
}

// +4.00 DS, 5 mm thick (the rim reaches 25 mm + the decentration from the optical centre), its
// optical centre decentration_mm to the observer's right.
SpectacleLens decentred_plus_lens(double decentration_mm) {
  SpectacleLensSpec spec = lens_spec(4.0, 5.0);
  spec.decentration_mm = glm::dvec2(decentration_mm, 0.0);  // optical centre 0.5 cm to the observer's right
  return SpectacleLens(spec);
}

// Prentice: decentred 0.3 cm, the +4 D lens deviates the primary line of sight by P = c F prism
// dioptres (F the equivalent power F_v (1 - (t / n) F1) for the thick lens: the eye's ray is parallel
// to the axis). A dot placed P prism dioptres to the right is seen straight ahead.
TEST(SpectacleWarp, DecentredLensDisplacesADotByPrenticesPrism) {
  const SpectacleFrame frame{401, 301, 0.02};
  const SpectacleLens lens = decentred_plus_lens(3.0);
  const double equivalent = 4.0 * (1.0 - 0.005 / 1.498 * lens.front_power_dioptres());
  const double prism = 0.3 * equivalent;  // prism dioptres
  const glm::dvec2 centre(200.0, 150.0);
  const glm::dvec2 dot = frame.pixel(glm::dvec3(prism / 100.0, 0.0, 1.0));
  const ImageRGBA seen = warp_through_spectacles(dots(frame, {dot}), lens, frame);
  const glm::dvec2 image = centroid(seen, 1, centre, 10);
  const double prism_px = dot.x - centre.x;
  std::printf("Prentice: P = %.4f prism dioptres = %.2f px; its image lies %.3f px from the centre\n", prism, prism_px,
              image.x - centre.x);
  EXPECT_NEAR(image.x, centre.x, 0.01 * prism_px);  // within 1 % of P: third-order terms, (c / R1)^2 ~ 0.4 %
  EXPECT_NEAR(image.y, centre.y, 0.05);
}

// TCA: a thin lens' prism c F is proportional to n - 1, so in the scene the red (C line) and blue
// (F line) lines of sight through the same point of the lens part by P (n_F - n_C) / (n_d - 1) = P /
// V_d prism dioptres; with other wavelengths, by P (n_blue - n_red) / (n_d - 1) under the Cauchy
// formula. For the thick lens the deviation is c F_e with F_e = F1 + F2 - (t / n) F1 F2, whose last
// term goes as (n - 1)^2 / n, so
//   dF_e / dn = [F_e - t F1 F2 / n^2] / (n - 1),   red-blue = c (n_blue - n_red) dF_e / dn,
// 3.7 % above P / V_d for this +4 D lens, 5 mm thick. The turning eye sees the angle magnified by SM:
// a dot placed at P (green seen straight ahead) has its red and blue images SM c dn dF_e/dn apart.
TEST(SpectacleWarp, RedBlueSeparationIsPrismOverAbbeNumber) {
  const SpectacleFrame frame{1001, 201, 0.002};  // +-1 deg
  const SpectacleLens lens = decentred_plus_lens(3.0);
  const double n = 1.498, t = 0.005;
  const double f1 = lens.front_power_dioptres(), f2 = lens.back_surface_power().xx();
  const double equivalent = f1 + f2 - t / n * f1 * f2;
  const double d_equivalent_dn = (equivalent - t * f1 * f2 / (n * n)) / (n - 1.0);
  const double prism = 0.3 * equivalent;                                                   // Prentice, c F_e
  const double magnification = 1.0 / (1.0 - 0.0255 * 4.0) / (1.0 - t / n * f1);           // SM at the d line
  const glm::dvec2 centre(500.0, 100.0);
  const ImageRGBA scene = dots(frame, {frame.pixel(glm::dvec3(prism / 100.0, 0.0, 1.0))}, 4.0);
  struct Case {
    SpectacleWarpOptions options;
    double index_difference;  // n_blue - n_red
  };
  SpectacleWarpOptions display_primaries;
  display_primaries.wavelengths_nm = {611.0, 549.0, 464.0};
  const Case cases[] = {{SpectacleWarpOptions{}, 0.498 / 58.0},
                        {display_primaries, lens.refractive_index(464.0) - lens.refractive_index(611.0)}};
  for (const Case& c : cases) {
    const ImageRGBA seen = warp_through_spectacles(scene, lens, frame, c.options);
    const glm::dvec2 red = centroid(seen, 0, centre, 30), blue = centroid(seen, 2, centre, 30);
    // A plus lens bends blue more: the blue image lies further from the optical centre (left).
    const double separation_px = red.x - blue.x;
    const double px_per_tangent = 1.0 / (2.0 * std::tan(0.5 * 0.002 / kDegPerRad));
    const double thin_px = magnification * prism / 100.0 * c.index_difference / (n - 1.0) * px_per_tangent;
    const double expected_px = magnification * 0.003 * c.index_difference * d_equivalent_dn * px_per_tangent;
    std::printf("TCA at %.0f/%.0f nm: P = %.4f prism dioptres, red-blue %.4f px; thick-lens closed form %.4f px (thin, SM P dn / (n - 1): %.4f px)\n",
                c.options.wavelengths_nm[0], c.options.wavelengths_nm[2], prism, separation_px, expected_px, thin_px);
    EXPECT_NEAR(separation_px, expected_px, 0.015 * expected_px);  // third-order terms at 3 mm: ~1 %
    EXPECT_NEAR(red.y - blue.y, 0.0, 0.02);
  }
}

// The grid's bilinear interpolation against tracing every pixel, over a 640 x 480 frame of
// 0.04 deg pixels (25.6 x 19.2 deg) for lenses with strong distortion, cylinder and progression.
TEST(SpectacleWarp, GridInterpolationStaysNearThePerPixelTrace) {
  const SpectacleFrame frame{640, 480, 0.04};
  SpectacleLensSpec cylinder;
  cylinder.prescription = {-3.0, -2.0, 30.0};
  SpectacleLensSpec progressive;
  progressive.prescription = {1.0, 0.0, 0.0};
  progressive.near_add_dioptres = 2.5;
  SpectacleLensSpec decentred = lens_spec(6.0, 6.0);
  decentred.decentration_mm = {2.0, -3.0};
  for (const SpectacleLensSpec& spec : {lens_spec(-8.0, 2.0), cylinder, progressive, decentred}) {
    const SpectacleLens lens(spec);
    const SourceMap traced = traced_source_map(lens, frame, kFraunhoferD_nm, {}, 2);
    for (int vertices : {17, 33}) {
      const SourceMap grid = grid_source_map(lens, frame, kFraunhoferD_nm, vertices, {}, 2);
      double largest = 0.0, sum = 0.0;
      for (int y = 0; y < frame.height_px; ++y)
        for (int x = 0; x < frame.width_px; ++x) {
          const double error = glm::length(grid.at(x, y) - traced.at(x, y));
          largest = std::max(largest, error);
          sum += error;
        }
      std::printf("%+.2f/%+.2f add %.2f, %d x %d grid: interpolation error max %.4f px, mean %.5f px\n",
                  spec.prescription.sphere_dioptres, spec.prescription.cylinder_dioptres, spec.near_add_dioptres, vertices,
                  vertices, largest, sum / (frame.width_px * frame.height_px));
      if (vertices == 33) {
        EXPECT_LT(largest, 0.1);
      }
    }
  }
}

TEST(SpectacleWarp, DistantSceneDistanceApproachesTheDistantMapping) {
  const SpectacleFrame frame{64, 48, 0.1};
  const SpectacleLens lens(lens_spec(4.0, 4.0));
  const SourceMap distant = traced_source_map(lens, frame, kFraunhoferD_nm);
  const SourceMap far = traced_source_map(lens, frame, kFraunhoferD_nm, 1e7);
  const SourceMap display = traced_source_map(lens, frame, kFraunhoferD_nm, 600.0);
  EXPECT_NEAR(far.at(0, 0).x, distant.at(0, 0).x, 1e-3);
  EXPECT_NEAR(far.at(0, 0).y, distant.at(0, 0).y, 1e-3);
  // At 600 mm the ray that leaves the front surface at (x_l, y_l, z_l) in direction d' meets the
  // plane z = D (13.5 + 600 mm from the centre of rotation) at (x_l, y_l) + (D - z_l) d'_xy / d'_z,
  // seen from the centre of rotation at that point over D: for a plus lens further out than the
  // distant direction d' itself, by (y_l - z_l d'_y / d'_z) / D.
  const double plane_m = 0.6135;
  for (const auto& [x, y] : {std::pair{0, 0}, std::pair{63, 20}}) {
    const LensRay ray = lens.trace_from_eye(frame.direction(glm::dvec2(x, y)), kFraunhoferD_nm);
    const glm::dvec3 point = ray.origin_m + ray.direction * ((plane_m - ray.origin_m.z) / ray.direction.z);
    const glm::dvec2 predicted = frame.pixel(point);
    EXPECT_NEAR(display.at(x, y).x, predicted.x, 1e-9);
    EXPECT_NEAR(display.at(x, y).y, predicted.y, 1e-9);
    const glm::dvec2 centre(31.5, 23.5);
    EXPECT_GT(glm::length(display.at(x, y) - centre), glm::length(distant.at(x, y) - centre) + 0.05);
  }
}

// A minus lens minifies: the frame's edge looks past the scene's edge (object angle = visual angle x
// 1 / SM, 1.15 for -6 D), where the scene is outside_cd_m2; the centre keeps the scene's value. The
// result does not depend on the thread count.
TEST(SpectacleWarp, MinusLensShowsTheOutsideBeyondTheSceneAndThreadsDoNotMatter) {
  const SpectacleFrame frame{101, 81, 0.1};
  const SpectacleLens lens(lens_spec(-6.0, 2.0));
  ImageRGBA scene(101, 81, 5.0f);
  SpectacleWarpOptions options;
  options.outside_cd_m2 = {1.0f, 2.0f, 3.0f};
  const ImageRGBA seen = warp_through_spectacles(scene, lens, frame, options);
  for (int channel = 0; channel < 3; ++channel) {
    EXPECT_EQ(seen.pixel(0, 0)[channel], options.outside_cd_m2[channel]);
    EXPECT_EQ(seen.pixel(100, 40)[channel], options.outside_cd_m2[channel]);
    EXPECT_FLOAT_EQ(seen.pixel(50, 40)[channel], 5.0f);
  }
  // Where the edge falls: the last pixel whose line of sight stays inside is near 50 + 50 / 1.15.
  EXPECT_FLOAT_EQ(seen.pixel(88, 40)[1], 5.0f);
  EXPECT_EQ(seen.pixel(95, 40)[1], 2.0f);
  options.threads = 3;
  const ImageRGBA threaded = warp_through_spectacles(scene, lens, frame, options);
  EXPECT_EQ(threaded.rgba, seen.rgba);
}

void expect_warp_refused(const std::function<void()>& call, const std::string& words) {
  try {
    call();
    ADD_FAILURE() << "accepted: " << words;
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("stimuli/spectacle_warp: "), std::string::npos) << message;
    EXPECT_NE(message.find(words), std::string::npos) << message;
  }
}

TEST(SpectacleWarp, RefusesAFieldOfViewTheLensDoesNotCover) {
  const SpectacleLens lens(lens_spec(-2.0, 2.0));
  // 1024 x 768 at 0.1 deg per pixel spans +-51 deg across its width; the 50 mm lens 25.5 mm from the
  // centre of rotation covers about +-44 deg.
  const SpectacleFrame wide{1024, 768, 0.1};
  expect_warp_refused([&] { warp_through_spectacles(ImageRGBA(1024, 768, 1.0f), lens, wide); }, "does not cover this field of view");
  expect_warp_refused([&] { traced_source_map(lens, wide, kFraunhoferD_nm); }, "does not cover this field of view");
  const SpectacleFrame frame{32, 24, 0.1};
  expect_warp_refused([&] { warp_through_spectacles(ImageRGBA(16, 24, 1.0f), lens, frame); }, "the scene is 16 x 24");
  expect_warp_refused([&] { grid_source_map(lens, frame, kFraunhoferD_nm, 1); }, "grid_vertices");
  expect_warp_refused([&] { grid_source_map(lens, SpectacleFrame{32, 24, 0.0}, kFraunhoferD_nm, 33); }, "degrees_per_pixel_at_centre");
  expect_warp_refused([&] { grid_source_map(lens, frame, 1000.0, 33); }, "wavelength");
  expect_warp_refused([&] { grid_source_map(lens, frame, kFraunhoferD_nm, 33, 5.0); }, "scene_distance_mm");
}

// The float warp (positions taken along each row cell by cell, samples in float) against its
// float64 reference by stage_timing.h's pixel metric, within the 1e-5: on the perception
// test frame (1e-3 to 1e4 cd/m2 with sharp 1e3 and 1e4 cd/m2 edges in its dark part, odd sizes)
// through a minus lens that looks past the scene's edge, a plus lens, a cylinder and a decentred
// lens, a distant and a near scene, two grid sizes; each form of the per-pixel loop the CPU runs
// (core/vector_isa.h). The result does not depend on the threads.
TEST(SpectacleWarp, FloatWarpMatchesItsFloat64Reference) {
  const SpectacleFrame frame{301, 203, 0.08};
  const ImageRGBA scene = perception_test_frame(frame.width_px, frame.height_px);
  SpectacleLensSpec cylinder;
  cylinder.prescription = {-3.0, -2.0, 30.0};
  SpectacleLensSpec decentred = lens_spec(4.0, 4.0);
  decentred.decentration_mm = {2.0, -3.0};
  int outside_pixels = 0;
  for (const SpectacleLensSpec& spec : {lens_spec(-6.0, 2.0), lens_spec(4.0, 4.0), cylinder, decentred})
    for (const int vertices : {9, 33})
      for (const std::optional<double> scene_distance_mm : {std::optional<double>{}, std::optional<double>{600.0}}) {
        const SpectacleLens lens(spec);
        SpectacleWarpOptions options;
        options.grid_vertices = vertices;
        options.scene_distance_mm = scene_distance_mm;
        options.outside_cd_m2 = {0.5f, 0.25f, 0.125f};
        const ImageRGBA reference = warp_through_spectacles_reference(scene, lens, frame, options);
        for (std::size_t i = 0; i < reference.rgba.size(); i += 4) outside_pixels += reference.rgba[i] == 0.5f ? 1 : 0;
        // Each form of the per-pixel loop this CPU runs (stimuli/spectacle_warp_span.h).
        for (const VectorIsa isa : {VectorIsa::sse2, VectorIsa::avx2_fma, VectorIsa::avx512}) {
          if (!vector_isa_available(isa)) continue;
          options.vector_isa = isa;
          options.threads = 1;
          const ImageRGBA fast = warp_through_spectacles(scene, lens, frame, options);
          EXPECT_LE(max_relative_pixel_error(fast, reference, 1e-6), 1e-5)
              << spec.prescription.sphere_dioptres << " D, " << vertices << " vertices, form " << static_cast<int>(isa);
          double alpha_error = 0.0;
          for (std::size_t i = 3; i < fast.rgba.size(); i += 4) alpha_error = std::max(alpha_error, std::abs(static_cast<double>(fast.rgba[i]) - reference.rgba[i]));
          EXPECT_LE(alpha_error, 1e-6);
          options.threads = 3;
          EXPECT_EQ(warp_through_spectacles(scene, lens, frame, options).rgba, fast.rgba);
          ImageRGBA reused(frame.width_px, frame.height_px, 7.0f);  // into a frame of the right size: every value written
          warp_through_spectacles(scene, lens, frame, options, reused);
          EXPECT_EQ(reused.rgba, fast.rgba);
        }
      }
  EXPECT_GT(outside_pixels, 1000);  // the minus lens looks past the scene's edge
  ImageRGBA same = scene;
  expect_warp_refused([&] { warp_through_spectacles(same, SpectacleLens(lens_spec(-6.0, 2.0)), frame, {}, same); },
                      "must not be the scene");
}

// Grids traced once and kept give the frame a fresh trace gives, bit for bit, frame after frame; a
// cache traces again only for another frame or other tracing options, and grids are refused for
// options they were not traced with.
TEST(SpectacleWarp, KeptGridsGiveTheFrameAFreshTraceGives) {
  const SpectacleFrame frame{211, 157, 0.1};
  const ImageRGBA scene = perception_test_frame(frame.width_px, frame.height_px);
  const auto lens = std::make_shared<const SpectacleLens>(lens_spec(-6.0, 2.0));
  SpectacleWarpOptions options;
  options.scene_distance_mm = 600.0;
  options.threads = 2;
  const ImageRGBA fresh = warp_through_spectacles(scene, *lens, frame, options);
  SpectacleWarpGridCache cache(lens);
  const std::shared_ptr<const SpectacleWarpGrids> grids = cache.grids(frame, options);
  EXPECT_TRUE(grids->traced_for(frame, options));
  for (int frame_index = 0; frame_index < 2; ++frame_index) {
    EXPECT_EQ(cache.grids(frame, options), grids);  // kept, not traced again
    EXPECT_EQ(warp_through_spectacles(scene, *cache.grids(frame, options), options).rgba, fresh.rgba);
  }
  options.threads = 1;  // the warp's own options do not ask for a new trace
  options.outside_cd_m2 = {1.0f, 1.0f, 1.0f};
  EXPECT_EQ(cache.grids(frame, options), grids);
  SpectacleWarpOptions other = options;
  other.scene_distance_mm.reset();
  EXPECT_FALSE(grids->traced_for(frame, other));
  expect_warp_refused([&] { warp_through_spectacles(scene, *grids, other); }, "were traced for other");
  const std::shared_ptr<const SpectacleWarpGrids> distant = cache.grids(frame, other);
  EXPECT_NE(distant, grids);
  EXPECT_EQ(warp_through_spectacles(scene, *distant, other).rgba, warp_through_spectacles(scene, *lens, frame, other).rgba);
  const SpectacleFrame wider{frame.width_px + 2, frame.height_px, frame.degrees_per_pixel_at_centre};
  EXPECT_FALSE(distant->traced_for(wider, other));
  EXPECT_EQ(cache.grids(wider, other)->frame().width_px, wider.width_px);
  expect_warp_refused([&] { warp_through_spectacles(scene, *cache.grids(wider, other), other); }, "the scene is 211 x 157");
}

}  // namespace
}  // namespace glarelab
