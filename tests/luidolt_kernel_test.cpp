// Luidolt 2020's glare kernel (glare/wave/luidolt_kernel.h) against the thesis' equations and their
// closed forms: Eq. 5.6's sampling condition (a grid that aliases is refused or enlarged), the
// Fresnel term's on-axis value (the Fresnel-zone closed form), Eq. 5.11's normalisation (Parseval),
// Eq. 5.12's sum (a disc M read at each wavelength's scale), the particles' coverage (the Boolean
// model's 1 - exp(-n a / W^2)) and the bright centre's share; then a session in which one row
// chooses glare_model = luidolt and another ritschel, each frame the convolution with its kernel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "cli_process.h"
#include "core/exr_io.h"
#include "core/image.h"
#include "glare/eye/eye_model.h"
#include "glare/wave/cie_cmf.h"
#include "glare/wave/luidolt_kernel.h"
#include "glare/wave/psf_scale.h"
#include "protocols/experiment.h"
#include "scratch_dir.h"
#include "stimuli/display_model.h"

namespace glarelab {
namespace {

constexpr double kLambdaD_mm2 = 575e-6 * 24.0;  // lambda d of Eq. 5.6 in mm^2

// The smallest even N >= n whose prime factors are 2, 3 and 5, by trial division.
int even_smooth_at_least(double n) {
  for (int m = static_cast<int>(std::ceil(n));; ++m) {
    if (m % 2 != 0) continue;
    int r = m;
    for (int p : {2, 3, 5})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

TEST(LuidoltKernel, SamplingConditionOfTheFresnelTermRefusesOrEnlargesAnAliasingGrid) {
  LuidoltKernelOptions options;  // 8 mm texture, 575 nm, d = 24 mm
  const double pupil_mm = 4.0;
  // Phase step at the pupil's edge pi (2 r dx - dx^2) / (lambda d) < pi  <=>  dx < lambda d / D (to
  // first order): N > W D / (lambda d) = 8 * 4 / 0.0138 = 2318.8.
  const double minimum = options.aperture_width_mm * pupil_mm / kLambdaD_mm2;
  EXPECT_NEAR(minimum, 2318.84, 0.01);
  const LuidoltSampling sampling = luidolt_sampling(pupil_mm, options);
  EXPECT_TRUE(sampling.aliased);
  EXPECT_EQ(sampling.required_grid_px, even_smooth_at_least(minimum));
  EXPECT_EQ(sampling.required_grid_px, 2400);
  EXPECT_NEAR(sampling.max_pixel_mm, kLambdaD_mm2 / pupil_mm, 1e-12);
  // The step itself, by hand, on the grid asked for (256 px: dx = 31.25 um).
  const double dx = 8.0 / 256, r = 2.0;
  EXPECT_NEAR(sampling.edge_phase_step_rad, std::numbers::pi * (2 * r * dx - dx * dx) / kLambdaD_mm2, 1e-9);
  // 2304 (the smooth size just below) still steps more than pi; 2400 less.
  for (const auto& [grid, aliased] : {std::pair{2304, true}, std::pair{2400, false}}) {
    options.grid_px = grid;
    const double step_dx = 8.0 / grid;
    const double step = std::numbers::pi * (2 * r * step_dx - step_dx * step_dx) / kLambdaD_mm2;
    EXPECT_EQ(step >= std::numbers::pi, aliased) << grid;
    EXPECT_EQ(luidolt_sampling(pupil_mm, options).aliased, aliased) << grid;
  }

  options.grid_px = 256;
  options.particle_count = 0;
  options.wavelength_count = 2;
  options.enlarge_grid = false;
  EXPECT_THROW(luidolt_kernel(pupil_mm, 1, options), LuidoltSamplingError);
  options.enlarge_grid = true;
  options.largest_grid_px = 2048;
  try {
    luidolt_kernel(pupil_mm, 1, options);
    ADD_FAILURE() << "a grid past the largest was not refused";
  } catch (const LuidoltSamplingError& error) {
    EXPECT_NE(std::string(error.what()).find("2400"), std::string::npos) << error.what();
  }
  options.largest_grid_px = 8192;
  const LuidoltKernel enlarged = luidolt_kernel(pupil_mm, 1, options);
  EXPECT_EQ(enlarged.grid_px, 2400);
  EXPECT_EQ(enlarged.psf.size_px, 2400);
  EXPECT_NE(enlarged.sampling_note.find("enlarged from 256 to 2400"), std::string::npos) << enlarged.sampling_note;
  // A grid that samples the term is used as asked, without a note.
  options.grid_px = 2400;
  EXPECT_TRUE(luidolt_kernel(pupil_mm, 1, options).sampling_note.empty());
}

// Eq. 5.6 on a clear pupil of radius R: the DFT's DC sums exp(i pi r^2 / (lambda d)) over the pupil's
// samples, (1 / dx^2) times the integral (exp(i pi R^2 / (lambda d)) - 1) lambda d / i, so by Eq. 5.11
// M(0) = 4 sin^2(pi R^2 / (2 lambda d)) / (N^2 dx^4): the on-axis Fresnel-zone oscillation. With
// R^2 = (2m + 1) lambda d the pupil holds an odd number of zones and M(0) is at its peak; with
// R^2 = 2m lambda d an even number, and the zones cancel.
TEST(LuidoltKernel, FresnelTermOnAxisIsTheFresnelZoneClosedForm) {
  LuidoltKernelOptions options;
  options.particle_count = 0;
  options.wavelength_count = 2;
  options.grid_px = 3000;  // finer than the condition asks at this pupil (1931 px)
  for (const auto& [zones, peak] : {std::pair{201, true}, std::pair{200, false}}) {
    const double radius_mm = std::sqrt(zones * kLambdaD_mm2);
    const LuidoltKernel kernel = luidolt_kernel(2.0 * radius_mm, 1, options);
    ASSERT_TRUE(kernel.sampling_note.empty()) << kernel.sampling_note;
    const double n = kernel.grid_px, dx_m = 8e-3 / n;
    const double expected = 4.0 * std::pow(std::sin(std::numbers::pi * zones / 2.0), 2) / (n * n * std::pow(dx_m, 4));
    const double scale = 4.0 / (n * n * std::pow(dx_m, 4));  // the peak value
    if (peak) EXPECT_NEAR(kernel.monochromatic_dc_per_m2 / expected, 1.0, 0.02) << zones;
    else EXPECT_LT(kernel.monochromatic_dc_per_m2, 0.02 * scale) << zones;
    std::printf("%d Fresnel zones: M(0) = %.6g / m^2, closed form %.6g\n", zones, kernel.monochromatic_dc_per_m2, expected);
  }
}

// Eq. 5.11 is normalised so that, by Parseval (sum |FFT L|^2 = N^2 sum |L|^2), sum M = the pupil's
// open samples / (lambda d)^2; the kernel then holds the open share in its centre and each channel
// sums to 1.
TEST(LuidoltKernel, NormalisationAndTheBrightCentreHoldTheUnscatteredLight) {
  LuidoltKernelOptions options;
  options.wavelength_count = 8;
  const double pupil_mm = 3.0;
  const LuidoltKernel kernel = luidolt_kernel(pupil_mm, 7, options);
  // The pupil's open samples counted here from the mask.
  const std::vector<double> mask = luidolt_aperture_mask(luidolt_particles(7, options), pupil_mm, kernel.grid_px, options);
  double open = 0.0, inside = 0.0;
  const double dx = 8.0 / kernel.grid_px;
  for (int y = 0; y < kernel.grid_px; ++y)
    for (int x = 0; x < kernel.grid_px; ++x) {
      const double px = (x + 0.5) * dx - 4.0, py = (y + 0.5) * dx - 4.0;
      if (px * px + py * py <= 2.25) inside += 1.0;
      open += mask[static_cast<std::size_t>(y) * kernel.grid_px + x];
    }
  EXPECT_EQ(kernel.pupil_pixels, inside);
  const double lambda_d_m2 = kLambdaD_mm2 * 1e-6;
  EXPECT_NEAR(kernel.monochromatic_sum_per_m2 / (open / (lambda_d_m2 * lambda_d_m2)), 1.0, 1e-9);
  EXPECT_NEAR(kernel.covered_fraction, 1.0 - open / inside, 1e-15);
  EXPECT_GT(kernel.covered_fraction, 0.0);
  const int n = kernel.psf.size_px, c = n / 2;
  for (int ch = 0; ch < 3; ++ch) {
    double sum = 0.0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) sum += kernel.psf.at(ch, x, y);
    EXPECT_NEAR(sum, 1.0, 1e-9) << ch;
    EXPECT_NEAR(kernel.psf.at(ch, c, c), open / inside, 1e-9) << ch;  // Eq. 5.10's overwritten pixel
    EXPECT_NEAR(kernel.psf.at(ch, c, c), kernel.centre_share, 1e-12) << ch;
  }
  // Without particles nothing is scattered: the kernel is the identity of convolution.
  options.particle_count = 0;
  const LuidoltKernel clear = luidolt_kernel(pupil_mm, 7, options);
  EXPECT_EQ(clear.covered_fraction, 0.0);
  for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(clear.psf.at(ch, c, c), 1.0);
}

// n discs of area a dropped uniformly on a W x W texture cover 1 - exp(-n a / W^2) of it (the
// Boolean model); the thesis' 1000 particles of 0.042 mm on 8 mm: 2.142 %.
TEST(LuidoltKernel, ParticlesCoverWhatTheBooleanModelPredictsAndFollowTheSeed) {
  LuidoltKernelOptions options;
  const double a = std::numbers::pi * 0.021 * 0.021;
  const double expected = 1.0 - std::exp(-1000.0 * a / 64.0);
  EXPECT_NEAR(expected, 0.021415, 1e-6);
  const int n = 2000;
  double covered_sum = 0.0;
  const int seeds = 4;
  for (int seed = 1; seed <= seeds; ++seed) {
    const std::vector<double> mask = luidolt_aperture_mask(luidolt_particles(seed, options), 8.0, n, options);
    double inside = 0.0, open = 0.0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double px = (x + 0.5) * 8.0 / n - 4.0, py = (y + 0.5) * 8.0 / n - 4.0;
        if (px * px + py * py > 16.0) continue;
        inside += 1.0;
        open += mask[static_cast<std::size_t>(y) * n + x];
      }
    covered_sum += 1.0 - open / inside;
  }
  // About 785 particles fall in the disc (binomial sd 13, 1.7 %) per seed; four seeds: 0.85 %.
  const double covered = covered_sum / seeds;
  std::printf("covered %.5f, Boolean model %.5f\n", covered, expected);
  EXPECT_NEAR(covered / expected, 1.0, 0.04);

  const std::vector<LuidoltParticle> one = luidolt_particles(3, options), again = luidolt_particles(3, options);
  const std::vector<LuidoltParticle> other = luidolt_particles(4, options);
  options.particle_count = 10;
  const std::vector<LuidoltParticle> first_ten = luidolt_particles(3, options);
  for (std::size_t i = 0; i < first_ten.size(); ++i) {
    EXPECT_EQ(first_ten[i].x_mm, one[i].x_mm);
    EXPECT_EQ(first_ten[i].y_mm, one[i].y_mm);
  }
  EXPECT_EQ(one.front().x_mm, again.front().x_mm);
  EXPECT_NE(one.front().x_mm, other.front().x_mm);
  for (const LuidoltParticle& p : one) {
    EXPECT_LT(std::abs(p.x_mm), 4.0);
    EXPECT_LT(std::abs(p.y_mm), 4.0);
  }
}

// Eq. 5.12 with k = 1 (phi = 380 and 770 nm) on an M that is 1 inside a disc of radius rho pixels:
// S(x) = (XYZ(380) [|x| 575/380 < rho] + XYZ(770) [|x| 575/770 < rho]) / 2, with no Jacobian.
TEST(LuidoltKernel, SpectralSumIsEq512) {
  const int n = 256;
  const double rho = 60.0;
  std::vector<double> m(static_cast<std::size_t>(n) * n, 0.0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (std::hypot(x - n / 2, y - n / 2) < rho) m[static_cast<std::size_t>(y) * n + x] = 1.0;
  const std::vector<double> xyz = luidolt_spectral_xyz(m, n, 575.0, 2);
  const Xyz blue = cie1931_cmf(380.0), red = cie1931_cmf(770.0);
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  auto at = [&](int plane_index, int radius_px) {
    return xyz[plane_index * plane + static_cast<std::size_t>(n / 2) * n + n / 2 + radius_px];
  };
  // Inside both copies (r < 60 * 380 / 575 = 39.7), only in the 770 nm one (r < 80.3), in neither.
  for (int r : {0, 20, 37}) {
    EXPECT_NEAR(at(0, r), 0.5 * (blue.x + red.x), 1e-15) << r;
    EXPECT_NEAR(at(1, r), 0.5 * (blue.y + red.y), 1e-15) << r;
    EXPECT_NEAR(at(2, r), 0.5 * (blue.z + red.z), 1e-15) << r;
  }
  for (int r : {44, 60, 77}) {
    EXPECT_NEAR(at(0, r), 0.5 * red.x, 1e-15) << r;
    EXPECT_NEAR(at(1, r), 0.5 * red.y, 1e-15) << r;
  }
  for (int r : {83, 120}) EXPECT_EQ(at(1, r), 0.0) << r;
}

// The scattered light of a particle at p on the pupil lands, through Eq. 5.6's term, near the angle
// p / d (the pupil's shadow, radius R / d) spread by its own diffraction (first zero 1.22 lambda / s,
// 1.1 degrees at 770 nm): the kernel's scattered light lies inside (R / d) (770 / 575) plus that.
TEST(LuidoltKernel, ScatteredLightFillsThePupilsShadow) {
  LuidoltKernelOptions options;
  options.wavelength_count = 8;
  const double pupil_mm = 3.0;
  const LuidoltKernel kernel = luidolt_kernel(pupil_mm, 11, options);
  const double shadow_deg = (0.5 * pupil_mm / 24.0) * 180.0 / std::numbers::pi;  // 3.58 degrees
  const double reach_deg = shadow_deg * 770.0 / 575.0 + 2.0 * 1.22 * 770e-6 / 0.042 * 180.0 / std::numbers::pi;
  const int n = kernel.psf.size_px, c = n / 2;
  for (int ch = 0; ch < 3; ++ch) {
    double scattered = 0.0, inside = 0.0, inner = 0.0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        if (x == c && y == c) continue;
        const double v = kernel.psf.at(ch, x, y), angle = std::hypot(x - c, y - c) * kernel.psf.degrees_per_pixel;
        scattered += v;
        if (angle <= reach_deg) inside += v;
        if (angle <= 0.5 * shadow_deg) inner += v;
      }
    EXPECT_NEAR(scattered, kernel.covered_fraction, 1e-9) << ch;
    EXPECT_GT(inside / scattered, 0.97) << ch;
    // A shadow filled evenly puts a quarter of its light inside half its radius; the copies of other
    // wavelengths stretch it by 380/575 to 770/575.
    EXPECT_GT(inner / scattered, 0.25 * std::pow(575.0 / 770.0, 2) * 0.7) << ch;
    EXPECT_LT(inner / scattered, 0.25 * std::pow(575.0 / 380.0, 2) * 1.3) << ch;
    std::printf("channel %d: %.4f of the scattered light within %.2f deg, %.4f within %.2f deg\n", ch,
                inside / scattered, reach_deg, inner / scattered, 0.5 * shadow_deg);
  }
}

TEST(LuidoltKernel, ModelIsSelectableInTheFileAndPerRow) {
  const std::string text = R"([experiment]
name = "g"
[scenes]
a = { file = "a.exr" }
[procedure]
type = "forced_choice"
[glare]
mode = "static"
model = "luidolt"
[[conditions.rows]]
name = "one"
scene_a = "a"
scene_b = "a"
[[conditions.rows]]
name = "two"
scene_a = "a"
scene_b = "a"
glare_model = "ritschel"
)";
  const Experiment e = parse_experiment_text(text, "g.toml", "/tmp");
  EXPECT_EQ(e.glare.model, GlareModel::luidolt);
  EXPECT_EQ(glare_model_for(e.glare, e.conditions[0]), GlareModel::luidolt);
  EXPECT_EQ(glare_model_for(e.glare, e.conditions[1]), GlareModel::ritschel);
  const Experiment reread = parse_experiment_text(resolved_config_toml(e), "<stored config>", "/");
  EXPECT_EQ(reread.glare.model, GlareModel::luidolt);
  EXPECT_EQ(parse_glare_model("luidolt"), GlareModel::luidolt);
  EXPECT_EQ(to_string(GlareModel::luidolt), "luidolt");
}

// A session (glarelab render, the session loop's preview) with two static rows on a lamp scene:
// "wide" chooses Luidolt's kernel, "eye" Ritschel's. The Luidolt frame is the control frame
// convolved, by direct summation here, with the kernel computed for the session's pupil and seed
// and mapped onto the display; the Ritschel frame is not, and its glare stops at its grid's reach
// (0.42 degrees at 256 px over 10 mm) where Luidolt's still lights the display.
class LuidoltSession : public ::testing::Test {
 protected:
  void SetUp() override {
    ImageRGBA scene(32, 32, 0.0f);
    for (int y = 14; y < 18; ++y)
      for (int x = 14; x < 18; ++x)
        for (int c = 0; c < 3; ++c) scene.pixel(x, y)[c] = 2000.0f;
    write_exr((dir.path() / "lamp.exr").string(), scene);
    experiment = dir.write("experiment.toml", R"([experiment]
name = "luidolt-session"
seed = 42

[display]
width_px = 128
height_px = 64
peak_luminance_cd_m2 = 250.0

[scenes]
lamp = { file = "lamp.exr" }

[procedure]
type = "forced_choice"
stimulus_frames = 2
counterbalance_sides = false

[presentation]
question_above_stimuli = false

[glare]
mode = "static"
backend = "cpu"
wavelength_samples = 8
skip_invisible = false

[[conditions.rows]]
name = "plain"
scene_a = "lamp"
scene_b = "lamp"
glare = "control"

[[conditions.rows]]
name = "wide"
scene_a = "lamp"
scene_b = "lamp"
glare_model = "luidolt"

[[conditions.rows]]
name = "eye"
scene_a = "lamp"
scene_b = "lamp"
glare_model = "ritschel"
)");
  }
  ImageRGBA render(const std::string& condition, std::string* output = nullptr) {
    const std::string out = (dir.path() / (condition + ".exr")).string();
    const test::RunOutput result =
        test::run_glarelab({"render", experiment, "--condition", condition, "--time", "0.5", "--out", out}, dir.path());
    EXPECT_EQ(result.exit_code, 0) << result.output;
    std::printf("%s", result.output.c_str());
    if (output != nullptr) *output = result.output;
    return read_exr(out).image;
  }
  test::ScratchDir dir;
  std::string experiment;
};

TEST_F(LuidoltSession, RowsChooseTheirKernelAndEachFrameIsItsConvolution) {
  const ImageRGBA control = render("plain");
  std::string said;
  const ImageRGBA luidolt = render("wide", &said);
  const ImageRGBA ritschel = render("eye");

  // The session's pupil: the static eye adapted to the frame's mean luminance (the stage's field),
  // from the session seed, clamped to the thesis' 2-8 mm.
  const Experiment e = load_experiment(experiment);
  EyeParameters parameters;
  parameters.mode = GlareMode::static_eye;
  parameters.static_time_s = e.glare.static_time_s;
  parameters.initial_field_luminance_cd_m2 = std::max(mean_luminance(control), 1e-4);
  const double pupil_mm = std::clamp(EyeModel(parameters, 42).state_at(0.5).pupil_diameter_mm, 2.0, 8.0);
  const std::size_t at = said.find("pupil ");
  ASSERT_NE(at, std::string::npos) << said;
  EXPECT_NEAR(std::stod(said.substr(at + 6)), pupil_mm, 1e-4) << said;

  LuidoltKernelOptions options;
  options.grid_px = e.glare.grid_px;
  options.wavelength_count = e.glare.wavelength_samples;
  const LuidoltKernel kernel = luidolt_kernel(pupil_mm, 42, options);
  const Psf k = resample_psf_to_display(kernel.psf, DisplayModel(e.display).degrees_per_pixel_at_centre());
  const int half = k.size_px / 2;
  double worst = 0.0, ritschel_reach_px = 0.0, luidolt_reach_px = 0.0;
  for (int y = 0; y < control.height_px; ++y)
    for (int x = 0; x < control.width_px; ++x)
      for (int c = 0; c < 3; ++c) {
        double expected = 0.0;
        for (int py = 0; py < control.height_px; ++py)
          for (int px = 0; px < control.width_px; ++px) {
            const float lamp = control.pixel(px, py)[c];
            const int kx = x - px + half, ky = y - py + half;
            if (lamp == 0.0f || kx < 0 || ky < 0 || kx >= k.size_px || ky >= k.size_px) continue;
            expected += lamp * k.at(c, kx, ky);
          }
        worst = std::max(worst, std::abs(luidolt.pixel(x, y)[c] - expected) / 2000.0);
        // How far from the nearer lamp (centres x 31.5 and 95.5, y 31.5) each row's glare lights a pixel.
        const double from_lamps = std::min(std::hypot(x - 31.5, y - 31.5), std::hypot(x - 95.5, y - 31.5));
        if (ritschel.pixel(x, y)[c] > 1e-6f) ritschel_reach_px = std::max(ritschel_reach_px, from_lamps);
        if (luidolt.pixel(x, y)[c] > 1e-3f) luidolt_reach_px = std::max(luidolt_reach_px, from_lamps);
      }
  const double dpp = DisplayModel(e.display).degrees_per_pixel_at_centre();
  std::printf("pupil %.4f mm, grid %d px, kernel %d px on the display, centre share %.5f; worst |frame - "
              "direct convolution| / lamp %.3g; glare reaches %.2f deg (ritschel), %.2f deg (luidolt)\n",
              pupil_mm, kernel.grid_px, k.size_px, kernel.centre_share, worst, ritschel_reach_px * dpp,
              luidolt_reach_px * dpp);
  EXPECT_LT(worst, 1e-6);
  // Ritschel's square grid (256 px over 10 mm) holds +-0.42 degrees at 575 nm along its sides,
  // sqrt(2) more at its corners and 770/575 more in its red copies; Luidolt's shadow of a 2.9 mm
  // pupil (3.5 degrees) lights every pixel of the 128 x 64 display, the farthest 44.5 px from the
  // nearer lamp.
  EXPECT_LT(ritschel_reach_px * dpp, 0.42 * std::sqrt(2.0) * 770.0 / 575.0 + 2.0 * dpp);
  EXPECT_GT(luidolt_reach_px, 44.0);
  // The lamp keeps the bright centre's share (plus the glare of its own neighbours).
  EXPECT_GT(luidolt.pixel(31, 31)[1], kernel.centre_share * 2000.0);
  EXPECT_NE(ritschel.rgba, luidolt.rgba);
}

TEST(LuidoltPsfCommand, WritesTheKernelAndRefusesOtherModelsOptions) {
  test::ScratchDir dir;
  const std::string out = (dir.path() / "luidolt.exr").string();
  const test::RunOutput made = test::run_glarelab(
      {"psf", "--model", "luidolt", "--pupil-diameter-mm", "2.5", "--wavelength-samples", "4", "--out", out}, dir.path());
  ASSERT_EQ(made.exit_code, 0) << made.output;
  // 8 * 2.5 / 0.0138 = 1449.3: the smallest even 2,3,5-smooth grid above it is 1458.
  EXPECT_NE(made.output.find("grid enlarged from 512 to 1458"), std::string::npos) << made.output;
  EXPECT_EQ(even_smooth_at_least(8.0 * 2.5 / kLambdaD_mm2), 1458);
  const ExrReadResult image = read_exr(out);
  EXPECT_EQ(image.image.width_px, 1458);
  const test::RunOutput refused =
      test::run_glarelab({"psf", "--model", "luidolt", "--fresnel", "none", "--out", out}, dir.path());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("--fresnel"), std::string::npos) << refused.output;
}

}  // namespace
}  // namespace glarelab
