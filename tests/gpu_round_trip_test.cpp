// The GPU engine with no round trip (issue 32, acceptance 2): every read-back of GPU data goes
// through core/gl/read_back.h, which counts it; a frame left on the GPU reaches the display's
// stimulus frame as it was; and a session on `--engine gpu` without --save-frames reads back no
// whole frame after each interval's first frame (its `read_backs` events, one per glared or
// perceived interval), while --save-frames, which reads the shown frame back, shows up in the same
// count (tests/engine_frames_test.cpp's GPU sessions, which save their frames).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/errors.h"
#include "core/gl/read_back.h"
#include "example_copies.h"
#include "runner/display/compute_context.h"
#include "scratch_dir.h"
#include "read_back_events.h"
#include "stimuli/frame_renderer.h"
#include "stimuli/glare_stage.h"
#include "stimuli/perception/gl_frame_buffer.h"

namespace glarelab {
namespace {

namespace fs = std::filesystem;

// A small image whose every float is distinct and known: pixel (x, y) channel c holds
// 1000 y + 10 x + c + 0.25 (alpha too), so a copy that moves, flips or drops a value is seen.
ImageRGBA numbered_image(int width_px, int height_px) {
  ImageRGBA image(width_px, height_px);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x)
      for (int c = 0; c < 4; ++c) image.pixel(x, y)[c] = static_cast<float>(1000 * y + 10 * x + c) + 0.25f;
  return image;
}

class GpuRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override {
    try {
      context_ = gl::create_compute_context();
    } catch (const DisplayError& error) {
      GTEST_SKIP() << "no OpenGL 4.5 context here: " << error.what();
    }
  }
  std::unique_ptr<DisplayBackend> context_;
};

// A frame read back counts one frame read-back of its bytes (4 floats a pixel); an upload and a
// copy on the GPU count nothing.
TEST_F(GpuRoundTrip, TheTallyCountsEachReadBackByKindAndBytes) {
  const ImageRGBA image = numbered_image(7, 5);
  const gl::ReadBackTally before = gl::read_back_tally();
  gl::GlFrameBuffer frame(image);
  gl::GlFrameBuffer copy(7, 5);
  copy.copy_from(frame.buffer());
  EXPECT_EQ(gl::read_back_tally().since(before).calls_of(gl::ReadBackKind::frame), 0u);
  const ImageRGBA back = copy.download();
  const gl::ReadBackTally read = gl::read_back_tally().since(before);
  EXPECT_EQ(read.calls_of(gl::ReadBackKind::frame), 1u);
  EXPECT_EQ(read.bytes_of(gl::ReadBackKind::frame), 7u * 5u * 4u * sizeof(float));
  EXPECT_EQ(read.calls_of(gl::ReadBackKind::kernel), 0u);
  EXPECT_EQ(read.calls_of(gl::ReadBackKind::reduction), 0u);
  EXPECT_EQ(back.rgba, image.rgba);  // the copy on the GPU is the image itself
  EXPECT_EQ(read.describe(), "1 frame (560 B), 0 kernel, 0 reduction");
}

// A frame left in a GL buffer, drawn into a rectangle of the stimulus frame, is there as the same
// floats (rows flipped into GL's order and back by the read-back), as the host's upload puts them.
TEST_F(GpuRoundTrip, AFrameOnTheGpuReachesTheStimulusFrameUnchanged) {
  const ImageRGBA region = numbered_image(6, 4);
  FrameRenderer from_gpu(16, 9), from_host(16, 9);
  from_gpu.compose({}, 3.5);
  from_host.compose({}, 3.5);
  const gl::GlFrameBuffer frame(region);
  const std::uint64_t generation = from_gpu.stimulus_generation();
  from_gpu.replace_stimulus_region_from_buffer(frame.buffer(), 5, 2, 6, 4);
  EXPECT_GT(from_gpu.stimulus_generation(), generation);
  EXPECT_EQ(from_gpu.unencoded_rect().x_px, 0);  // the compose marked the whole frame
  from_host.replace_stimulus_region(region, 5, 2);
  const ImageRGBA got = from_gpu.read_stimulus();
  const ImageRGBA expected = from_host.read_stimulus();
  EXPECT_EQ(got.rgba, expected.rgba);
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 16; ++x) {
      const bool inside = x >= 5 && x < 11 && y >= 2 && y < 6;
      const float want = inside ? static_cast<float>(1000 * (y - 2) + 10 * (x - 5)) + 0.25f : 3.5f;
      ASSERT_EQ(got.pixel(x, y)[0], want) << "pixel (" << x << ", " << y << ")";
    }
  EXPECT_THROW(from_gpu.replace_stimulus_region_from_buffer(frame.buffer(), 12, 2, 6, 4), DisplayError);
}

// A night street: a dim field, a grey wall and a small lamp far above a display's peak.
ImageRGBA night_scene(int width_px, int height_px) {
  ImageRGBA frame(width_px, height_px);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x) {
      float* p = frame.pixel(x, y);
      const float wall = (x > width_px / 2 && y > height_px / 2) ? 12.0f : 0.4f;
      p[0] = wall;
      p[1] = 0.9f * wall;
      p[2] = 0.7f * wall;
      p[3] = 1.0f;
    }
  for (int y = 40; y < 43; ++y)
    for (int x = 50; x < 53; ++x) frame.pixel(x, y)[0] = frame.pixel(x, y)[1] = frame.pixel(x, y)[2] = 5000.0f;
  return frame;
}

// The glare stage's frame left on the GPU is its frame on the host (the same stage, the same GL
// backend, one context): Ritschel's wave-optics eye and the human eye (the hybrid near part on the
// GPU, its far part and halo from the host), within 1e-4 relative above 1 cd/m2 and 1e-4 cd/m2
// below (the host convolves the lit boxes, the GPU the whole frame: float rounding apart), and
// nothing of the frame is read back on the way.
TEST_F(GpuRoundTrip, TheGlareStageOnTheGpuGivesItsHostFrame) {
  DisplaySpec display;
  display.width_px = 160;
  display.height_px = 120;
  const ImageRGBA scene = night_scene(160, 120);
  for (const GlareModel model : {GlareModel::ritschel, GlareModel::human}) {
    SCOPED_TRACE(to_string(model));
    GlareSpec spec;
    spec.grid_px = 256;
    spec.wavelength_samples = 8;
    spec.skip_invisible = false;
    spec.backend = GlareBackendRequest::gl;
    spec.model = model;
    GlareStage stage(spec, display, 3, one_context_factory(*context_));
    GlareFrameReport host_report, gpu_report;
    const ImageRGBA host = stage.apply(scene, GlareMode::static_eye, 0.5, &host_report);
    ASSERT_TRUE(host_report.convolved);
    const gl::ReadBackTally before = gl::read_back_tally();
    const GlareStage::GlaredOnGpu on_gpu =
        stage.apply_on_gpu(scene, GlareMode::static_eye, 0.5, &gpu_report, std::nullopt, std::nullopt, nullptr);
    ASSERT_NE(on_gpu.gpu_buffer, 0u) << "the frame did not stay on the GPU";
    EXPECT_TRUE(on_gpu.image.empty());
    EXPECT_TRUE(gpu_report.convolved);
    EXPECT_EQ(gl::read_back_tally().since(before).calls_of(gl::ReadBackKind::frame), 0u);
    gl::GlFrameBuffer kept(160, 120);
    kept.copy_from(on_gpu.gpu_buffer);
    const ImageRGBA got = kept.download();
    double worst = 0.0;
    for (std::size_t i = 0; i < host.rgba.size(); ++i) {
      const double scale = std::max(1.0, std::abs(static_cast<double>(host.rgba[i])));
      worst = std::max(worst, std::abs(static_cast<double>(got.rgba[i]) - host.rgba[i]) / scale);
    }
    std::cout << to_string(model) << ": glare on the GPU against the host, worst " << worst << "\n";
    EXPECT_LE(worst, 1e-4);
    // The glare is there: the lamp's neighbourhood is brighter than the scene.
    EXPECT_GT(got.pixel(56, 41)[1], scene.pixel(56, 41)[1] * 1.01f);
  }
}

// Every read-back of the product goes through core/gl/read_back.cpp, so that the tally sees it: no
// other source file calls a GL function that brings texture, framebuffer or buffer data to the
// host (comments aside). Reported as "FILE:LINE: CALL".
TEST(ReadBackSites, EveryReadBackGoesThroughTheTally) {
  static const std::regex call(
      R"(\b(glReadn?Pixels|glGetn?TexImage|glGetTextureImage|glGetTextureSubImage|glGetCompressedTexImage|)"
      R"(glGetCompressedTextureImage|glGetBufferSubData|glGetNamedBufferSubData|glMapBuffer|glMapBufferRange|)"
      R"(glMapNamedBuffer|glMapNamedBufferRange)\s*\()");
  const fs::path root = GLARELAB_SOURCE_DIR;
  std::vector<std::string> found;
  int files = 0;
  for (const std::string folder : {"core", "glare", "stimuli", "protocols", "analysis", "runner", "bench"}) {
    if (!fs::is_directory(root / folder)) continue;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root / folder)) {
      const std::string extension = entry.path().extension().string();
      if (!entry.is_regular_file() || (extension != ".cpp" && extension != ".h")) continue;
      const std::string relative = fs::relative(entry.path(), root).string();
      if (relative == "core/gl/read_back.cpp") continue;
      ++files;
      std::ifstream in(entry.path());
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        const std::string code = line.substr(0, line.find("//"));
        std::smatch match;
        if (std::regex_search(code, match, call)) found.push_back(relative + ":" + std::to_string(number) + ": " + match[1].str());
      }
    }
  }
  EXPECT_GT(files, 100);
  std::string listed;
  for (const std::string& site : found) listed += site + "\n";
  EXPECT_TRUE(found.empty()) << "read-backs outside core/gl/read_back.cpp:\n" << listed;
}

struct GpuSession {
  std::string file;
  std::string trials;  // --stop-after
};

class NoRoundTrip : public ::testing::TestWithParam<GpuSession> {};

TEST_P(NoRoundTrip, TheGpuEngineReadsBackNoFrameAfterEachIntervalsFirst) {
  const test::ScratchDir scratch;
  // Two frames a stimulus: the first and one after it, all the read-back count below needs. The
  // same sessions with --save-frames, which reads each shown frame back, show those read-backs in
  // the same count: tests/engine_frames_test.cpp checks that on every example's GPU session.
  const fs::path file = test::examples_with_frames(scratch.path(), 2) / GetParam().file;
  const fs::path db = scratch.path() / "live.db";
  const test::RunOutput run =
      test::run_glarelab({"run", file.string(), "--display", "offscreen", "--observer", "simulated", "--seed", "1", "--db",
                          db.string(), "--stop-after", GetParam().trials, "--engine", "gpu"},
                         scratch.path());
  if (run.exit_code == 3) GTEST_SKIP() << "no OpenGL 4.5 context here: " << run.output;
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<test::IntervalReadBacks> intervals = test::read_back_events(db.string());
  ASSERT_FALSE(intervals.empty()) << "no read_backs event: " << run.output;
  int with_later_frames = 0;
  for (const test::IntervalReadBacks& interval : intervals) {
    std::cout << GetParam().file << ": " << interval.message << "\n";
    ASSERT_GE(interval.frames_computed, 1) << interval.message;
    if (interval.frames_computed > 1) ++with_later_frames;
    EXPECT_EQ(interval.frames_after_first, 0u) << interval.message;
  }
  // The sessions make frames after the first (dynamic glare or adapting perception stages).
  EXPECT_GT(with_later_frames, 0);
}

// ritschel_2afc: Ritschel's dynamic wave-optics glare on the GL backend, the glare alone;
// luidolt_ratings: Luidolt's kernel between every perception stage (its seventh trial), on the GL
// stages.
INSTANTIATE_TEST_SUITE_P(Examples, NoRoundTrip,
                         ::testing::Values(GpuSession{"ritschel_2afc.toml", "2"},
                                           GpuSession{"luidolt_ratings.toml", "8"}),
                         [](const ::testing::TestParamInfo<GpuSession>& param) {
                           return param.param.file.substr(0, param.param.file.find('.'));
                         });

}  // namespace
}  // namespace glarelab
