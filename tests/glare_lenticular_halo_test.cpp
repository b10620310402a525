// The human eye's lenticular halo (glare/analytic/lenticular_halo.h, docs/GLARE_OPTICS.md 9.8):
// the ring against the grating equation sin(theta) = lambda / e and the K-slit lobe's width, its
// energy against the binary grating's Fourier coefficient and the patches' area, and a session's
// saved frame (a point lamp, a 6 mm pupil) whose azimuthal mean peaks at 3.0 degrees, red outside
// blue, while a 2.5 mm pupil shows no ring above the smooth CIE 146 profile.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "glare/analytic/lenticular_halo.h"
#include "glare/eye/eye_model.h"
#include "glare/wave/cie_cmf.h"

namespace glarelab {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;
// The eye model's fibre period: 568 nm / sin(3 deg) (Spencer 1995, 3.1.1).
constexpr double kPeriodNm = 568.0 / 0.052335956242943835;

// The grating equation, written out.
double first_order_deg(double wavelength_nm) { return std::asin(wavelength_nm / kPeriodNm) * kDegPerRad; }

TEST(LenticularHalo, EachWavelengthsRingLiesWhereTheGratingEquationPutsIt) {
  const LenticularHalo halo{HaloGratings{}};
  for (const double nm : {450.0, 568.0, 650.0}) {
    // Per steradian and per radian of theta (the ring's energy per unit of its radius).
    double best_sr = 0.0, best_sr_deg = 0.0, best_radial = 0.0, best_radial_deg = 0.0, energy = 0.0;
    const double step = 0.0002;
    for (double a = 0.5; a < 8.0; a += step) {
      const double density = halo.per_sr_at_wavelength(a, nm);
      const double radial = density * 2.0 * kPi * std::sin(a / kDegPerRad);
      energy += radial * step / kDegPerRad;
      if (density > best_sr) best_sr = density, best_sr_deg = a;
      if (radial > best_radial) best_radial = radial, best_radial_deg = a;
    }
    // Half maximum of the radial density: the K-slit lobe's FWHM 0.886 lambda / (K e cos theta).
    double low = 0.0, high = 0.0;
    for (double a = 0.5; a < 8.0; a += step) {
      const double radial = halo.per_sr_at_wavelength(a, nm) * 2.0 * kPi * std::sin(a / kDegPerRad);
      if (radial >= 0.5 * best_radial) {
        if (low == 0.0) low = a;
        high = a;
      }
    }
    const double expected_fwhm = 0.886 * nm / (8.0 * kPeriodNm * std::cos(first_order_deg(nm) / kDegPerRad)) * kDegPerRad;
    std::printf("%.0f nm: asin(lambda / e) %.4f deg, radial peak %.4f, per-sr peak %.4f, FWHM %.4f (K-slit %.4f), energy %.6f\n",
                nm, first_order_deg(nm), best_radial_deg, best_sr_deg, high - low, expected_fwhm, energy);
    EXPECT_NEAR(halo.first_order_deg(nm), first_order_deg(nm), 1e-9);
    // The slit envelope and 1/sin(theta) pull the peaks in by about 0.01 degrees.
    EXPECT_NEAR(best_radial_deg, first_order_deg(nm), 0.02) << nm;
    EXPECT_NEAR(best_sr_deg, first_order_deg(nm), 0.03) << nm;
    EXPECT_NEAR(high - low, expected_fwhm, 0.1 * expected_fwhm) << nm;
    EXPECT_NEAR(energy, 1.0, 1e-4) << nm;
  }
  // White light: each channel has unit energy, red's ring outside green's outside blue's.
  std::array<double, 3> peak_deg{0.0, 0.0, 0.0};
  for (int c = 0; c < 3; ++c) {
    double best = 0.0, energy = 0.0;
    const double step = 0.0005;
    for (double a = 0.5; a < 8.0; a += step) {
      const double density = halo.per_sr(a, c);
      energy += density * 2.0 * kPi * std::sin(a / kDegPerRad) * step / kDegPerRad;
      if (density > best) best = density, peak_deg[c] = a;
    }
    EXPECT_NEAR(energy, 1.0, 1e-3) << c;
  }
  std::printf("white: peaks R %.3f, G %.3f, B %.3f deg\n", peak_deg[0], peak_deg[1], peak_deg[2]);
  EXPECT_GT(peak_deg[0], peak_deg[1]);
  EXPECT_GT(peak_deg[1], peak_deg[2]);
}

// A white (D65) lamp's ring as the eye sees it: its luminance at theta is
// Int V(lambda) D65(lambda) ring_lambda(theta) dlambda over Int V D65, written out here on 1 nm
// steps from the single-wavelength rings. The channels' Rec.709 luminance must follow it: it peaks
// where that integral does, within 0.01 degrees, and keeps its shape within the light that taking
// the out-of-gamut colours towards grey and restoring each channel's energy moves (measured 5 % of
// the peak). No channel is negative anywhere.
TEST(LenticularHalo, WhiteLampsLuminanceRingIsTheVWeightedSpectralRing) {
  const LenticularHalo halo{HaloGratings{}};
  std::vector<double> v_d65;
  double norm = 0.0;
  for (int nm = 380; nm <= 780; ++nm) {
    v_d65.push_back(cie1931_cmf(nm).y * cie_d65_relative_power(nm));
    norm += v_d65.back();
  }
  double exact_peak = 0.0, exact_deg = 0.0, channels_peak = 0.0, channels_deg = 0.0, worst = 0.0, lowest = 0.0;
  std::vector<std::pair<double, double>> pairs;
  for (double a = 1.0; a < 6.5; a += 0.001) {
    double exact = 0.0;
    for (int nm = 380; nm <= 780; ++nm) exact += v_d65[static_cast<std::size_t>(nm - 380)] * halo.per_sr_at_wavelength(a, nm);
    exact /= norm;
    const double channels = 0.2126 * halo.per_sr(a, 0) + 0.7152 * halo.per_sr(a, 1) + 0.0722 * halo.per_sr(a, 2);
    for (int c = 0; c < 3; ++c) lowest = std::min(lowest, halo.per_sr(a, c));
    if (exact > exact_peak) exact_peak = exact, exact_deg = a;
    if (channels > channels_peak) channels_peak = channels, channels_deg = a;
    pairs.emplace_back(exact, channels);
  }
  for (const auto& [exact, channels] : pairs) worst = std::max(worst, std::abs(channels - exact) / exact_peak);
  std::printf("white lamp: V-weighted ring peaks at %.3f deg (per sr), the channels' luminance at %.3f; largest "
              "difference %.4f of the peak; lowest channel value %.3g\n",
              exact_deg, channels_deg, worst, lowest);
  EXPECT_NEAR(channels_deg, exact_deg, 0.03);
  EXPECT_LT(worst, 0.07);
  EXPECT_GE(lowest, 0.0);
  // The V-weighted ring itself lies between asin(540 nm / e) and asin(568 nm / e).
  EXPECT_GT(exact_deg, first_order_deg(540.0));
  EXPECT_LT(exact_deg, first_order_deg(568.0));
  const DisplayKernel kernel = lenticular_halo_kernel(halo, DisplayGeometry{600.0, 0.5});
  EXPECT_GE(*std::min_element(kernel.values.begin(), kernel.values.end()), 0.0);
}

// 2 ((1 - t) sin(pi f) / pi)^2, the +-1 orders of a binary amplitude grating; one line across the
// pupil counted for its length inside; the eye model's 200 patches of K lines, 0.6 mm long, all
// inside a 12 mm disc: K e L each.
TEST(LenticularHalo, EnergyIsTheFirstOrdersOfThePatchesInsideThePupil) {
  const HaloGratings gratings;
  EXPECT_NEAR(first_order_efficiency(gratings), 2.0 * std::pow(0.5 / kPi, 2), 1e-15);
  EXPECT_NEAR(first_order_efficiency(HaloGratings{0.01, 8, 0.25, 0.0}), 2.0 * std::pow(std::sin(kPi / 4.0) / kPi, 2), 1e-15);
  // A radial line from 1 to 4 mm, 5 um wide: 2 mm of it inside a 6 mm pupil.
  const ApertureLine line{1.0 / std::sqrt(2.0), 1.0 / std::sqrt(2.0), 4.0 / std::sqrt(2.0), 4.0 / std::sqrt(2.0), 0.005, 0.5};
  EXPECT_NEAR(lenticular_halo_energy({line}, gratings, 6.0), 0.005 * 2.0 / 0.5 / (kPi * 9.0) * first_order_efficiency(gratings),
              1e-15);
  EXPECT_EQ(lenticular_halo_energy({line}, gratings, 1.8), 0.0);

  const EyeParameters parameters;
  const EyeModel eye(parameters, 7);
  const std::vector<ApertureLine>& lines = eye.lens().grating_lines();
  ASSERT_EQ(lines.size(), 200u * 8u);
  const HaloGratings model = halo_gratings(parameters);
  const double all_patches_mm2 = 200.0 * 8.0 * parameters.lens_grating_period_mm * parameters.lens_grating_length_mm;
  EXPECT_NEAR(lenticular_halo_energy(lines, model, 12.0), all_patches_mm2 / (kPi * 36.0) * first_order_efficiency(model), 1e-12);
  // The clear central lens: a pupil under 3 mm meets no grating (Spencer 2.1).
  EXPECT_EQ(lenticular_halo_energy(lines, model, 2.5), 0.0);
  EXPECT_EQ(lenticular_halo_energy(lines, model, 2.95), 0.0);
  double previous = 0.0;
  for (const double pupil : {3.5, 4.5, 6.0, 7.5}) {
    const double energy = lenticular_halo_energy(lines, model, pupil);
    std::printf("pupil %.1f mm: halo energy %.5f\n", pupil, energy);
    EXPECT_GT(energy, 0.0);
    EXPECT_LT(energy, first_order_efficiency(model));
    if (pupil <= 6.0) {
      EXPECT_GT(energy, previous) << pupil;
    }
    previous = energy;
  }
}

// The kernel integrates the ring over each display pixel: every channel's sum is the ring's unit
// energy when the display holds the whole ring.
TEST(LenticularHalo, KernelHoldsTheRingsEnergy) {
  const LenticularHalo halo{HaloGratings{}};
  for (const double pitch_mm : {0.25, 1.0}) {
    const DisplayKernel kernel = lenticular_halo_kernel(halo, DisplayGeometry{600.0, pitch_mm});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(kernel.energy(c), 1.0, 2e-3) << pitch_mm << " " << c;
  }
}

// Each kernel pixel is the ring integrated over that pixel's solid angle: the midpoint rule on
// subsamples of at most 0.01 degrees (at least 3 a side), written out here for offsets in each of
// the eight octants the kernel is made from by symmetry, on and beside the ring and off its axes
// and diagonals, at a pitch whose subsamples are 3 a side and at one whose are 5.
TEST(LenticularHalo, EachKernelPixelIsTheRingIntegratedOverThatPixel) {
  const LenticularHalo halo{HaloGratings{}};
  constexpr double kDistance = 600.0;
  for (const double pitch_mm : {0.25, 0.5}) {
    const DisplayKernel kernel = lenticular_halo_kernel(halo, DisplayGeometry{kDistance, pitch_mm});
    const double pixel_deg = std::atan(pitch_mm / kDistance) * kDegPerRad;
    const int n = std::max(3, static_cast<int>(std::ceil(pixel_deg / 0.01)));
    const int ring_px = static_cast<int>(std::lround(kDistance * std::tan(3.0 / kDegPerRad) / pitch_mm));
    double peak = 0.0;
    for (const double value : kernel.values) peak = std::max(peak, value);
    int compared = 0;
    for (const auto& [dx, dy] : std::vector<std::pair<int, int>>{{ring_px, 0},
                                                                {0, -ring_px},
                                                                {ring_px - 9, 31},
                                                                {31, ring_px - 9},
                                                                {-31, ring_px - 9},
                                                                {-(ring_px - 9), 31},
                                                                {-(ring_px - 9), -31},
                                                                {-31, -(ring_px - 9)},
                                                                {31, -(ring_px - 9)},
                                                                {ring_px - 9, -31},
                                                                {ring_px * 7 / 10, ring_px * 7 / 10},
                                                                {-ring_px / 2, ring_px * 9 / 10},
                                                                {ring_px / 3, -ring_px / 4}}) {
      std::array<double, 3> sum{0.0, 0.0, 0.0};
      const double sub = pitch_mm / n;
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
          const double x = (dx - 0.5 + (a + 0.5) / n) * pitch_mm, y = (dy - 0.5 + (b + 0.5) / n) * pitch_mm;
          const double r2 = x * x + y * y;
          const double angle_deg = std::atan(std::sqrt(r2) / kDistance) * kDegPerRad;
          // The solid angle of a small flat patch at distance sqrt(d^2 + r^2), tilted by the angle.
          const double solid_angle = kDistance * sub * sub / std::pow(kDistance * kDistance + r2, 1.5);
          for (int c = 0; c < 3; ++c) sum[static_cast<std::size_t>(c)] += halo.per_sr(angle_deg, c) * solid_angle;
        }
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(kernel.at(c, dx, dy), sum[static_cast<std::size_t>(c)], 1e-12 * peak)
            << pitch_mm << " mm, (" << dx << ", " << dy << ") channel " << c;
        compared += sum[static_cast<std::size_t>(c)] > 1e-3 * peak ? 1 : 0;
      }
    }
    EXPECT_GT(compared, 12) << "the offsets lie on the ring";  // most of them carry light
  }
}

// A session: a 2 x 2 px white lamp on the line of sight of a black 256 x 256 display of 0.048
// degree pixels (600 mm, 0.5 mm pitch; 6.1 degrees to each side), observer 25 years.
constexpr int kSide = 256;
constexpr double kDistanceMm = 600.0, kPitchMm = 0.5;

std::string halo_experiment(const std::string& eye_table) {
  return R"([experiment]
name = "lenticular-halo"
seed = 5

[display]
width_px = 256
height_px = 256
viewing_distance_mm = 600.0
pixel_pitch_mm = 0.5
peak_luminance_cd_m2 = 250.0

[observer]
age_years = 25.0
pigmentation = 0.5

[scenes]
lamp = { file = "lamp.exr" }

[procedure]
type = "rating"
categories = ["glare"]
stimulus_frames = 1

[presentation]
question_above_stimuli = false
)" + eye_table + R"(
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

// Azimuthal means of glare - control on 1-pixel rings about the lamp's centre (the display's), per
// channel and as Rec.709 luminance (index 3), with the ring's angle.
struct Rings {
  std::vector<double> angle_deg;
  std::vector<std::array<double, 4>> mean;
};
Rings ring_means(const ImageRGBA& glare, const ImageRGBA& control) {
  Rings rings;
  const int count = kSide / 2;
  std::vector<std::array<double, 4>> sum(static_cast<std::size_t>(count), {0.0, 0.0, 0.0, 0.0});
  std::vector<double> n(static_cast<std::size_t>(count), 0.0);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const auto k = static_cast<std::size_t>(std::lround(std::hypot(x + 0.5 - 0.5 * kSide, y + 0.5 - 0.5 * kSide)));
      if (k >= sum.size()) continue;
      std::array<double, 3> d{};
      for (int c = 0; c < 3; ++c) d[c] = static_cast<double>(glare.pixel(x, y)[c]) - control.pixel(x, y)[c];
      for (int c = 0; c < 3; ++c) sum[k][c] += d[c];
      sum[k][3] += 0.2126 * d[0] + 0.7152 * d[1] + 0.0722 * d[2];
      n[k] += 1.0;
    }
  for (int k = 0; k < count; ++k) {
    rings.angle_deg.push_back(std::atan(k * kPitchMm / kDistanceMm) * kDegPerRad);
    std::array<double, 4> m{};
    for (int c = 0; c < 4; ++c) m[c] = sum[static_cast<std::size_t>(k)][c] / n[static_cast<std::size_t>(k)];
    rings.mean.push_back(m);
  }
  return rings;
}

class LenticularHaloSession : public ::testing::Test {
 protected:
  // The lamp's luminance sets the field's mean and so the pupil (Eq. 2) unless [glare.eye] holds it.
  void write(float lamp_cd_m2, const std::string& eye_table) {
    ImageRGBA scene(kSide, kSide, 0.0f);
    for (int y = kSide / 2 - 1; y <= kSide / 2; ++y)
      for (int x = kSide / 2 - 1; x <= kSide / 2; ++x)
        for (int c = 0; c < 3; ++c) scene.pixel(x, y)[c] = lamp_cd_m2;
    write_exr((dir.path() / "lamp.exr").string(), scene);
    experiment = dir.write("experiment.toml", halo_experiment(eye_table));
  }
  test::ScratchDir dir;
  std::string experiment;
};

// Acceptance 3: a 6 mm pupil (held by [glare.eye]) uncovers the gratings; the saved frame's ring
// has a ring near asin(568 nm / e) = 3.0 degrees, red outside green outside blue, well
// above the smooth profile there. Without the halo the azimuthal mean falls monotonically through
// the band: it has no local maximum there.
TEST_F(LenticularHaloSession, SavedFrameShowsTheHaloAtThreeDegreesWithASixMillimetrePupil) {
  write(1e7f, "\n[glare.eye]\npupil_min_diameter_mm = 6.0\n");
  const auto frames = dir.path() / "frames";
  const auto run = test::run_glarelab({"run", experiment, "--display", "offscreen", "--observer", "simulated", "--db",
                                       (dir.path() / "s.db").string(), "--save-frames", frames.string()},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const ImageRGBA first = read_exr((frames / "trial_0000.exr").string()).image;
  const ImageRGBA second = read_exr((frames / "trial_0001.exr").string()).image;
  const bool first_is_control = first.pixel(0, 0)[1] == 0.0f;
  ASSERT_NE(first_is_control, second.pixel(0, 0)[1] == 0.0f) << "one glare frame, one control frame";
  const ImageRGBA& glared = first_is_control ? second : first;
  const Rings rings = ring_means(glared, first_is_control ? first : second);
  // The ring's colours outside Rec.709 are taken to grey before they reach the frame: no channel of
  // any pixel is negative (with signed weights red's lobe near 2.7 degrees would outweigh the veil).
  float lowest = 0.0f;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      for (int c = 0; c < 3; ++c) lowest = std::min(lowest, glared.pixel(x, y)[c]);
  EXPECT_GE(lowest, 0.0f);
  // The smooth profile: the lamp's illuminance at the eye times CIE 146's GSF (25 years, p = 0.5),
  // written out; the default eye's veil is that within 1 % (tests/glare_human_eye_test.cpp).
  const double illuminance_lx = 4.0 * 1e7 * kPitchMm * kPitchMm / (kDistanceMm * kDistanceMm);
  const auto smooth_cd_m2 = [&](double deg) {
    return illuminance_lx * (10.0 / std::pow(deg, 3.0) + (5.0 / (deg * deg) + 0.05 / deg) * (1.0 + std::pow(25.0 / 62.5, 4.0)) +
                             0.00125);
  };
  // The ring: the brightest local maximum of the luminance between 2 and 4.5 degrees (the smooth
  // profile has none), and each channel's largest excess over the smooth profile.
  std::size_t at = 0;
  std::array<double, 3> excess_peak_deg{0.0, 0.0, 0.0}, excess_best{-1e300, -1e300, -1e300};
  for (std::size_t k = 1; k + 1 < rings.angle_deg.size(); ++k) {
    if (rings.angle_deg[k] < 2.0 || rings.angle_deg[k] > 4.5) continue;
    if (rings.mean[k][3] > rings.mean[k - 1][3] && rings.mean[k][3] >= rings.mean[k + 1][3] &&
        (at == 0 || rings.mean[k][3] > rings.mean[at][3]))
      at = k;
    for (int c = 0; c < 3; ++c)
      if (rings.mean[k][c] - smooth_cd_m2(rings.angle_deg[k]) > excess_best[c])
        excess_best[c] = rings.mean[k][c] - smooth_cd_m2(rings.angle_deg[k]), excess_peak_deg[c] = rings.angle_deg[k];
  }
  ASSERT_GT(at, 0u) << "no ring between 2 and 4.5 degrees";
  const double contrast = rings.mean[at][3] / smooth_cd_m2(rings.angle_deg[at]);
  std::printf("6 mm pupil: ring at %.3f deg (asin(568 nm / e) %.3f), %.2f x the smooth profile there; channels' rings "
              "R %.3f, G %.3f, B %.3f deg\n",
              rings.angle_deg[at], first_order_deg(568.0), contrast, excess_peak_deg[0], excess_peak_deg[1], excess_peak_deg[2]);
  // Acceptance 3: the luminance ring at 3.0 +- 0.15 degrees. The frame's white lamp is D65, whose
  // V(lambda)-weighted ring peaks at 2.88 degrees per steradian (the test above); on CIE 146's
  // falling veil the sum peaks about 0.03 degrees further in, on the 0.048 degree rings here.
  EXPECT_NEAR(rings.angle_deg[at], first_order_deg(568.0), 0.15);
  EXPECT_NEAR(excess_peak_deg[0], first_order_deg(600.0), 0.15);
  EXPECT_NEAR(excess_peak_deg[2], first_order_deg(450.0), 0.15);
  EXPECT_GT(excess_peak_deg[0], excess_peak_deg[1]);
  EXPECT_GT(excess_peak_deg[1], excess_peak_deg[2]);
  EXPECT_GT(contrast, 1.5);
}

// With a 2.5 mm pupil (the field's mean 100 cd/m2) no grating is uncovered: through the halo's
// band the azimuthal mean falls ring by ring, as CIE 146's profile does. A session's dynamic eye
// starts adapted to what the participant saw before the first frame, the display's background
// (docs/PERCEPTION.md): the background is the field's mean here, so the pupil is 2.5 mm from the
// first frame (the scene covers the whole display, so the background itself is not shown).
TEST_F(LenticularHaloSession, RenderedFrameHasNoRingWithATwoAndAHalfMillimetrePupil) {
  write(100.0f * kSide * kSide / 4.0f, "");
  {
    std::ifstream in(experiment);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string peak = "peak_luminance_cd_m2 = 250.0\n";
    ASSERT_NE(text.find(peak), std::string::npos);
    text.replace(text.find(peak), peak.size(), peak + "background_cd_m2 = 100.0\n");
    std::ofstream(experiment) << text;
  }
  const auto render = [&](const std::string& condition) {
    const auto out = dir.path() / (condition + ".exr");
    const auto run = test::run_glarelab({"render", experiment, "--condition", condition, "--out", out.string()}, dir.path());
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return read_exr(out.string()).image;
  };
  const Rings rings = ring_means(render("glare"), render("control"));
  int rises = 0;
  for (std::size_t k = 1; k < rings.angle_deg.size(); ++k)
    if (rings.angle_deg[k] >= 1.5 && rings.angle_deg[k] <= 4.5 && rings.mean[k][3] > rings.mean[k - 1][3]) ++rises;
  std::printf("2.5 mm pupil: %d rings between 1.5 and 4.5 degrees brighter than the ring inside them\n", rises);
  EXPECT_EQ(rises, 0);
}

}  // namespace
}  // namespace glarelab
