// A stereo session with depth of field and a refraction (runner/session/eye_glare.cpp, docs/STEREO.md):
// each eye's half of a saved frame is, bit for bit, the frame of a mono session on a display of the
// half's size, with the same Z, gaze (the view's centre) and pupil (Eq. 2 for the view's mean
// luminance). The scene puts a near board at its left edge and a far wall with a bright point at
// its centre, so the full frame's centre column, where the halves meet, lies on the right eye's
// near board while each eye's own view centre lies on the far point: an eye accommodated on the
// full frame's centre, or a half blurred without its scene's Z, shows a blurred point or a sharp
// board where the mono eye does not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "session_events.h"
#include "stimuli/stereo_layout.h"

namespace glarelab {
namespace {

constexpr int kViewWidth = 160, kHeight = 120;  // one eye's view, and the mono display
constexpr float kNearM = 0.4f, kFarM = 1.0f;     // the display is at 0.5 m
constexpr int kBoardWidth = 48;                  // the near board: columns 0 .. 47
constexpr int kPointX = kViewWidth / 2, kPointY = kHeight / 2;  // the view's centre pixel
constexpr float kPointCdM2 = 2000.0f, kWallCdM2 = 20.0f;

// A wall at 1 m (20 cd/m2) with a 2000 cd/m2 point at the view's centre, and a 0.4 m board with a
// 2 px checkerboard over the left edge.
ImageRGBA near_and_far() {
  ImageRGBA image(kViewWidth, kHeight, 1.0f);
  image.depth.assign(static_cast<std::size_t>(kViewWidth) * kHeight, kFarM);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kViewWidth; ++x) {
      float value = x == kPointX && y == kPointY ? kPointCdM2 : kWallCdM2;
      if (x < kBoardWidth) {
        value = ((x / 2 + y / 2) % 2 == 0) ? 60.0f : 10.0f;
        image.depth[static_cast<std::size_t>(y) * kViewWidth + x] = kNearM;
      }
      for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = value;
    }
  return image;
}

// A myope of 0.5 D (age 20: amplitude enough to accommodate on 1 m), static Ritschel glare at gain
// 0 (the glare adds nothing, the frames go through the eye), depth of field on.
std::string experiment_toml(int width_px, bool stereo) {
  return "[experiment]\nname = \"near_far\"\nseed = 7\n\n"
         "[display]\nwidth_px = " + std::to_string(width_px) + "\nheight_px = 120\nrefresh_hz = 60.0\n"
         "viewing_distance_mm = 500.0\npixel_pitch_mm = 0.25\npeak_luminance_cd_m2 = 2500.0\nbackground_cd_m2 = 0.0\n"
         "encoding = \"srgb\"\n" + (stereo ? "stereo = \"side_by_side\"\n" : "") + "\n"
         "[scenes]\nnear_far = { file = \"near_far.exr\" }\n\n"
         "[procedure]\ntype = \"rating\"\ncategories = [\"sharpness\"]\nscale_points = 5\nrepetitions = 1\n"
         "stimulus_duration_s = 0.1\n\n"
         "[observer]\nage_years = 20.0\ndepth_of_field = true\n\n[observer.refraction]\nsphere_dioptres = -0.5\n\n"
         "[[conditions.rows]]\nname = \"near_far\"\nscene = \"near_far\"\nglare_gain = 0.0\n\n"
         "[glare]\nmode = \"static\"\nmodel = \"ritschel\"\ngrid_px = 512\nwavelength_samples = 8\n\n"
         "[presentation]\nquestion_above_stimuli = false\n";
}

struct Session {
  ImageRGBA frame;
  std::filesystem::path db;
};

Session run_session(const std::filesystem::path& dir, int width_px, bool stereo) {
  std::filesystem::create_directories(dir);
  ExrWriteOptions options;
  options.write_depth = true;
  write_exr((dir / "near_far.exr").string(), near_and_far(), options);
  const std::filesystem::path experiment = dir / "near_far.toml";
  test::write_bytes(experiment.string(), experiment_toml(width_px, stereo));
  const std::filesystem::path db = dir / "session.db", frames = dir / "frames";
  const test::RunOutput output =
      test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db",
                          db.string(), "--save-frames", frames.string(), "--stop-after", "1"},
                         dir);
  EXPECT_EQ(output.exit_code, 0) << output.output;
  if (output.exit_code != 0) return {};
  return {read_exr((frames / "trial_0000.exr").string()).image, db};
}

ImageRGBA half(const ImageRGBA& frame, int which) {
  return crop_view(frame, {which * frame.width_px / 2, 0, frame.width_px / 2, frame.height_px});
}

// The checkerboard's spread (standard deviation of green) inside the board, away from its edges.
double board_spread(const ImageRGBA& image) {
  double sum = 0.0, squares = 0.0;
  int n = 0;
  for (int y = 20; y < kHeight - 20; ++y)
    for (int x = 8; x < kBoardWidth - 8; ++x) {
      const double value = image.pixel(x, y)[1];
      sum += value;
      squares += value * value;
      ++n;
    }
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, squares / n - mean * mean));
}

TEST(StereoDepthOfFieldTest, EachHalfIsTheMonoFrameOfItsEyeWithItsOwnDepthAndAccommodation) {
  const test::ScratchDir scratch;
  const Session mono = run_session(scratch.path() / "mono", kViewWidth, false);
  const Session stereo = run_session(scratch.path() / "stereo", 2 * kViewWidth, true);
  ASSERT_EQ(mono.frame.width_px, kViewWidth);
  ASSERT_EQ(stereo.frame.width_px, 2 * kViewWidth);
  const ImageRGBA left = half(stereo.frame, 0), right = half(stereo.frame, 1);
  const double scene_spread = board_spread(near_and_far());
  std::printf("point peak (cd/m2): mono %.1f, left half %.1f, right half %.1f (scene %.0f)\n",
              mono.frame.pixel(kPointX, kPointY)[1], left.pixel(kPointX, kPointY)[1], right.pixel(kPointX, kPointY)[1],
              kPointCdM2);
  std::printf("near board spread (cd/m2): mono %.2f, left half %.2f, right half %.2f (scene %.2f)\n",
              board_spread(mono.frame), board_spread(left), board_spread(right), scene_spread);

  // The mono eye against the closed form: accommodated on its view centre's depth (1 m), the point
  // there is the scene itself, and the board 1 / 0.4 - 1 / 1 = 1.5 D nearer is blurred (its 2 px
  // checks spread over a disc of several pixels for any pupil of Eq. 2: 2 mm and up).
  EXPECT_NEAR(mono.frame.pixel(kPointX, kPointY)[1], kPointCdM2, 1.0);
  EXPECT_LT(board_spread(mono.frame), 0.5 * scene_spread);

  // Each half is that frame, bit for bit.
  EXPECT_EQ(left.rgba, mono.frame.rgba) << "the left eye's half";
  EXPECT_EQ(right.rgba, mono.frame.rgba) << "the right eye's half";

  // Each eye says where it accommodated: on its own view's centre, at 1 m.
  const std::vector<std::string> eyes = test::session_event_messages(stereo.db.string(), "stereo_eyes");
  ASSERT_EQ(eyes.size(), 1u);
  for (const std::string eye : {"left eye depth of field: accommodated", "right eye depth of field: accommodated"}) {
    const std::size_t at = eyes[0].find(eye);
    ASSERT_NE(at, std::string::npos) << eye << " in: " << eyes[0];
    EXPECT_EQ(eyes[0].find(" D on the centre at 1 m ", at), eyes[0].find(" D on the centre at ", at)) << eyes[0];
  }
}

}  // namespace
}  // namespace glarelab
