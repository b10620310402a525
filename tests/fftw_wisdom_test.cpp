// Measured FFTW plans kept in a wisdom file (glare/cpu/fftw_wisdom.h): the planned float32 convolution
// measures its plans once, writes them to the file and reads them back in every later planning, in
// this process or another, for the same bits; where no file can be kept its plans are estimated.
// Every result is checked against the float64 convolution (convolve_image_cpu).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli_process.h"
#include "core/exr_io.h"
#include "glare/cpu/convolution.h"
#include "glare/cpu/float_convolution.h"
#include "glare/cpu/fft.h"
#include "glare/cpu/fftw_float_plan.h"
#include "glare/cpu/fftw_wisdom.h"
#include "glare_psf_test_support.h"
#include "scratch_dir.h"
#include "session_events.h"

namespace glarelab {
namespace {

// A scene with a few bright pixels on a dim, varied background (the PSF: test::lopsided_psf).
ImageRGBA test_scene(int width, int height) {
  ImageRGBA image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      for (int c = 0; c < 3; ++c) p[c] = 0.5f + 0.01f * static_cast<float>((x * 7 + y * 3 + c * 5) % 11);
      p[3] = 1.0f;
    }
  image.pixel(width / 3, height / 2)[0] = 4000.0f;
  image.pixel(2 * width / 3, height / 4)[1] = 2500.0f;
  return image;
}

// The float32 convolution of the test scene, planned now with whatever wisdom place is in use.
ImageRGBA convolve_float(const ImageRGBA& scene, const Psf& psf) {
  CpuFloatConvolution convolution(scene.width_px, scene.height_px, psf.size_px);
  convolution.set_scene(scene);
  ImageRGBA out;
  convolution.convolve(psf, out);
  return out;
}

// Largest |float - double| relative to the double result's largest value.
double relative_error(const ImageRGBA& result, const ImageRGBA& reference) {
  double largest = 0.0, error = 0.0;
  for (std::size_t k = 0; k < reference.rgba.size(); ++k) {
    if (k % 4 == 3) continue;
    largest = std::max(largest, std::abs(static_cast<double>(reference.rgba[k])));
    error = std::max(error, std::abs(static_cast<double>(result.rgba[k]) - reference.rgba[k]));
  }
  return error / largest;
}

class FftwWisdom : public ::testing::Test {
 protected:
  // Each test chooses its own file; the process's place is put back afterwards to what it was, so
  // that tests run after these in the same process plan as the sessions they start do (with "none"
  // left behind, a test comparing an in-process frame with a child session's got estimated plans
  // against the child's measured ones: other rounding, 2e-5 apart on dim pixels).
  void SetUp() override { place_before_ = fftw_wisdom_place(); }
  void TearDown() override { use_fftw_wisdom_file(place_before_.kept() ? place_before_.path : "none"); }
  test::ScratchDir scratch_;
  FftwWisdomPlace place_before_;
};

TEST_F(FftwWisdom, KeptPlansAreMeasuredOnceAndReadBackForTheSameBits) {
  const std::filesystem::path file = scratch_.path() / "cache" / "fftwf.wisdom";
  use_fftw_wisdom_file(file.string());
  ASSERT_TRUE(fftw_wisdom_place().kept()) << fftw_wisdom_place().reason;
  EXPECT_EQ(fftw_wisdom_place().describe(), "FFTW plans measured once and kept in " + file.string());
  const ImageRGBA scene = test_scene(96, 64);
  const Psf psf = test::lopsided_psf(31);
  const ImageRGBA reference = convolve_image_cpu(scene, psf, ConvolutionOptions{});

  const ImageRGBA first = convolve_float(scene, psf);
  EXPECT_LT(relative_error(first, reference), 1e-6);
  ASSERT_TRUE(std::filesystem::exists(file));
  const std::string wisdom = test::read_bytes(file.string());
  EXPECT_EQ(wisdom.rfind("(fftw-3", 0), 0u) << wisdom.substr(0, 80);
  EXPECT_TRUE(std::filesystem::exists(file.string() + ".lock"));

  // As a new process would: nothing in memory, the plans read from the file. The same bits, and
  // the file unchanged (nothing was measured again).
  forget_fftw_float_wisdom();
  const ImageRGBA second = convolve_float(scene, psf);
  EXPECT_EQ(second.rgba, first.rgba);
  EXPECT_EQ(test::read_bytes(file.string()), wisdom);

  // A new size adds its plans to the file and keeps the old ones.
  const ImageRGBA other_scene = test_scene(70, 50);
  const ImageRGBA other = convolve_float(other_scene, psf);
  EXPECT_LT(relative_error(other, convolve_image_cpu(other_scene, psf, ConvolutionOptions{})), 1e-6);
  const std::string grown = test::read_bytes(file.string());
  EXPECT_GT(grown.size(), wisdom.size());
  forget_fftw_float_wisdom();
  EXPECT_EQ(convolve_float(scene, psf).rgba, first.rgba);
}

TEST_F(FftwWisdom, ADamagedFileIsReplacedAndTheResultIsRight) {
  const std::filesystem::path file = scratch_.path() / "fftwf.wisdom";
  test::write_bytes(file.string(), "not wisdom at all\n");
  use_fftw_wisdom_file(file.string());
  const ImageRGBA scene = test_scene(80, 48);
  const Psf psf = test::lopsided_psf(21);
  EXPECT_LT(relative_error(convolve_float(scene, psf), convolve_image_cpu(scene, psf, ConvolutionOptions{})), 1e-6);
  EXPECT_EQ(test::read_bytes(file.string()).rfind("(fftw-3", 0), 0u);
}

TEST_F(FftwWisdom, WithoutAFilePlansAreEstimatedAndTheReasonIsSaid) {
  use_fftw_wisdom_file("none");
  EXPECT_FALSE(fftw_wisdom_place().kept());
  EXPECT_EQ(fftw_wisdom_place().describe(), "FFTW plans estimated (no wisdom file chosen)");
  const ImageRGBA scene = test_scene(64, 40);
  const Psf psf = test::lopsided_psf(17);
  const ImageRGBA estimated = convolve_float(scene, psf);
  EXPECT_LT(relative_error(estimated, convolve_image_cpu(scene, psf, ConvolutionOptions{})), 1e-6);
  EXPECT_EQ(convolve_float(scene, psf).rgba, estimated.rgba);  // estimate plans: the same in every run

  // A directory that cannot be made: said, with the path, and nothing kept.
  use_fftw_wisdom_file("/proc/glarelab-no-such-dir/fftwf.wisdom");
  EXPECT_FALSE(fftw_wisdom_place().kept());
  EXPECT_NE(fftw_wisdom_place().reason.find("/proc/glarelab-no-such-dir"), std::string::npos) << fftw_wisdom_place().reason;
  EXPECT_LT(relative_error(convolve_float(scene, psf), convolve_image_cpu(scene, psf, ConvolutionOptions{})), 1e-6);
}

// Two sessions, two processes, one wisdom file named by GLARELAB_FFTW_WISDOM: the first measures
// and writes it, the second reads it; the log names it, and the frames are the same bits.
TEST_F(FftwWisdom, SessionsShareTheFileNamedByTheEnvironmentAndGiveTheSameFrames) {
  // In this process: a per-call float FFT first (it makes FFTW's planner), then a kept plan.
  std::vector<float> real(64 * 48, 1.0f);
  (void)fft2d_real_forward(real, 48, 64);
  use_fftw_wisdom_file((scratch_.path() / "in_process.wisdom").string());
  (void)convolve_float(test_scene(72, 40), test::lopsided_psf(9));
  const std::string in_process_wisdom = test::read_bytes((scratch_.path() / "in_process.wisdom").string());

  const std::filesystem::path file = scratch_.path() / "lab" / "fftwf.wisdom";
  ASSERT_EQ(setenv("GLARELAB_FFTW_WISDOM", file.c_str(), 1), 0);
  std::vector<std::filesystem::path> frames, databases;
  std::vector<std::string> wisdom;
  for (const std::string run : {"first", "second"}) {
    const auto dir = scratch_.path() / run;
    std::filesystem::create_directories(dir);
    const auto experiment = test::demo_variant(
        dir, {{"stimulus_frames", "stimulus_frames = 3"}, {"grid_px", "grid_px = 128"}});
    frames.push_back(dir / "frames");
    databases.push_back(dir / "session.db");
    const test::RunOutput output =
        test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db",
                            databases.back().string(), "--save-frames", frames.back().string(), "--stop-after", "3"},
                           dir);
    ASSERT_EQ(output.exit_code, 0) << output.output;
    ASSERT_TRUE(std::filesystem::exists(file)) << output.output;
    wisdom.push_back(test::read_bytes(file.string()));
  }
  unsetenv("GLARELAB_FFTW_WISDOM");
  EXPECT_EQ(wisdom[1], wisdom[0]);  // the second run measured nothing
  // Wisdom carries the planner's configuration as its signature (its first line), and a process
  // reads only wisdom of its own configuration. This test process planned a per-call float FFT
  // (glare/cpu/fft.h) before any kept plan, the sessions did not: the same signature, so each can read
  // what the other wrote.
  const std::string first_line = wisdom[0].substr(0, wisdom[0].find('\n'));
  EXPECT_EQ(in_process_wisdom.substr(0, in_process_wisdom.find('\n')), first_line);
  for (const auto& db : databases) {
    const auto backend = test::session_event_messages(db.string(), "glare_backend");
    ASSERT_EQ(backend.size(), 1u);
    EXPECT_NE(backend[0].find("FFTW plans measured once and kept in " + file.string()), std::string::npos) << backend[0];
  }
  for (int trial = 0; trial < 3; ++trial) {
    char name[32];
    std::snprintf(name, sizeof name, "trial_%04d.exr", trial);
    EXPECT_EQ(read_exr((frames[1] / name).string()).image.rgba, read_exr((frames[0] / name).string()).image.rgba) << name;
  }
}

}  // namespace
}  // namespace glarelab
