// Spencer et al. 1995's flare lines (glare/analytic/spencer_flare_lines.h, section 3.2): every ring of
// the lined kernel holds what Spencer's smooth kernel holds there (the azimuthal mean is P); the
// antialiased coverage equals a brute-force supersampling of the lines; the lines' ring contrast is
// non-zero and falls as the source grows (section 2.2), in the closed form (checked against its
// Fourier series) and in a frame convolved from disc sources; one seed gives one set of lines; the
// key is read and refused at file:line:column; the Spencer study's saved frames show the lines.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "glare/analytic/analytic_glare.h"
#include "glare/analytic/spencer_flare_lines.h"
#include "protocols/experiment.h"

namespace glarelab {
namespace {

constexpr double kPi = std::numbers::pi;
const DisplayGeometry kGeometry{600.0, 0.25};  // 0.0239 degrees per pixel at the centre

double angle_deg_of_px(double r_px) { return std::atan2(r_px * kGeometry.pixel_pitch_mm, kGeometry.viewing_distance_mm) * 180.0 / kPi; }

// Sums of a kernel's channel over the rings of pixels whose distance rounds to one integer.
std::vector<double> ring_sums(const DisplayKernel& kernel, int channel) {
  std::vector<double> sums(static_cast<std::size_t>(std::hypot(kernel.half_width_px, kernel.half_height_px)) + 2, 0.0);
  for (int dy = -kernel.half_height_px; dy <= kernel.half_height_px; ++dy)
    for (int dx = -kernel.half_width_px; dx <= kernel.half_width_px; ++dx)
      sums[static_cast<std::size_t>(std::lround(std::hypot(dx, dy)))] += kernel.at(channel, dx, dy);
  return sums;
}

AnalyticGlareOptions lined_options(SpencerRegime regime, int width, int height, std::uint64_t seed) {
  AnalyticGlareOptions options;
  options.model = GlareModel::spencer;
  options.regime = regime;
  options.eye = ObserverEye{50.0, 0.5};
  options.geometry = kGeometry;
  options.width_px = width;
  options.height_px = height;
  options.flare_lines = true;
  options.flare_seed = seed;
  return options;
}

// Acceptance 4: on every ring (to the kernel's corners) and channel the lined kernel's mean equals
// the smooth kernel's, the smooth one integrated directly from the mixture's P (no components, no
// lines), for a fixed regime with a halo and for the adaptive one.
TEST(SpencerFlareLines, AzimuthalMeanEqualsTheSmoothFilterOnEveryRing) {
  const int width = 150, height = 140;  // the kernel reaches 3.6 degrees along x: the halo inside
  for (const SpencerRegime regime : {SpencerRegime::mesopic, SpencerRegime::adaptive}) {
    AnalyticGlare lined(lined_options(regime, width, height, 11), 2);
    lined.adapt(0.5);
    const DisplayKernel flare = lined.current_kernel();
    const AnalyticPsf smooth_psf = AnalyticPsf::spencer(regime, 0.5, ObserverEye{50.0, 0.5});
    ASSERT_GT(smooth_psf.mixture().f3, 0.0);
    const DisplayKernel smooth = analytic_display_kernel(smooth_psf, kGeometry, width - 1, height - 1, 2);
    ASSERT_EQ(flare.channels, 3);
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
      const std::vector<double> a = ring_sums(flare, c), b = ring_sums(smooth, c);
      for (std::size_t r = 0; r < b.size(); ++r) {
        if (b[r] <= 0.0) continue;
        worst = std::max(worst, std::abs(a[r] / b[r] - 1.0));
        EXPECT_NEAR(a[r], b[r], 0.01 * b[r]) << "ring " << r << " channel " << c;
      }
    }
    std::printf("%s: worst ring |flare / smooth - 1| = %.2e\n", to_string(regime).c_str(), worst);
  }
  // The closed form's azimuthal mean is 1 on every ring, for a point and for discs.
  const FlareLines corona(FlareLineSet::corona, 11);
  for (double angle : {0.05, 0.5, 2.0, 8.0})
    for (double source : {0.0, 0.1, 0.5}) {
      double sum = 0.0;
      const int n = 1 << 16;
      for (int i = 0; i < n; ++i) sum += corona.normalised(angle, 2.0 * kPi * (i + 0.5) / n, source);
      EXPECT_NEAR(sum / n, 1.0, 2e-3) << angle << " deg, source " << source;
    }
}

// "Antialiased": a pixel's coverage is the fraction of its square inside each line's wedge times the
// line's intensity; a 128 x 128 supersampling of the pixel counts the same by brute force.
TEST(SpencerFlareLines, PixelCoverageIsTheAreaOfTheLinesOnThePixel) {
  const FlareLines halo(FlareLineSet::halo, 3);
  for (const auto& [dx, dy] : std::vector<std::pair<int, int>>{{0, 0}, {1, 0}, {2, -1}, {5, 3}, {-17, 40}, {130, -2}, {-300, -211}}) {
    const double r = std::hypot(dx, dy);
    const double h = FlareLines::half_width_rad(angle_deg_of_px(r));
    const int n = 128;
    double brute = 0.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = dx - 0.5 + (i + 0.5) / n, y = dy - 0.5 + (j + 0.5) / n;
        const double phi = std::atan2(y, x);
        for (const FlareLine& line : halo.lines())
          if (std::abs(std::remainder(phi - line.azimuth_rad, 2.0 * kPi)) < h) brute += line.intensity;
      }
    brute /= n * n;
    const double exact = halo.pixel_coverage(dx, dy, kGeometry);
    EXPECT_NEAR(exact, brute, 0.02 * std::max(brute, 0.05)) << dx << ", " << dy;
  }
}

// The ring's contrast (standard deviation / mean) of the closed form, sampled on n azimuths.
double contrast(const FlareLines& lines, double angle_deg, double source_deg, int n = 8192) {
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double v = lines.normalised(angle_deg, 2.0 * kPi * (i + 0.5) / n, source_deg);
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean;
}

// The same from the Fourier series: the lines sum_k a_k g(phi - phi_k), g a box of half width h
// convolved with the disc's semicircle of half width b, have the normalised variance
// sum_{m != 0} |A_m|^2 sinc^2(m h) (2 J1(m b) / (m b))^2 / A_0^2, A_m = sum_k a_k exp(-i m phi_k).
double fourier_contrast(const FlareLines& lines, double angle_deg, double source_deg, int terms) {
  const double h = FlareLines::half_width_rad(angle_deg);
  const double b = std::asin(std::sin(0.5 * source_deg * kPi / 180.0) / std::sin(angle_deg * kPi / 180.0));
  std::vector<std::complex<double>> z, step;
  double a0 = 0.0;
  for (const FlareLine& line : lines.lines()) {
    z.emplace_back(line.intensity, 0.0);
    step.push_back(std::polar(1.0, -line.azimuth_rad));
    a0 += line.intensity;
  }
  double variance = 0.0;
  for (int m = 1; m <= terms; ++m) {
    std::complex<double> am = 0.0;
    for (std::size_t k = 0; k < z.size(); ++k) am += (z[k] *= step[k]);
    const double sinc = std::sin(m * h) / (m * h), disc = 2.0 * std::cyl_bessel_j(1.0, m * b) / (m * b);
    variance += 2.0 * std::norm(am) * sinc * sinc * disc * disc;
  }
  return std::sqrt(variance) / a0;
}

// Acceptance 4 and section 2.2: the lines' contrast is non-zero and falls as the source grows; a
// source of 80 arcmin, "much larger than 20", keeps about half of the 20 arcmin source's contrast
// (the lines overlap four times as deep), and the closed form equals its Fourier series.
TEST(SpencerFlareLines, AngularVarianceFallsWithTheSourcesSize) {
  const FlareLines corona(FlareLineSet::corona, 5);
  const std::vector<double> sources_deg{0.0, 5.0 / 60.0, 20.0 / 60.0, 80.0 / 60.0};
  for (double angle : {1.0, 2.0, 4.0}) {
    std::vector<double> cv;
    for (double s : sources_deg) cv.push_back(contrast(corona, angle, s, s == 0.0 ? 1 << 16 : 8192));
    std::printf("%.0f deg: line contrast %.3f (point), %.3f (5'), %.3f (20'), %.3f (80')\n", angle, cv[0], cv[1], cv[2], cv[3]);
    EXPECT_GT(cv[0], 0.5) << angle;
    for (std::size_t i = 1; i < cv.size(); ++i) EXPECT_LT(cv[i], cv[i - 1]) << angle << " deg, source " << sources_deg[i];
    EXPECT_LT(cv[3], 0.65 * cv[2]) << angle;
    EXPECT_GT(cv[2], 0.1) << angle << ": a 20 arcmin source keeps faint lines";
    for (std::size_t i = 1; i < sources_deg.size(); ++i)
      EXPECT_NEAR(cv[i], fourier_contrast(corona, angle, sources_deg[i], 30000), 0.02 * cv[i]) << angle << " deg, " << i;
  }
}

// The frame: a disc source convolved with the lined kernel sums the lines of every pixel of the
// disc; its ring contrast at 1.2-2.1 degrees falls with the disc's size and matches the closed form
// for the disc.
TEST(SpencerFlareLines, FramesOfLargerSourcesShowFainterLines) {
  const int size = 201, centre = 100;
  AnalyticGlare glare(lined_options(SpencerRegime::photopic, size, size, 5), 2);
  const FlareLines corona(FlareLineSet::corona, 5);
  double previous = 1e9;
  for (double diameter_deg : {0.05, 1.0 / 3.0, 1.0}) {
    const double radius_px = 0.5 * diameter_deg / angle_deg_of_px(1.0);
    ImageRGBA frame(size, size), out;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        int inside = 0;  // 8 x 8 samples: the disc's area on the pixel
        for (int j = 0; j < 8; ++j)
          for (int i = 0; i < 8; ++i)
            inside += std::hypot(x - centre - 0.5 + (i + 0.5) / 8.0, y - centre - 0.5 + (j + 0.5) / 8.0) <= radius_px;
        for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = static_cast<float>(1000.0 * inside / 64.0);
        frame.pixel(x, y)[3] = 1.0f;
      }
    glare.convolve(frame, out);
    double measured = 0.0, predicted = 0.0;
    int rings = 0;
    for (int r = 50; r <= 88; r += 2, ++rings) {
      double sum = 0.0, sum2 = 0.0, n = 0.0;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
          if (std::lround(std::hypot(x - centre, y - centre)) == r) {
            const double v = out.pixel(x, y)[1];
            sum += v, sum2 += v * v, n += 1.0;
          }
      measured += std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n))) / (sum / n);
      if (diameter_deg > 0.1) predicted += contrast(corona, angle_deg_of_px(r), diameter_deg, 2048);
    }
    measured /= rings;
    predicted /= rings;
    std::printf("disc %.3f deg: ring contrast %.3f in the frame, %.3f closed form\n", diameter_deg, measured, predicted);
    EXPECT_GT(measured, 0.05);
    EXPECT_LT(measured, previous) << diameter_deg;
    previous = measured;
    if (diameter_deg > 0.1) {
      EXPECT_NEAR(measured, predicted, 0.05 * predicted) << diameter_deg;
    }
  }
}

// One seed, one set of lines: the same seed draws the same lines and kernel, another seed and the
// other set other lines; the draws are azimuths in [0, 2 pi) and intensities in [0, 1).
TEST(SpencerFlareLines, TheSameSeedGivesTheSameLines) {
  const FlareLines a(FlareLineSet::corona, 42), b(FlareLineSet::corona, 42), c(FlareLineSet::corona, 43),
      halo(FlareLineSet::halo, 42);
  ASSERT_EQ(a.lines().size(), static_cast<std::size_t>(kFlareLineCount));
  double mean = 0.0;
  int same_other_seed = 0, same_other_set = 0;
  for (std::size_t k = 0; k < a.lines().size(); ++k) {
    EXPECT_EQ(a.lines()[k].azimuth_rad, b.lines()[k].azimuth_rad);
    EXPECT_EQ(a.lines()[k].intensity, b.lines()[k].intensity);
    same_other_seed += a.lines()[k].azimuth_rad == c.lines()[k].azimuth_rad;
    same_other_set += a.lines()[k].azimuth_rad == halo.lines()[k].azimuth_rad;
    EXPECT_GE(a.lines()[k].azimuth_rad, 0.0);
    EXPECT_LT(a.lines()[k].azimuth_rad, 2.0 * kPi);
    EXPECT_GE(a.lines()[k].intensity, 0.0);
    EXPECT_LT(a.lines()[k].intensity, 1.0);
    mean += a.lines()[k].intensity / kFlareLineCount;
  }
  EXPECT_EQ(same_other_seed, 0);
  EXPECT_EQ(same_other_set, 0);
  EXPECT_NEAR(mean, 0.5, 0.05);  // 4 standard errors of 600 uniform draws
  const DisplayKernel k1 = AnalyticGlare(lined_options(SpencerRegime::photopic, 40, 30, 42), 2).current_kernel();
  const DisplayKernel k2 = AnalyticGlare(lined_options(SpencerRegime::photopic, 40, 30, 42), 2).current_kernel();
  const DisplayKernel k3 = AnalyticGlare(lined_options(SpencerRegime::photopic, 40, 30, 43), 2).current_kernel();
  EXPECT_EQ(k1.values, k2.values);
  double largest = 0.0;
  for (std::size_t i = 0; i < k1.values.size(); ++i)
    largest = std::max(largest, std::abs(k1.values[i] - k3.values[i]) / std::max(k1.values[i], 1e-300));
  EXPECT_GT(largest, 0.5) << "another seed, other lines";
}

std::string experiment_with_glare(const std::string& glare) {
  return "[experiment]\nname = \"g\"\n[scenes]\na = { file = \"a.exr\" }\n[procedure]\ntype = \"forced_choice\"\n" + glare +
         "\n[[conditions.rows]]\nname = \"one\"\nscene_a = \"a\"\nscene_b = \"a\"\n";
}

TEST(SpencerFlareLines, TheKeyIsReadAndABadValueNamesItsPlace) {
  EXPECT_FALSE(parse_experiment_text(experiment_with_glare(""), "g.toml", "/tmp").glare.spencer_flare_lines);
  const Experiment on =
      parse_experiment_text(experiment_with_glare("[glare]\nmodel = \"spencer\"\nspencer_flare_lines = true"), "g.toml", "/tmp");
  EXPECT_TRUE(on.glare.spencer_flare_lines);
  EXPECT_TRUE(parse_experiment_text(resolved_config_toml(on), "<stored>", "/").glare.spencer_flare_lines);
  std::string message = "no error";
  try {
    parse_experiment_text(experiment_with_glare("[glare]\nmodel = \"spencer\"\nspencer_flare_lines = \"yes\""), "g.toml", "/tmp");
  } catch (const ConfigError& error) {
    message = error.what();
  }
  EXPECT_NE(message.find("g.toml:9:23"), std::string::npos) << message;
  EXPECT_NE(message.find("glare.spencer_flare_lines"), std::string::npos) << message;
}

// The ring contrast of a saved frame around its brightest glared source, 1-2.4 degrees out.
double saved_frame_contrast(const ImageRGBA& image) {
  // The glare image's side: the half whose ring at 40-100 px around its brightest pixel is brighter.
  double best_mean = -1.0, best_cv = 0.0;
  for (int half = 0; half < 2; ++half) {
    int bx = 0, by = 0;
    float peak = -1.0f;
    const int x0 = half * image.width_px / 2;
    for (int y = 0; y < image.height_px; ++y)
      for (int x = x0; x < x0 + image.width_px / 2; ++x)
        if (image.pixel(x, y)[1] > peak) peak = image.pixel(x, y)[1], bx = x, by = y;
    double sx = 0.0, sy = 0.0, sw = 0.0;  // the centroid of the source's bright pixels
    for (int y = by - 20; y <= by + 20; ++y)
      for (int x = bx - 20; x <= bx + 20; ++x)
        if (image.pixel(x, y)[1] > 0.5f * peak) sx += x, sy += y, sw += 1.0;
    const double cx = sx / sw, cy = sy / sw;
    double cv = 0.0, mean = 0.0;
    int rings = 0;
    for (int r = 40; r <= 100; r += 4, ++rings) {
      double sum = 0.0, sum2 = 0.0, n = 0.0;
      for (int y = 0; y < image.height_px; ++y)
        for (int x = x0; x < x0 + image.width_px / 2; ++x)
          if (std::lround(std::hypot(x - cx, y - cy)) == r) {
            const double v = image.pixel(x, y)[1];
            sum += v, sum2 += v * v, n += 1.0;
          }
      mean += sum / n;
      cv += std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n))) / std::max(sum / n, 1e-30);
    }
    if (mean > best_mean) best_mean = mean, best_cv = cv / rings;
  }
  return best_cv;
}

// The Spencer study example (flare lines on) in an offscreen session: its saved glare frames show
// the lines around the 0.4 degree source; the same file with spencer_flare_lines = false does not.
TEST(SpencerFlareLines, TheSpencerStudysSavedFramesShowTheLines) {
  const test::ScratchDir scratch;
  std::string csv = "name,group,reference,comparison,glare,glare_gain\n";
  for (const char* group : {"alone", "context"})
    for (int i = 1; i <= 12; ++i) {
      char row[96];
      std::snprintf(row, sizeof row, "%s_%02d,%s,%s,disc,static,2\n", group, i, group,
                    std::string(group) == "alone" ? "source" : "lamp");
      csv += row;
    }
  test::write_bytes((scratch.path() / "spencer_conditions.csv").string(), csv);
  const std::string text = test::read_bytes(std::string(GLARELAB_SOURCE_DIR) + "/examples/spencer_staircase.toml");
  const std::string key = "spencer_flare_lines = true";
  ASSERT_NE(text.find(key), std::string::npos);
  std::vector<double> contrasts;
  for (const bool lines : {true, false}) {
    std::string variant = text;
    if (!lines) variant.replace(variant.find(key), key.size(), "spencer_flare_lines = false");
    const auto dir = scratch.path() / (lines ? "on" : "off");
    std::filesystem::create_directories(dir);
    test::write_bytes((dir / "spencer.toml").string(), variant);
    std::filesystem::copy_file(scratch.path() / "spencer_conditions.csv", dir / "spencer_conditions.csv");
    const auto run = test::run_glarelab({"run", (dir / "spencer.toml").string(), "--display", "offscreen", "--observer",
                                         "simulated", "--db", (dir / "s.db").string(), "--save-frames",
                                         (dir / "frames").string(), "--stop-after", "2"},
                                        dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const double cv = saved_frame_contrast(read_exr((dir / "frames" / "trial_0000.exr").string()).image);
    std::printf("flare lines %s: ring contrast %.3f around the source\n", lines ? "on" : "off", cv);
    contrasts.push_back(cv);
  }
  EXPECT_GT(contrasts[0], 0.1);
  EXPECT_LT(contrasts[1], 0.05);
}

// `psf --model spencer --flare-lines` writes the lined filter: its rings hold the smooth image's
// light, its pixels on a ring differ; the option is refused for other models.
TEST(SpencerFlareLines, PsfCommandWritesTheFlareFilter) {
  const test::ScratchDir scratch;
  const auto lined = scratch.path() / "lined.exr", smooth = scratch.path() / "smooth.exr";
  const auto a = test::run_glarelab({"psf", "--model", "spencer", "--regime", "mesopic", "--grid", "128", "--flare-lines",
                                     "--flare-seed", "9", "--out", lined.string()},
                                    scratch.path());
  ASSERT_EQ(a.exit_code, 0) << a.output;
  EXPECT_NE(a.output.find("flare lines of seed 9"), std::string::npos) << a.output;
  const auto b = test::run_glarelab({"psf", "--model", "spencer", "--regime", "mesopic", "--grid", "128", "--out",
                                     smooth.string()},
                                    scratch.path());
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const ImageRGBA x = read_exr(lined.string()).image, y = read_exr(smooth.string()).image;
  ASSERT_EQ(x.width_px, 128);
  std::vector<double> rx(100, 0.0), ry(100, 0.0);
  double ratio_max = 0.0;
  for (int row = 0; row < 128; ++row)
    for (int col = 0; col < 128; ++col) {
      const std::size_t r = static_cast<std::size_t>(std::lround(std::hypot(col - 64, row - 64)));
      rx[r] += x.pixel(col, row)[1];
      ry[r] += y.pixel(col, row)[1];
      if (r > 30 && r < 60) ratio_max = std::max(ratio_max, static_cast<double>(x.pixel(col, row)[1] / y.pixel(col, row)[1]));
    }
  for (std::size_t r = 0; r < 64; ++r) EXPECT_NEAR(rx[r], ry[r], 0.01 * ry[r] + 1e-7) << "ring " << r;
  EXPECT_GT(ratio_max, 2.0) << "the lines raise some pixels well above the smooth filter";
  const auto refused = test::run_glarelab({"psf", "--model", "cie", "--flare-lines", "--out", lined.string()}, scratch.path());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("--flare-lines"), std::string::npos) << refused.output;
}

}  // namespace
}  // namespace glarelab
