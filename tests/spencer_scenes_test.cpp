// The generated stimuli of Spencer et al. 1995, section 4 (stimuli/spencer_scenes.h): exact
// pixel-area coverage against closed-form areas, the disc/annulus luminances and light flux, the
// source's peak, and the experiment-file keys with their refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "core/display_spec.h"
#include "protocols/experiment.h"
#include "stimuli/disc_coverage.h"
#include "stimuli/scene_library.h"
#include "stimuli/spencer_scenes.h"

namespace glarelab {
namespace {

constexpr double kPi = std::numbers::pi;

DisplaySpec spencer_display() {
  DisplaySpec display;
  display.viewing_distance_mm = 600.0;
  display.pixel_pitch_mm = 0.25;
  display.peak_luminance_cd_m2 = 200.0;
  return display;
}

double sum_luminance(const ImageRGBA& image) {
  double sum = 0.0;
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x) sum += image.pixel(x, y)[1];
  return sum;
}

// Circular segment: the part of a disc of radius r beyond a chord at distance d from the centre,
// r^2 acos(d / r) - d sqrt(r^2 - d^2).
double segment_area(double r, double d) { return r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d); }

TEST(DiscCoverage, WholeDiscHalfAndQuarterAgainstClosedForms) {
  const double r = 7.3;
  EXPECT_NEAR(disc_rectangle_overlap(0.0, 0.0, r, -10, -10, 10, 10), kPi * r * r, 1e-9);
  EXPECT_NEAR(disc_rectangle_overlap(0.0, 0.0, r, 0, -10, 10, 10), 0.5 * kPi * r * r, 1e-9);
  EXPECT_NEAR(disc_rectangle_overlap(0.0, 0.0, r, 0, 0, 10, 10), 0.25 * kPi * r * r, 1e-9);
  // A chord: everything right of x = 3 (a circular segment), and the band between two chords.
  EXPECT_NEAR(disc_rectangle_overlap(0.0, 0.0, r, 3, -10, 10, 10), segment_area(r, 3.0), 1e-9);
  EXPECT_NEAR(disc_rectangle_overlap(0.0, 0.0, r, -10, -2, 10, 5),
              kPi * r * r - segment_area(r, 2.0) - segment_area(r, 5.0), 1e-9);
  // A square wholly inside, and one wholly outside.
  EXPECT_NEAR(disc_rectangle_overlap(0.0, 0.0, r, 1, 1, 2, 2), 1.0, 1e-12);
  EXPECT_EQ(disc_rectangle_overlap(0.0, 0.0, r, 8, 8, 9, 9), 0.0);
}

TEST(DiscCoverage, PixelCoveragesSumToTheDiscAreaAnywhere) {
  for (const double r : {0.3, 0.5, 1.7, 12.25}) {
    for (const double cx : {20.0, 20.5, 20.37}) {
      double sum = 0.0, most = 0.0;
      for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) {
          const double c = disc_pixel_coverage(cx, 19.81, r, x, y);
          ASSERT_GE(c, -1e-12);
          ASSERT_LE(c, 1.0 + 1e-12);
          sum += c, most = std::max(most, c);
        }
      EXPECT_NEAR(sum, kPi * r * r, 1e-9 * std::max(1.0, r * r)) << "r " << r << " cx " << cx;
    }
  }
}

TEST(SpencerScenes, DiscAnnulusLuminancesAndFluxMatchClosedForms) {
  const DisplaySpec display = spencer_display();
  GeneratedSceneSpec spec;
  spec.generator = SceneGenerator::disc_annulus;
  spec.size_px = 120;
  spec.disc_diameter_deg = 1.0;
  spec.annulus_diameter_deg = 2.5;
  spec.disc_fraction_of_peak = 0.6;
  const ImageRGBA image = draw_generated_scene(spec, display);
  ASSERT_EQ(image.width_px, 120);
  const double disc_cd_m2 = 0.6 * 200.0;
  // Diameters: 2 d tan(deg / 2) / pitch.
  const double r_disc = 600.0 * std::tan(0.5 * kPi / 180.0) / 0.25;
  const double r_annulus = 600.0 * std::tan(1.25 * kPi / 180.0) / 0.25;
  EXPECT_NEAR(2.0 * r_disc, generated_scene_pixels(spec, display).disc_diameter_px, 1e-9);
  // Centre: the disc; a pixel half way between the disc's edge and the annulus's: a third of it;
  // corners: black.
  EXPECT_FLOAT_EQ(image.pixel(60, 60)[1], static_cast<float>(disc_cd_m2));
  const int mid = 60 + static_cast<int>(0.5 * (r_disc + r_annulus));
  EXPECT_FLOAT_EQ(image.pixel(mid, 60)[1], static_cast<float>(disc_cd_m2 / 3.0));
  EXPECT_EQ(image.pixel(0, 0)[1], 0.0f);
  EXPECT_EQ(image.pixel(0, 0)[3], 1.0f);
  // Light: L pi r_d^2 + (L / 3) pi (r_a^2 - r_d^2), in cd/m2 x pixel areas.
  const double flux = disc_cd_m2 * kPi * r_disc * r_disc + disc_cd_m2 / 3.0 * kPi * (r_annulus * r_annulus - r_disc * r_disc);
  EXPECT_NEAR(sum_luminance(image), flux, 1e-5 * flux);
  // Grey: R = G = B.
  EXPECT_EQ(image.pixel(mid, 60)[0], image.pixel(mid, 60)[2]);
}

TEST(SpencerScenes, SourcePeaksAtItsFractionOfTheDisplayPeakEvenBelowAPixel) {
  const DisplaySpec display = spencer_display();
  for (const double diameter_deg : {0.02, 0.3}) {  // 0.8 px and 12.6 px
    GeneratedSceneSpec spec;
    spec.generator = SceneGenerator::light_source;
    spec.size_px = 64;
    spec.disc_diameter_deg = diameter_deg;
    spec.disc_fraction_of_peak = 0.75;
    const ImageRGBA image = draw_generated_scene(spec, display);
    EXPECT_FLOAT_EQ(static_cast<float>(max_luminance(image)), 150.0f) << diameter_deg;
  }
  // The lamp's bulb is the brightest thing in the context scene, at the same place.
  GeneratedSceneSpec lamp;
  lamp.generator = SceneGenerator::desk_lamp;
  lamp.size_px = 300;
  lamp.disc_diameter_deg = 0.3;
  lamp.disc_fraction_of_peak = 0.75;
  const ImageRGBA context = draw_generated_scene(lamp, display);
  EXPECT_FLOAT_EQ(context.pixel(150, 150)[1], 150.0f);
  EXPECT_FLOAT_EQ(static_cast<float>(max_luminance(context)), 150.0f);
  EXPECT_NEAR(context.pixel(20, 290)[1], kDeskTopFractionOfPeak * 200.0, 1e-4);
  EXPECT_EQ(context.pixel(290, 10)[1], 0.0f);
}

TEST(SpencerScenes, ExperimentFileReadsGeneratedScenesAndTheLibraryDrawsThem) {
  const std::string text = R"(
[experiment]
name = "generated"
[display]
peak_luminance_cd_m2 = 200.0
[scenes]
disc = { generator = "disc_annulus", size_px = 100, disc_diameter_deg = 0.5, annulus_diameter_deg = 1.5, disc_fraction_of_peak = 1.0 }
source = { generator = "light_source", size_px = 100, disc_diameter_deg = 0.2, disc_fraction_of_peak = 0.75 }
[procedure]
type = "staircase"
alternatives = 3
responses = ["left", "right", "neither"]
start_intensity = 100.0
[[conditions.rows]]
name = "a"
reference = "source"
comparison = "disc"
)";
  const Experiment experiment = parse_experiment_text(text, "generated.toml", ".");
  ASSERT_TRUE(experiment.scenes.at("disc").generated);
  EXPECT_EQ(experiment.scenes.at("disc").generated->annulus_diameter_deg, 1.5);
  const SceneLibrary library(experiment.scenes, experiment.display);
  EXPECT_FLOAT_EQ(static_cast<float>(library.get("disc").peak_cd_m2), 200.0f);
  EXPECT_FLOAT_EQ(static_cast<float>(library.get("source").peak_cd_m2), 150.0f);
  // The stored configuration reads back to the same scenes.
  const Experiment again = parse_experiment_text(resolved_config_toml(experiment), "stored.toml", ".");
  EXPECT_EQ(again.scenes.at("source").generated->disc_fraction_of_peak, 0.75);
  EXPECT_EQ(again.scenes.at("disc").generated->size_px, 100);
  EXPECT_EQ(again.scenes.at("disc").generated->generator, SceneGenerator::disc_annulus);
}

std::string scene_error(const std::string& scene_line) {
  const std::string text = "[experiment]\nname = \"bad\"\n[scenes]\n" + scene_line +
                           "\n[procedure]\ntype = \"staircase\"\n[[conditions.rows]]\nreference = \"s\"\ncomparison = \"s\"\n";
  try {
    parse_experiment_text(text, "bad.toml", ".");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(SpencerScenes, BadKeysAndValuesAreRefusedAtFileLineColumnAndKey) {
  // Line 4 holds the scene; the column is where the offending key or value starts.
  const std::string unknown = scene_error(
      R"(s = { generator = "disc_annulus", disc_diameter_deg = 0.5, annulus_diameter_deg = 1.0, disc_fraction_of_peak = 1.0, ring_deg = 2 })");
  EXPECT_NE(unknown.find("bad.toml:4:"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("ring_deg"), std::string::npos) << unknown;

  const std::string fraction = scene_error(
      R"(s = { generator = "light_source", disc_diameter_deg = 0.5, disc_fraction_of_peak = 1.5 })");
  EXPECT_NE(fraction.find("bad.toml:4:"), std::string::npos) << fraction;
  EXPECT_NE(fraction.find("scenes.s.disc_fraction_of_peak"), std::string::npos) << fraction;

  const std::string inside = scene_error(
      R"(s = { generator = "disc_annulus", disc_diameter_deg = 1.0, annulus_diameter_deg = 0.5, disc_fraction_of_peak = 1.0 })");
  EXPECT_NE(inside.find("scenes.s.annulus_diameter_deg"), std::string::npos) << inside;
  EXPECT_NE(inside.find("larger than disc_diameter_deg"), std::string::npos) << inside;

  // 10 deg at 600 mm and 0.25 mm pixels is 420 px: not in a 300 px image.
  const std::string too_big = scene_error(
      R"(s = { generator = "disc_annulus", disc_diameter_deg = 1.0, annulus_diameter_deg = 10.0, disc_fraction_of_peak = 1.0 })");
  EXPECT_NE(too_big.find("scenes.s.annulus_diameter_deg"), std::string::npos) << too_big;
  EXPECT_NE(too_big.find("300 px image"), std::string::npos) << too_big;

  const std::string generator = scene_error(R"(s = { generator = "spot", disc_diameter_deg = 1.0, disc_fraction_of_peak = 1.0 })");
  EXPECT_NE(generator.find("bad.toml:4:19"), std::string::npos) << generator;
  EXPECT_NE(generator.find("scenes.s.generator"), std::string::npos) << generator;

  const std::string annulus_on_source = scene_error(
      R"(s = { generator = "light_source", disc_diameter_deg = 0.5, annulus_diameter_deg = 1.0, disc_fraction_of_peak = 1.0 })");
  EXPECT_NE(annulus_on_source.find("annulus_diameter_deg"), std::string::npos) << annulus_on_source;
  EXPECT_NE(annulus_on_source.find("unknown key"), std::string::npos) << annulus_on_source;

  const std::string huge = scene_error(
      R"(s = { generator = "light_source", size_px = 100000, disc_diameter_deg = 0.5, disc_fraction_of_peak = 0.75 })");
  EXPECT_NE(huge.find("bad.toml:4:"), std::string::npos) << huge;
  EXPECT_NE(huge.find("scenes.s.size_px"), std::string::npos) << huge;

  const std::string missing = scene_error(R"(s = { generator = "light_source", disc_diameter_deg = 0.5 })");
  EXPECT_NE(missing.find("scenes.s.disc_fraction_of_peak"), std::string::npos) << missing;
  EXPECT_NE(missing.find("missing required key"), std::string::npos) << missing;

  const std::string scaled = scene_error(
      R"(s = { generator = "light_source", disc_diameter_deg = 0.5, disc_fraction_of_peak = 0.75, scale_cd_m2 = 2.0 })");
  EXPECT_NE(scaled.find("scenes.s.scale_cd_m2"), std::string::npos) << scaled;
}

}  // namespace
}  // namespace glarelab
