// The ciliary corona's radial lines in the default eye's frames (glare/analytic/ciliary_corona.h,
// glare/analytic/compact_sources.h, docs/GLARE_OPTICS.md 9.9): the frame's compact bright sources,
// each ring of a source's lines summing to 0 (so the azimuthal mean stays CIE 146's), and a
// session's saved and rendered frames whose lines along the rings at 3.5-4.5 degrees have the
// angular variance of Spencer's closed form around a disc of the lamp's size (FlareLines::normalised
// averaged over each receiving pixel, written here), falling with the lamp's size (Spencer 1995,
// section 2.2), and none for a lamp much larger than 20 arcmin.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "glare/analytic/ciliary_corona.h"
#include "glare/analytic/compact_sources.h"
#include "glare/analytic/spencer_flare_lines.h"

namespace glarelab {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;

TEST(CiliaryCorona, AnnulusAndSourceWeightsAreRaisedCosinesBetweenTheirEdges) {
  EXPECT_EQ(corona_annulus_weight(1.49), 0.0);
  EXPECT_NEAR(corona_annulus_weight(1.75), 0.5, 1e-12);
  EXPECT_EQ(corona_annulus_weight(2.0), 1.0);
  EXPECT_EQ(corona_annulus_weight(5.0), 1.0);
  EXPECT_EQ(corona_annulus_weight(8.0), 1.0);
  EXPECT_NEAR(corona_annulus_weight(8.5), 0.5, 1e-12);
  EXPECT_EQ(corona_annulus_weight(9.01), 0.0);
  EXPECT_EQ(corona_source_weight(0.5), 1.0);
  EXPECT_NEAR(corona_source_weight(0.875), 0.5, 1e-12);
  EXPECT_EQ(corona_source_weight(1.0), 0.0);
}

// A dim room (1 cd/m2, median 1), a 3 x 3 lamp of 5000 cd/m2 (over 1000 x the median), a 2 x 2
// one of 500 (under it), a 40 x 40 window of 5000 (a disc of 46 px, over the rule's 20 px), and a
// green 1 x 2 lamp of 4000.
TEST(CompactSources, AreTheSmallLampsBrightAgainstTheFrame) {
  ImageRGBA frame(200, 120, 1.0f);
  const auto fill = [&](int x0, int y0, int w, int h, float r, float g, float b) {
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) frame.pixel(x, y)[0] = r, frame.pixel(x, y)[1] = g, frame.pixel(x, y)[2] = b;
  };
  fill(20, 30, 3, 3, 5000.0f, 5000.0f, 5000.0f);
  fill(60, 30, 2, 2, 500.0f, 500.0f, 500.0f);
  fill(120, 40, 40, 40, 5000.0f, 5000.0f, 5000.0f);
  fill(90, 100, 1, 2, 0.0f, 4000.0f, 0.0f);
  CompactSourceRule rule;
  rule.largest_diameter_px = 20.0;
  // Energy: luminance times 2 (any weights; the centroid and moment are energy-weighted).
  ImageRGBA energy = frame;
  for (float& v : energy.rgba) v *= 2.0f;
  const std::vector<CompactSource> sources = compact_sources(frame, energy, rule);
  ASSERT_EQ(sources.size(), 2u);
  // Most energetic first: the white lamp (9 px x 5000 x 2 per channel), then the green one.
  EXPECT_EQ(sources[0].pixels, 9);
  EXPECT_DOUBLE_EQ(sources[0].x_px, 21.0);
  EXPECT_DOUBLE_EQ(sources[0].y_px, 31.0);
  EXPECT_DOUBLE_EQ(sources[0].energy[0], 9 * 10000.0);
  // Three pixel centres per axis (variance 2/3 each) plus each pixel's square (1/6).
  EXPECT_NEAR(sources[0].second_moment_px2, 4.0 / 3.0 + 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(sources[0].disc_diameter_px(), std::sqrt(12.0), 1e-12);
  EXPECT_EQ(sources[1].pixels, 2);
  EXPECT_DOUBLE_EQ(sources[1].y_px, 100.5);
  EXPECT_DOUBLE_EQ(sources[1].energy[0], 0.0);
  EXPECT_DOUBLE_EQ(sources[1].energy[1], 2 * 8000.0);
  // On black (median 0) the peak's 1e-3 rules: a lamp of 1e6 keeps a 500 cd/m2 patch out.
  ImageRGBA black(64, 64, 0.0f);
  for (int c = 0; c < 3; ++c) black.pixel(10, 10)[c] = 1e6f, black.pixel(40, 40)[c] = 500.0f;
  EXPECT_EQ(compact_sources(black, black, rule).size(), 1u);
  EXPECT_TRUE(compact_sources(ImageRGBA(8, 8, 0.0f), ImageRGBA(8, 8, 0.0f), rule).empty());
}

// One source's lines on a frame holding its whole annulus (0.095 degree pixels, 9 degrees = 95 px):
// every ring's sum is 0 in every channel, the channels go as the source's energy, nothing lies
// outside 1.5-9 degrees, and the lines move the pixels by a large share of the smooth veil.
TEST(CiliaryCorona, EveryRingOfASourcesLinesSumsToZero) {
  const DisplayGeometry geometry{300.0, 0.5};
  const CiliaryCorona corona(ObserverEye{40.0, 0.5}, geometry, 11);
  CompactSource source;
  source.x_px = 109.5;
  source.y_px = 109.5;
  source.energy = {2.0, 3.0, 4.0};
  source.second_moment_px2 = 0.5 + 1.0 / 6.0;  // a 2 x 2 lamp
  ImageRGBA lines(220, 220, 0.0f);
  corona.add(source, lines);
  const int rings = 110;
  std::vector<std::array<double, 3>> sum(rings, {0.0, 0.0, 0.0});
  std::vector<double> absolute(rings, 0.0), smooth(rings, 0.0);
  double outside = 0.0, worst_ratio = 0.0;
  for (int y = 0; y < 220; ++y)
    for (int x = 0; x < 220; ++x) {
      const double r = std::hypot(x - source.x_px, y - source.y_px);
      const double angle = std::atan(r * 0.5 / 300.0) * kDegPerRad;
      const float* p = lines.pixel(x, y);
      if (angle <= 1.5 || angle >= 9.0) {
        outside += std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2]);
        continue;
      }
      const auto k = static_cast<std::size_t>(std::lround(r));
      if (k >= static_cast<std::size_t>(rings)) continue;
      for (int c = 0; c < 3; ++c) sum[k][c] += p[c];
      absolute[k] += std::abs(p[1]);
      // CIE 146 (40 years, p = 0.5) per sr times the pixel's solid angle times the annulus, written out.
      const double gsf = 10.0 / std::pow(angle, 3.0) + (5.0 / (angle * angle) + 0.05 / angle) * (1.0 + std::pow(40.0 / 62.5, 4.0)) + 0.00125;
      smooth[k] += 3.0 * gsf * 300.0 * 0.25 / std::pow(300.0 * 300.0 + r * r * 0.25, 1.5) * corona_annulus_weight(angle);
      if (p[0] != 0.0f) worst_ratio = std::max(worst_ratio, std::abs(p[2] / p[0] - 2.0));
    }
  EXPECT_EQ(outside, 0.0);
  EXPECT_LT(worst_ratio, 1e-6);
  int checked = 0;
  for (int k = 0; k < rings; ++k) {
    if (smooth[k] == 0.0) continue;
    ++checked;
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(sum[k][c]), 1e-5 * absolute[k] * (c + 2) / 3.0) << "ring " << k;
    // Mean |C| over the ring against the ring's smooth energy: a point-like lamp's lines are deep.
    if (corona_annulus_weight(std::atan(k * 0.5 / 300.0) * kDegPerRad) == 1.0) {
      EXPECT_GT(absolute[k] / smooth[k], 0.3) << "ring " << k;
    }
  }
  EXPECT_GT(checked, 70);
  // A source of 1.2 degrees (a disc of 12.6 px here) has none.
  source.second_moment_px2 = std::pow(1.2 / corona.degrees_per_pixel(), 2.0) / 8.0;
  ImageRGBA none(220, 220, 0.0f);
  corona.add(source, none);
  for (std::size_t i = 0; i < none.rgba.size(); ++i)
    if (i % 4 != 3) {
      ASSERT_EQ(none.rgba[i], 0.0f);
    }
}

// A source met again is added from the values kept for it: bit for bit what a corona that keeps
// nothing adds, with any energy. A source that differs in the last bit of its centroid or second
// moment (one lamp at two luminances, its floats scaled and rounded) is the same source: it adds
// what the first added. A source a quarter pixel away, or a frame of another size, is made afresh
// (again what a fresh corona adds).
TEST(CiliaryCorona, ASourceMetAgainAddsWhatAFreshCoronaAdds) {
  const DisplayGeometry geometry{300.0, 0.5};
  const ObserverEye eye{40.0, 0.5};
  const CiliaryCorona corona(eye, geometry, 11);
  CompactSource source;
  source.x_px = 109.25;
  source.y_px = 101.5;
  source.energy = {2.0, 3.0, 4.0};
  source.second_moment_px2 = 0.5 + 1.0 / 6.0;
  // The frames start from a glare energy of their own (a few negative zeros among it), as a far
  // glare frame does: what is added, and where, must be the same bits.
  const auto start = [](int width, int height) {
    ImageRGBA frame(width, height, 0.0f);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = (x + y) % 7 == 0 ? -0.0f : 1e-3f * static_cast<float>(1 + (x * 3 + y + c) % 11);
    return frame;
  };
  const auto fresh = [&](const CompactSource& s, int width, int height) {
    ImageRGBA frame = start(width, height);
    CiliaryCorona(eye, geometry, 11).add(s, frame);
    return frame;
  };
  const auto kept = [&](const CompactSource& s, int width, int height) {
    ImageRGBA frame = start(width, height);
    corona.add(s, frame);
    return frame;
  };
  EXPECT_EQ(kept(source, 220, 210).rgba, fresh(source, 220, 210).rgba);
  CompactSource brighter = source;
  brighter.energy = {7.5, 0.25, 1e4};
  EXPECT_EQ(kept(brighter, 220, 210).rgba, fresh(brighter, 220, 210).rgba) << "met again, another energy";
  const ImageRGBA first = kept(brighter, 220, 210);
  CompactSource moved = brighter;
  moved.x_px = std::nextafter(moved.x_px, 200.0);
  const ImageRGBA moved_frame = kept(moved, 220, 210);
  EXPECT_EQ(moved_frame.rgba, fresh(moved, 220, 210).rgba);
  EXPECT_EQ(moved_frame.rgba, first.rgba) << "a centroid a last bit away is the same source";
  CompactSource shifted = brighter;
  shifted.x_px += 0.25;
  const ImageRGBA shifted_frame = kept(shifted, 220, 210);
  EXPECT_EQ(shifted_frame.rgba, fresh(shifted, 220, 210).rgba);
  EXPECT_NE(shifted_frame.rgba, first.rgba) << "a source a quarter pixel away has lines of its own";
  CompactSource lower = brighter;
  lower.y_px = std::nextafter(lower.y_px, 0.0);
  EXPECT_EQ(kept(lower, 220, 210).rgba, fresh(lower, 220, 210).rgba);
  EXPECT_EQ(kept(lower, 220, 210).rgba, first.rgba);
  CompactSource wider = brighter;
  wider.second_moment_px2 = std::nextafter(wider.second_moment_px2, 1.0);
  EXPECT_EQ(kept(wider, 220, 210).rgba, fresh(wider, 220, 210).rgba);
  EXPECT_EQ(kept(wider, 220, 210).rgba, first.rgba) << "a second moment a last bit away is the same source";
  CompactSource broader = brighter;
  broader.second_moment_px2 += 0.25;
  EXPECT_NE(kept(broader, 220, 210).rgba, first.rgba) << "a quarter square pixel broader has lines of its own";
  EXPECT_EQ(kept(brighter, 180, 230).rgba, fresh(brighter, 180, 230).rgba) << "a frame of another size";
  // More sources than are kept, then the first again.
  for (int i = 0; i < 10; ++i) {
    CompactSource other = source;
    other.x_px += 0.125 * (i + 1);
    EXPECT_EQ(kept(other, 220, 210).rgba, fresh(other, 220, 210).rgba) << "source " << i;
  }
  EXPECT_EQ(kept(source, 220, 210).rgba, fresh(source, 220, 210).rgba);
}

// A session on a black 256 x 256 display of 0.048 degree pixels (600 mm, 0.5 mm pitch; 6.1 degrees
// to each side) with one lamp of 2e6 cd/m2 on the line of sight per scene: 2 x 2 px, and discs of
// 7, 13 and 31 px (0.33, 0.62 and 1.48 degrees). The field's mean is over 100 cd/m2 with every lamp
// and the display's background is 100 cd/m2, so the pupil stays under 3 mm: no halo.
constexpr int kSide = 256;
constexpr double kDistanceMm = 600.0, kPitchMm = 0.5;
constexpr float kLampCdM2 = 2e6f;
constexpr std::uint64_t kSeed = 5;
const int kLampDiameters[] = {2, 7, 13, 31};

ImageRGBA lamp_scene(int diameter_px) {
  ImageRGBA scene(kSide, kSide, 0.0f);
  const double centre = 0.5 * kSide - 0.5;  // between the middle pixels
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const bool lit = diameter_px == 2 ? std::abs(x - centre) < 1.0 && std::abs(y - centre) < 1.0
                                        : std::hypot(x - centre, y - centre) <= 0.5 * diameter_px;
      if (lit)
        for (int c = 0; c < 3; ++c) scene.pixel(x, y)[c] = kLampCdM2;
    }
  return scene;
}

std::string corona_experiment() {
  std::string text = R"([experiment]
name = "ciliary-corona"
seed = )" + std::to_string(kSeed) + R"(

[display]
width_px = 256
height_px = 256
viewing_distance_mm = 600.0
pixel_pitch_mm = 0.5
peak_luminance_cd_m2 = 250.0
background_cd_m2 = 100.0

[observer]
age_years = 25.0
pigmentation = 0.5

[procedure]
type = "rating"
categories = ["glare"]
stimulus_frames = 1

[presentation]
question_above_stimuli = false

[scenes]
)";
  for (const int d : kLampDiameters) text += "lamp" + std::to_string(d) + " = { file = \"lamp" + std::to_string(d) + ".exr\" }\n";
  for (const int d : kLampDiameters)
    text += "\n[[conditions.rows]]\nname = \"glare" + std::to_string(d) + "\"\nscene = \"lamp" + std::to_string(d) +
            "\"\nglare = \"dynamic\"\n";
  return text;
}

// The lines along the rings whose angle from the lamp's centre lies in 3.5-4.5 degrees: the
// frame's relative modulation m = (glare - scene) / GSF(theta), over its ring's mean, less 1, and
// the closed form's e = l / (its ring's mean) - 1 with l = FlareLines::normalised about a disc of
// the lamp's area, averaged over 4 x 4 points of each pixel.
struct LineStatistics {
  double variance = 0.0;              // mean m^2
  double closed_form_variance = 0.0;  // mean e^2
  double correlation = 0.0;
  int pixels = 0;
};

LineStatistics line_statistics(const ImageRGBA& glared, const ImageRGBA& scene, const FlareLines& lines) {
  int lamp_pixels = 0;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) lamp_pixels += scene.pixel(x, y)[1] > 0.0f;
  const double degrees_per_px = std::atan(kPitchMm / kDistanceMm) * kDegPerRad;
  const double lamp_deg = 2.0 * std::sqrt(lamp_pixels / kPi) * degrees_per_px;
  const double centre = 0.5 * kSide - 0.5;
  const auto angle_deg = [](double r_px) { return std::atan(r_px * kPitchMm / kDistanceMm) * kDegPerRad; };
  struct Pixel {
    int ring;
    double m, l;
  };
  std::vector<Pixel> band;
  std::vector<double> ring_m(kSide, 0.0), ring_l(kSide, 0.0), ring_n(kSide, 0.0);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const double r = std::hypot(x - centre, y - centre), theta = angle_deg(r);
      if (theta < 3.5 || theta > 4.5) continue;
      const float* g = glared.pixel(x, y);
      const float* s = scene.pixel(x, y);
      const double difference = 0.2126 * (g[0] - s[0]) + 0.7152 * (g[1] - s[1]) + 0.0722 * (g[2] - s[2]);
      const double gsf = 10.0 / std::pow(theta, 3.0) + (5.0 / (theta * theta) + 0.05 / theta) * (1.0 + std::pow(25.0 / 62.5, 4.0)) + 0.00125;
      double l = 0.0;
      for (int b = 0; b < 4; ++b)
        for (int a = 0; a < 4; ++a) {
          const double dx = x - centre - 0.5 + (a + 0.5) / 4.0, dy = y - centre - 0.5 + (b + 0.5) / 4.0;
          l += lines.normalised(angle_deg(std::hypot(dx, dy)), std::atan2(dy, dx), lamp_deg) / 16.0;
        }
      const int k = static_cast<int>(std::lround(r));
      band.push_back({k, difference / gsf, l});
      ring_m[k] += difference / gsf, ring_l[k] += l, ring_n[k] += 1.0;
    }
  LineStatistics stats;
  double me = 0.0;
  for (const Pixel& p : band) {
    const double m = p.m / (ring_m[p.ring] / ring_n[p.ring]) - 1.0, e = p.l / (ring_l[p.ring] / ring_n[p.ring]) - 1.0;
    stats.variance += m * m;
    stats.closed_form_variance += e * e;
    me += m * e;
  }
  stats.pixels = static_cast<int>(band.size());
  stats.correlation = me / std::sqrt(stats.variance * stats.closed_form_variance);
  stats.variance /= stats.pixels;
  stats.closed_form_variance /= stats.pixels;
  return stats;
}

class CoronaSession : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const int d : kLampDiameters) write_exr((dir.path() / ("lamp" + std::to_string(d) + ".exr")).string(), lamp_scene(d));
    experiment = dir.write("experiment.toml", corona_experiment());
  }
  // Acceptance: lines in 2-8 degrees that match the closed form, fall with the lamp's size, and
  // vanish for a lamp much larger than 20 arcmin.
  static void expect_lines_as_spencer_says(const std::vector<ImageRGBA>& glared, const std::string& what) {
    const FlareLines lines(FlareLineSet::corona, kSeed);
    std::vector<double> variances;
    for (std::size_t i = 0; i < glared.size(); ++i) {
      const LineStatistics stats = line_statistics(glared[i], lamp_scene(kLampDiameters[i]), lines);
      std::printf("%s, lamp of %d px: %d pixels at 3.5-4.5 deg, angular variance %.4g (closed form %.4g, ratio %.3f), "
                  "correlation %.3f\n",
                  what.c_str(), kLampDiameters[i], stats.pixels, stats.variance, stats.closed_form_variance,
                  stats.variance / stats.closed_form_variance, stats.correlation);
      variances.push_back(stats.variance);
      if (kLampDiameters[i] == 31) {
        EXPECT_LT(stats.variance, 1e-4) << what;  // 1.48 degrees: no lines
        continue;
      }
      EXPECT_GT(stats.correlation, 0.9) << what << ", lamp " << kLampDiameters[i];
      EXPECT_NEAR(stats.variance / stats.closed_form_variance, 1.0, 0.2) << what << ", lamp " << kLampDiameters[i];
    }
    for (std::size_t i = 1; i < variances.size(); ++i) EXPECT_LT(variances[i], variances[i - 1]) << what;
  }
  test::ScratchDir dir;
  std::string experiment;
};

TEST_F(CoronaSession, RenderedFramesShowLinesFallingWithTheLampsSize) {
  std::vector<ImageRGBA> glared;
  for (const int d : kLampDiameters) {
    const auto out = dir.path() / ("glare" + std::to_string(d) + ".exr");
    const auto run = test::run_glarelab(
        {"render", experiment, "--condition", "glare" + std::to_string(d), "--out", out.string()}, dir.path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    glared.push_back(read_exr(out.string()).image);
  }
  expect_lines_as_spencer_says(glared, "render");
}

TEST_F(CoronaSession, SavedSessionFramesShowLinesFallingWithTheLampsSize) {
  const auto frames = dir.path() / "frames";
  const auto run = test::run_glarelab({"run", experiment, "--display", "offscreen", "--observer", "simulated", "--db",
                                       (dir.path() / "s.db").string(), "--save-frames", frames.string()},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // The trials come in the seed's order: each frame is known by its lamp's pixels (over half the lamp's luminance).
  std::vector<ImageRGBA> glared(std::size(kLampDiameters));
  for (int trial = 0; trial < static_cast<int>(std::size(kLampDiameters)); ++trial) {
    char name[32];
    std::snprintf(name, sizeof(name), "trial_%04d.exr", trial);
    ImageRGBA frame = read_exr((frames / name).string()).image;
    int lit = 0;
    for (int y = 0; y < kSide; ++y)
      for (int x = 0; x < kSide; ++x) lit += frame.pixel(x, y)[1] > 0.5f * kLampCdM2;
    std::size_t which = 0;
    for (std::size_t i = 0; i < std::size(kLampDiameters); ++i) {
      int lamp_pixels = 0;
      const ImageRGBA scene = lamp_scene(kLampDiameters[i]);
      for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) lamp_pixels += scene.pixel(x, y)[1] > 0.0f;
      if (lamp_pixels == lit) which = i + 1;
    }
    ASSERT_NE(which, 0u) << name << ": " << lit << " pixels over half the lamp";
    glared[which - 1] = std::move(frame);
  }
  expect_lines_as_spencer_says(glared, "run --save-frames");
}

}  // namespace
}  // namespace glarelab
