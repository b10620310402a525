// `glarelab psf` with the observer's refraction, end to end: the contract flags (--sphere-dioptres,
// --cylinder-dioptres, --axis-deg, --spectacles, --viewing-distance-m,
// --accommodation-amplitude-dioptres, --age-years, --vertex-distance-mm) run the built binary and the
// EXR it writes is checked against the closed forms; bad input exits 2 naming the flag, nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "cli_process.h"
#include "glare/wave/psf_exr.h"
#include "glare_refraction_test_support.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// 4 mm pupil on 8 mm, 512 px: PSF pixels of 0.0041 deg at 575 nm.
std::vector<std::string> psf_arguments(const std::vector<std::string>& extra, const std::string& out) {
  std::vector<std::string> arguments = {"psf", "--model", "ritschel", "--pupil-diameter-mm", "4", "--aperture-width-mm", "8", "--grid", "512"};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  arguments.push_back("--out");
  arguments.push_back(out);
  return arguments;
}

TEST(GlarePsfRefractionCommand, PresbyopeAtAQuarterMetreIsTheGeometricDisc) {
  test::ScratchDir dir;
  const auto out = (dir.path() / "presbyope.exr").string();
  const auto run = test::run_glarelab(
      psf_arguments({"--accommodation-amplitude-dioptres", "1", "--viewing-distance-m", "0.25"}, out), dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("accommodation 1 D"), std::string::npos) << run.output;
  const Psf psf = read_psf_exr(out);
  const double radius_deg = 3.0 * 2e-3 * kDegPerRad;  // 0.344 deg: 0.69 deg across
  const test::PsfMoments moments = test::psf_moments(psf, 0);
  EXPECT_NEAR(moments.xx_deg2 / (radius_deg * radius_deg / 4.0), 1.0, 0.10);
  EXPECT_NEAR(moments.yy_deg2 / (radius_deg * radius_deg / 4.0), 1.0, 0.10);

  // --age-years 60 sets the amplitude by Hofstetter, 18.5 - 18 = 0.5 D: 3.5 D are left.
  const auto aged = test::run_glarelab(psf_arguments({"--age-years", "60", "--viewing-distance-m", "0.25"}, out), dir.path());
  ASSERT_EQ(aged.exit_code, 0) << aged.output;
  EXPECT_NE(aged.output.find("amplitude 0.5 D"), std::string::npos) << aged.output;
  const double aged_radius_deg = 3.5 * 2e-3 * kDegPerRad;
  EXPECT_NEAR(test::psf_moments(read_psf_exr(out), 0).xx_deg2 / (aged_radius_deg * aged_radius_deg / 4.0), 1.0, 0.10);
}

TEST(GlarePsfRefractionCommand, ObliqueAxisOrientsTheImageAsTheObserverSeesIt) {
  test::ScratchDir dir;
  const auto out = (dir.path() / "astigmat.exr").string();
  // -3 x TABO 45 at the cornea: too strong by 3 D along 45 deg in the observer frame (up and to the
  // right): a streak 2 * 3 D * 2 mm = 0.69 deg long, rows above the centre toward the right.
  const auto run = test::run_glarelab(psf_arguments({"--sphere-dioptres", "0", "--cylinder-dioptres", "-3", "--axis-deg",
                                                     "45", "--vertex-distance-mm", "0"},
                                                    out),
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Psf psf = read_psf_exr(out);
  const test::PsfMoments moments = test::psf_moments(psf, 0);
  EXPECT_LT(test::axis_difference_deg(moments.major_angle_deg, 45.0), 1.0) << moments.major_angle_deg;
  EXPECT_NEAR(moments.semi_major_deg / (3.0 * 2e-3 * kDegPerRad), 1.0, 0.05);
  const int c = psf.size_px / 2, k = 40;
  EXPECT_GT(psf.at(0, c + k, c - k), 20.0 * psf.at(0, c - k, c - k));
}

TEST(GlarePsfRefractionCommand, OwnSpectaclesAreSharpAndAPlusCylinderIsTransposed) {
  test::ScratchDir dir;
  const auto path = [&](const std::string& name) { return (dir.path() / name).string(); };
  const auto corrected = test::run_glarelab(
      psf_arguments({"--sphere-dioptres", "-3", "--cylinder-dioptres", "-1.5", "--axis-deg", "30", "--spectacles", "-3,-1.5,30"},
                    path("corrected.exr")),
      dir.path());
  ASSERT_EQ(corrected.exit_code, 0) << corrected.output;
  EXPECT_GT(test::encircled_fraction(read_psf_exr(path("corrected.exr")), 0, 0.05), 0.9);
  // The same lenses written with a plus cylinder: transposed, and as sharp.
  const auto plus_lens = test::run_glarelab(
      psf_arguments({"--sphere-dioptres", "-3", "--cylinder-dioptres", "-1.5", "--axis-deg", "30", "--spectacles", "-4.5,1.5,120"},
                    path("plus_lens.exr")),
      dir.path());
  ASSERT_EQ(plus_lens.exit_code, 0) << plus_lens.output;
  EXPECT_NE(plus_lens.output.find("--spectacles -4.5 / 1.5 x 120 has a plus cylinder"), std::string::npos) << plus_lens.output;
  EXPECT_GT(test::encircled_fraction(read_psf_exr(path("plus_lens.exr")), 0, 0.05), 0.9);

  // -4.5 / +1.5 x 120 is the lens -3 / -1.5 x 30: the same PSF, and stderr says so.
  const auto minus = test::run_glarelab(
      psf_arguments({"--sphere-dioptres", "-3", "--cylinder-dioptres", "-1.5", "--axis-deg", "30"}, path("minus.exr")),
      dir.path());
  const auto plus = test::run_glarelab(
      psf_arguments({"--sphere-dioptres", "-4.5", "--cylinder-dioptres", "1.5", "--axis-deg", "120"}, path("plus.exr")),
      dir.path());
  ASSERT_EQ(minus.exit_code, 0) << minus.output;
  ASSERT_EQ(plus.exit_code, 0) << plus.output;
  EXPECT_NE(plus.output.find("minus-cylinder transposition -3 / -1.5 x 30"), std::string::npos) << plus.output;
  const Psf a = read_psf_exr(path("minus.exr")), b = read_psf_exr(path("plus.exr"));
  ASSERT_EQ(a.values.size(), b.values.size());
  double largest = 0.0, difference = 0.0;
  for (std::size_t k = 0; k < a.values.size(); ++k) {
    largest = std::max(largest, a.values[k]);
    difference = std::max(difference, std::abs(a.values[k] - b.values[k]));
  }
  EXPECT_LT(difference, 1e-4 * largest);
  EXPECT_LT(test::encircled_fraction(a, 0, 0.05), 0.2);
}

TEST(GlarePsfRefractionCommand, SpectralMyopeBlursBlueMoreThanRed) {
  test::ScratchDir dir;
  const auto out = (dir.path() / "spectral.exr").string();
  const auto run = test::run_glarelab(
      psf_arguments({"--sphere-dioptres", "-2", "--vertex-distance-mm", "0", "--spectral", "--wavelength-samples", "8"}, out),
      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("longitudinal chromatic aberration"), std::string::npos) << run.output;
  const Psf psf = read_psf_exr(out);
  ASSERT_EQ(psf.channels, 3);
  const double red = test::psf_moments(psf, 0).xx_deg2, blue = test::psf_moments(psf, 2).xx_deg2;
  // At 450 nm the eye is 1.0 D stronger than at 575 nm, at 650 nm 0.30 D weaker (Thibos): blue
  // blurs with about 3 D, red with about 1.7 D.
  EXPECT_GT(std::sqrt(blue / red), 1.4);
}

TEST(GlarePsfRefractionCommand, BadInputExitsTwoNamingTheFlagAndWritesNothing) {
  test::ScratchDir dir;
  const auto out = (dir.path() / "never.exr").string();
  struct Case {
    std::vector<std::string> arguments;
    std::string flag;
  };
  const std::vector<Case> cases = {
      {{"--cylinder-dioptres", "-1", "--axis-deg", "181"}, "--axis-deg"},
      {{"--cylinder-dioptres", "-1", "--axis-deg", "-5"}, "--axis-deg"},
      {{"--cylinder-dioptres", "-1"}, "--axis-deg"},
      {{"--spectacles", "abc"}, "--spectacles"},
      {{"--spectacles", "-2,-1"}, "--spectacles"},
      {{"--spectacles", "-2,x,90"}, "--spectacles"},
      {{"--spectacles", "-2,-1,200"}, "--spectacles"},
      {{"--spectacles", "-2,-1,90,4"}, "--spectacles"},
      {{"--sphere-dioptres", "nan"}, "--sphere-dioptres"},
      {{"--sphere-dioptres", "-40"}, "--sphere-dioptres"},
      {{"--age-years", "50", "--accommodation-amplitude-dioptres", "2"}, "--accommodation-amplitude-dioptres"},
      {{"--sphere-dioptres", "-2", "--fresnel", "paper"}, "--fresnel"},
      {{"--spectacles", "-2,0,0", "--viewing-distance-m", "0.01"}, "--viewing-distance-m"},
      {{"--viewing-distance-m", "0"}, "--viewing-distance-m"},
      // 200 D at a 5 mm distance with a cylinder: no grid up to 8192 samples its phase.
      {{"--viewing-distance-m", "0.005", "--accommodation-amplitude-dioptres", "0", "--cylinder-dioptres", "-1",
        "--axis-deg", "10"},
       "--viewing-distance-m"},
  };
  for (const Case& bad : cases) {
    const auto run = test::run_glarelab(psf_arguments(bad.arguments, out), dir.path());
    std::string joined;
    for (const std::string& argument : bad.arguments) joined += argument + " ";
    EXPECT_EQ(run.exit_code, 2) << joined << "\n" << run.output;
    EXPECT_NE(run.output.find(bad.flag), std::string::npos) << joined << "\n" << run.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << joined;
  }
  // The refraction is the wave-optics eye's: refused for the analytic models.
  const auto spencer = test::run_glarelab({"psf", "--model", "spencer", "--sphere-dioptres", "-2", "--out", out}, dir.path());
  EXPECT_EQ(spencer.exit_code, 2) << spencer.output;
  EXPECT_NE(spencer.output.find("--sphere-dioptres"), std::string::npos) << spencer.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  // The sampling refusal names the grid it needs.
  const auto aliased = test::run_glarelab(psf_arguments(cases.back().arguments, out), dir.path());
  EXPECT_NE(aliased.output.find("needs a grid of"), std::string::npos) << aliased.output;
}

// Every --backend computes the refraction itself, as a session's frame engine does
// (stimuli/frame_engine.h, engine_glare_backend): "auto" (the planned float32 path on a CPU, GL on a
// hardware GPU) and "gl" within 1e-5 of the float64 reference's peak ("cpu", the default), on the
// aperture grid (--model ritschel) and at the display's scale (--model human, whose near field is the
// wave-optics PSF).
TEST(GlarePsfRefractionCommand, EveryBackendComputesTheRefractionWithinTheReference) {
  test::ScratchDir dir;
  const auto path = [&](const std::string& name) { return (dir.path() / name).string(); };
  const std::vector<std::vector<std::string>> models = {
      {"psf", "--model", "ritschel", "--pupil-diameter-mm", "4", "--aperture-width-mm", "8", "--grid", "256"},
      {"psf", "--model", "human", "--mode", "static", "--aperture-width-mm", "10", "--grid", "256"}};
  for (const std::vector<std::string>& model : models) {
    Psf reference;
    for (const std::string backend : {"cpu", "auto", "gl"}) {
      std::vector<std::string> arguments = model;
      for (const char* extra : {"--spectral", "--wavelength-samples", "8", "--sphere-dioptres", "-0.5", "--backend"})
        arguments.push_back(extra);
      arguments.push_back(backend);
      arguments.push_back("--out");
      arguments.push_back(path(model[2] + "_" + backend + ".exr"));
      const auto run = test::run_glarelab(arguments, dir.path());
      ASSERT_EQ(run.exit_code, 0) << model[2] << " " << backend << "\n" << run.output;
      EXPECT_NE(run.output.find("computes the observer's refraction"), std::string::npos) << run.output;
      EXPECT_EQ(run.output.find("aliased"), std::string::npos) << run.output;  // a grid that samples every wavelength
      const Psf psf = read_psf_exr(path(model[2] + "_" + backend + ".exr"));
      if (backend == std::string("cpu")) {
        EXPECT_NE(run.output.find("glare backend cpu float64"), std::string::npos) << run.output;
        reference = psf;
        continue;
      }
      ASSERT_EQ(psf.values.size(), reference.values.size());
      double largest = 0.0, peak = 0.0;
      for (std::size_t i = 0; i < psf.values.size(); ++i) {
        largest = std::max(largest, std::abs(psf.values[i] - reference.values[i]));
        peak = std::max(peak, reference.values[i]);
      }
      std::printf("psf --model %s --backend %s with a refraction: max |difference| / peak %.3g\n", model[2].c_str(),
                  backend.c_str(), largest / peak);
      EXPECT_LT(largest, 1e-5 * peak) << model[2] << " " << backend;
      // Computed by the backend chosen, not handed over by the reference: GL's float32 transforms
      // differ in the file's float32 values; the planned CPU path's are float64 like the reference's
      // (its own transforms, tests/glare_cpu_planned_chromatic_test.cpp), so the file names it.
      // "auto" takes GL on a hardware GPU (an NVIDIA H200, say) and the planned CPU path elsewhere.
      const bool on_gl = backend == std::string("gl") ||
                         run.output.find("glare backend auto picked gl") != std::string::npos;
      if (on_gl)
        EXPECT_NE(psf.values, reference.values) << model[2] << " " << backend;
      else
        EXPECT_NE(run.output.find("psf: cpu float32 planned computes the observer's refraction"), std::string::npos) << run.output;
    }
  }
}

}  // namespace
}  // namespace glarelab
