// The default eye's veil around a lamp on the demo's display (1024 x 512 px, 0.0239 degrees per
// pixel: the far field's two-level convolution, its cross-fade at 64-128 px, the whole-display
// kernel) falls smoothly with the distance from the lamp: no step anywhere from 60 to 450 px. The
// faint circle the demo's PNG screenshots show about 280 px from each glared lamp is where the
// veil falls below half of the first 8-bit sRGB code (0.5 / 255 / 12.92 of the 250 cd/m2 peak,
// 0.038 cd/m2): the PNG's quantisation, not the glare's (docs/GLARE_OPTICS.md 9.5).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"

namespace glarelab {
namespace {

// The lamp: a disc of 25 px radius (1.2 degrees) holding the energy of the demo's 5 px lamp of
// 4000 cd/m2 (4000 x (5 / 25)^2 = 160 cd/m2). A disc that large is an areal light, for which the
// ciliary corona draws no lines (Spencer 1995, section 2.2; glare/analytic/ciliary_corona.h), so
// the veil here is the smooth CIE 146 one this test is about; a small lamp's lines are
// tests/glare_ciliary_corona_test.cpp's.
constexpr int kWidth = 1024, kHeight = 512, kLampX = 768, kLampY = 256, kLampRadiusPx = 25;
constexpr double kPeakCdM2 = 250.0;
constexpr float kLampCdM2 = 160.0f;

std::string experiment_text() {
  return R"([experiment]
name = "smooth-veil"
seed = 11

[display]
width_px = 1024
height_px = 512
viewing_distance_mm = 600.0
pixel_pitch_mm = 0.25
peak_luminance_cd_m2 = 250.0

[scenes]
lamp = { file = "lamp.exr" }

[procedure]
type = "rating"
categories = ["glare"]
stimulus_frames = 1

[presentation]
question_above_stimuli = false

[glare]
grid_px = 256
aperture_width_mm = 10.0
wavelength_samples = 16

[glare.eye]
lens_grating_count = 0

[[conditions.rows]]
name = "glare"
scene = "lamp"
glare = "dynamic"

[[conditions.rows]]
name = "control"
scene = "lamp"
glare = "control"
)";
}

double luminance(const ImageRGBA& image, int x, int y) {
  const float* p = image.pixel(x, y);
  return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

TEST(HumanEyeSmoothVeil, VeilAroundALampHasNoStepOnTheDemosDisplay) {
  test::ScratchDir dir;
  ImageRGBA scene(kWidth, kHeight, 0.0f);
  for (int y = kLampY - kLampRadiusPx; y <= kLampY + kLampRadiusPx; ++y)
    for (int x = kLampX - kLampRadiusPx; x <= kLampX + kLampRadiusPx; ++x)
      if (std::hypot(x + 0.5 - kLampX, y + 0.5 - kLampY) <= kLampRadiusPx)
        for (int c = 0; c < 3; ++c) scene.pixel(x, y)[c] = kLampCdM2;
  write_exr((dir.path() / "lamp.exr").string(), scene);
  const std::string experiment = dir.write("experiment.toml", experiment_text());
  const auto render = [&](const std::string& condition) {
    const auto out = dir.path() / (condition + ".exr");
    const auto run = test::run_glarelab({"render", experiment, "--condition", condition, "--out", out.string()}, dir.path());
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return read_exr(out.string()).image;
  };
  const ImageRGBA glare = render("glare"), control = render("control");
  ASSERT_EQ(glare.width_px, kWidth);

  // Azimuthal means of the glare on 1-pixel rings about the lamp, out to 250 px (the display's
  // edges cut the rings beyond): from ring to ring the mean changes as smoothly as a power law does.
  const int last_ring = 250;
  std::vector<double> sum(last_ring + 2, 0.0), count(last_ring + 2, 0.0);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const auto k = static_cast<std::size_t>(std::lround(std::hypot(x + 0.5 - (kLampX + 0.5), y + 0.5 - (kLampY + 0.5))));
      if (k >= sum.size()) continue;
      sum[k] += luminance(glare, x, y) - luminance(control, x, y);
      count[k] += 1.0;
    }
  // The local power-law exponent -d ln m / d ln r between neighbouring rings, and how much it moves
  // from one pair to the next: a step in the veil shows as a spike in it.
  double worst_ring_jump = 0.0;
  int worst_ring = 0;
  std::vector<double> exponent(sum.size(), 0.0);
  for (std::size_t k = 60; k + 1 <= static_cast<std::size_t>(last_ring); ++k)
    exponent[k] = -std::log((sum[k + 1] / count[k + 1]) / (sum[k] / count[k])) / std::log((static_cast<double>(k) + 1.0) / static_cast<double>(k));
  for (std::size_t k = 61; k + 1 <= static_cast<std::size_t>(last_ring); ++k)
    if (std::abs(exponent[k] - exponent[k - 1]) > worst_ring_jump)
      worst_ring_jump = std::abs(exponent[k] - exponent[k - 1]), worst_ring = static_cast<int>(k);

  // Along the row through the lamp, leftwards to 450 px (past the gap between the demo's stimuli):
  // the second difference of ln(glare) per pixel.
  double worst_row = 0.0, half_code_px = 0.0;
  int worst_row_at = 0;
  const double half_code_cd_m2 = kPeakCdM2 * (0.5 / 255.0) / 12.92;  // sRGB's linear segment (IEC 61966-2-1)
  std::vector<double> row;
  for (int k = 0; k <= 451; ++k) row.push_back(luminance(glare, kLampX - k, kLampY) - luminance(control, kLampX - k, kLampY));
  for (int k = 61; k < 451; ++k) {
    const double second = std::log(row[k + 1]) - 2.0 * std::log(row[k]) + std::log(row[k - 1]);
    if (std::abs(second) > worst_row) worst_row = std::abs(second), worst_row_at = k;
    if (half_code_px == 0.0 && row[k] < half_code_cd_m2) half_code_px = k;
  }
  std::printf("veil about a %.0f cd/m2 lamp: local exponent %.3f (100 px) %.3f (200 px); largest change between rings %.4f "
              "(ring %d); largest second difference of ln along the row %.5f (%d px); the veil falls below half an 8-bit "
              "sRGB code (%.4f cd/m2) at %.0f px\n",
              kLampCdM2, exponent[100], exponent[200], worst_ring_jump, worst_ring, worst_row, worst_row_at, half_code_cd_m2,
              half_code_px);
  // A smooth veil: the exponent (about 2 for CIE 146's 5 / theta^2 term) moves by far less than a
  // step of even 1 % between neighbouring rings would move it (ln 1.01 / ln(1 + 1/k) = 2.0 at k = 200).
  EXPECT_LT(worst_ring_jump, 0.2);
  EXPECT_LT(worst_row, 5e-3);  // a 1 % step gives 1e-2
  EXPECT_GT(exponent[200], 1.5);
  EXPECT_LT(exponent[200], 2.5);
}

}  // namespace
}  // namespace glarelab
