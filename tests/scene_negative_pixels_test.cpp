// Photographs as they come (issue: a lab's first study): a scene's negative pixels are refused by
// default with the key that accepts them named; negative_pixels = "clamp" sets them to 0 and
// validate, the session's record and render report the count and the energy fraction removed;
// glarelab's own frames (render, run --save-frames) load as scenes with no option.
#include <gtest/gtest.h>

#include <ImfHeader.h>
#include <ImfInputFile.h>


#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli_process.h"
#include "core/exr_io.h"
#include "scratch_dir.h"
#include "session_events.h"
#include "stimuli/scene_library.h"

namespace glarelab {
namespace {

constexpr double kWr = 0.2126, kWg = 0.7152, kWb = 0.0722;  // Rec.709 Y

// 4 x 2 px: six grey pixels of 2, one pixel with red -1, one with green -0.5 and blue -3.
ImageRGBA negative_scene() {
  ImageRGBA image(4, 2, 2.0f);
  image.pixel(1, 0)[0] = -1.0f;
  image.pixel(3, 1)[1] = -0.5f;
  image.pixel(3, 1)[2] = -3.0f;
  return image;
}

// The energy fraction by hand: the removed channels' weighted magnitudes over all channels'.
double expected_fraction() {
  const double removed = kWr * 1.0 + kWg * 0.5 + kWb * 3.0;
  const double total = 6 * 2.0 * (kWr + kWg + kWb) + (kWr * 1.0 + 2.0 * (kWg + kWb)) + (2.0 * kWr + kWg * 0.5 + kWb * 3.0);
  return removed / total;
}

TEST(SceneNegativePixels, ClampSetsNegativesToZeroAndCountsPixelsAndEnergy) {
  const test::ScratchDir dir;
  write_exr(dir.file("neg.exr"), negative_scene());
  SceneSpec spec;
  spec.name = "neg";
  spec.file = dir.file("neg.exr");
  spec.scale_cd_m2 = 10.0;
  spec.negative_pixels = NegativePixels::clamp;
  const SceneLibrary library({{"neg", spec}}, DisplaySpec{});
  const LoadedScene& scene = library.get("neg");
  EXPECT_EQ(scene.clamped_pixels, 2u);
  EXPECT_NEAR(scene.clamped_energy_fraction, expected_fraction(), 1e-12);
  EXPECT_EQ(scene.image_cd_m2.pixel(1, 0)[0], 0.0f);
  EXPECT_EQ(scene.image_cd_m2.pixel(1, 0)[1], 20.0f);  // the other channels scaled, untouched
  EXPECT_EQ(scene.image_cd_m2.pixel(3, 1)[1], 0.0f);
  EXPECT_EQ(scene.image_cd_m2.pixel(3, 1)[2], 0.0f);
  EXPECT_EQ(scene.image_cd_m2.pixel(3, 1)[0], 20.0f);
  const std::string note = describe_clamping("neg", scene);
  EXPECT_NE(note.find("scene 'neg': 2 negative pixels set to 0 (negative_pixels = \"clamp\")"), std::string::npos) << note;

  spec.negative_pixels = NegativePixels::refuse;
  try {
    const SceneLibrary refused({{"neg", spec}}, DisplaySpec{});
    FAIL() << "negative pixels were accepted";
  } catch (const ImageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("2 negative pixels"), std::string::npos) << message;
    EXPECT_NE(message.find("negative_pixels = \"clamp\""), std::string::npos) << message;
  }
}

TEST(SceneNegativePixels, NanIsRefusedEvenWithClamp) {
  const test::ScratchDir dir;
  ImageRGBA image = negative_scene();
  image.pixel(0, 0)[1] = std::nanf("");
  write_exr(dir.file("nan.exr"), image);
  SceneSpec spec;
  spec.file = dir.file("nan.exr");
  spec.negative_pixels = NegativePixels::clamp;
  EXPECT_THROW(SceneLibrary({{"nan", spec}}, DisplaySpec{}), ImageError);
}

TEST(SceneNegativePixels, RoundOffBelowZeroIsZeroedDeeperNegativesKept) {
  ImageRGBA frame(3, 1, 0.0f);
  frame.pixel(0, 0)[0] = 200.0f;                               // the peak
  frame.pixel(1, 0)[1] = -2e-5f;                               // FFT round-off: 1e-7 of the peak
  frame.pixel(2, 0)[2] = static_cast<float>(-200.0 * 1e-3);    // ten times the bound: a fault
  EXPECT_EQ(zero_round_off_negatives(frame), 1u);
  EXPECT_EQ(frame.pixel(1, 0)[1], 0.0f);
  EXPECT_LT(frame.pixel(2, 0)[2], 0.0f);
}

std::string experiment_with(const std::string& scenes_line, int width_px, int height_px) {
  return "[experiment]\nname = \"photos\"\nseed = 3\n\n[display]\nwidth_px = " + std::to_string(width_px) +
         "\nheight_px = " + std::to_string(height_px) +
         "\npeak_luminance_cd_m2 = 250.0\n\n[scenes]\n" + scenes_line +
         "\n\n[procedure]\ntype = \"forced_choice\"\nstimulus_frames = 2\n\n[presentation]\nquestion_above_stimuli = false\n\n"
         "[glare]\nmode = \"control\"\n\n[[conditions.rows]]\nname = \"pair\"\nscene_a = \"photo\"\nscene_b = \"dim\"\n";
}

TEST(SceneNegativePixels, ValidateRunAndRenderReportTheClamp) {
  const test::ScratchDir dir;
  write_exr(dir.file("neg.exr"), negative_scene());
  const std::string dim = "dim = { file = \"neg.exr\", scale_cd_m2 = 0.5, negative_pixels = \"clamp\" }";
  const std::string refused = dir.write("refused.toml", experiment_with("photo = { file = \"neg.exr\" }\n" + dim, 64, 32));
  const test::RunOutput no = test::run_glarelab({"validate", refused}, dir.path());
  EXPECT_EQ(no.exit_code, 2) << no.output;
  EXPECT_NE(no.output.find("negative_pixels = \"clamp\""), std::string::npos) << no.output;

  const std::string clamped =
      dir.write("clamped.toml", experiment_with("photo = { file = \"neg.exr\", negative_pixels = \"clamp\" }\n" + dim, 64, 32));
  const test::RunOutput ok = test::run_glarelab({"validate", clamped}, dir.path());
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("note: scene 'photo': 2 negative pixels set to 0"), std::string::npos) << ok.output;
  EXPECT_NE(ok.output.find("note: scene 'dim': 2 negative pixels set to 0"), std::string::npos) << ok.output;

  const std::string db = dir.file("run.db");
  const test::RunOutput run = test::run_glarelab(
      {"run", clamped, "--display", "offscreen", "--observer", "simulated", "--db", db}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto events = test::session_event_messages(db, "scene_load");
  ASSERT_EQ(events.size(), 2u);
  EXPECT_NE(events[1].find("scene 'photo': 2 negative pixels set to 0"), std::string::npos) << events[1];

  const test::RunOutput render = test::run_glarelab(
      {"render", clamped, "--condition", "pair", "--out", dir.file("frame.exr")}, dir.path());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  EXPECT_NE(render.output.find("note: scene 'photo': 2 negative pixels set to 0"), std::string::npos) << render.output;
}

// A frame saved by run --save-frames and one written by render, each with the glare's FFT round-off,
// load as scenes of a new experiment with no option. Both are written uncompressed (core/exr_io.h,
// ExrCompression: zlib would cost 20 to 27 times the write for a file half to two thirds the size).
TEST(SceneNegativePixels, GlarelabsOwnFramesLoadAsScenes) {
  const test::ScratchDir dir;
  const auto experiment = test::small_dynamic_demo(dir.path(), "");
  const test::RunOutput run =
      test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db",
                          dir.file("s.db"), "--save-frames", dir.file("frames"), "--stop-after", "1"},
                         dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const test::RunOutput render = test::run_glarelab(
      {"render", experiment.string(), "--condition", "ratio_1.30", "--out", dir.file("rendered.exr")}, dir.path());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  for (const std::string& written : {dir.file("frames/trial_0000.exr"), dir.file("rendered.exr")})
    EXPECT_EQ(Imf::InputFile(written.c_str()).header().compression(), Imf::NO_COMPRESSION) << written;
  const std::string reuse = dir.write(
      "reuse.toml",
      experiment_with("photo = { file = \"frames/trial_0000.exr\" }\ndim = { file = \"rendered.exr\", scale_cd_m2 = 0.5 }",
                      1100, 300));
  const test::RunOutput validate = test::run_glarelab({"validate", reuse}, dir.path());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;
  EXPECT_EQ(validate.output.find("negative"), std::string::npos) << validate.output;
}

// The three sample photographs refused without the key (docs: ../shared/data/openexr-images, or
// $GLARELAB_OPENEXR_IMAGES) validate and run with negative_pixels = "clamp", and say so.
TEST(SceneNegativePixels, SamplePhotographsValidateAndRunWithClamp) {
  const char* override_dir = std::getenv("GLARELAB_OPENEXR_IMAGES");
  const std::filesystem::path images = override_dir != nullptr && *override_dir != '\0'
                                           ? std::filesystem::path(override_dir)
                                           : std::filesystem::path(GLARELAB_SOURCE_DIR) / ".." / "shared" / "data" /
                                                 "openexr-images";
  if (!std::filesystem::exists(images / "ScanLines_CandleGlass.exr"))
    GTEST_SKIP() << "the OpenEXR sample images are not at " << images
                 << " (they are not part of the repository; set GLARELAB_OPENEXR_IMAGES to their folder)";
  for (const std::string name : {"ScanLines_CandleGlass.exr", "ScanLines_Desk.exr", "ScanLines_Carrots.exr"}) {
    SCOPED_TRACE(name);
    const test::ScratchDir dir;
    const std::string file = (images / name).string();
    const std::string refused = dir.write(
        "refused.toml", experiment_with("photo = { file = \"" + file + "\" }\ndim = { file = \"" + file +
                                            "\", scale_cd_m2 = 0.5, negative_pixels = \"clamp\" }",
                                        2048, 1024));
    const test::RunOutput no = test::run_glarelab({"validate", refused}, dir.path());
    EXPECT_EQ(no.exit_code, 2) << no.output;
    EXPECT_NE(no.output.find("negative_pixels = \"clamp\""), std::string::npos) << no.output;
    const std::string clamped = dir.write(
        "clamped.toml", experiment_with("photo = { file = \"" + file + "\", negative_pixels = \"clamp\" }\ndim = { file = \"" +
                                            file + "\", scale_cd_m2 = 0.5, negative_pixels = \"clamp\" }",
                                        2048, 1024));
    const test::RunOutput ok = test::run_glarelab({"validate", clamped}, dir.path());
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    EXPECT_NE(ok.output.find("note: scene 'photo': "), std::string::npos) << ok.output;
    std::printf("%s", ok.output.c_str());
    const std::string db = dir.file("run.db");
    const test::RunOutput run = test::run_glarelab(
        {"run", clamped, "--display", "offscreen", "--observer", "simulated", "--db", db}, dir.path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(test::session_event_messages(db, "scene_load").size(), 2u);
  }
}

}  // namespace
}  // namespace glarelab
