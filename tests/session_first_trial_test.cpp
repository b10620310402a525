// The session's first trial is seen like every later one (issue 33): its gaze window is centred on
// the tracker's latest gaze, not the display centre, and its dynamic eye meets the first stimulus
// frame adapted to the display's background, what the participant looked at before it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_process.h"
#include "glare/eye/eye_model.h"
#include "protocols/experiment.h"
#include "runner/session/session_eyes.h"
#include "scratch_dir.h"
#include "session_events.h"

namespace glarelab {
namespace {

// A replayed binocular gaze: (0.25, 0.30) at t = 0, then (0.70, 0.60) every 1/120 s up to 1 s.
std::filesystem::path write_gaze_replay(const std::filesystem::path& dir) {
  const auto csv = dir / "gaze.csv";
  std::ostringstream text;
  text << std::setprecision(17);  // the times read back as the flips' own (1/60 s == 2/120 s)
  text << "eye,device_time_s,session_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid\n";
  for (int k = 0; k <= 120; ++k)
    for (int eye = 0; eye < 2; ++eye) {
      const double t_s = k / 120.0;
      text << eye << "," << 100.0 + t_s << "," << t_s << ",4.0," << (k == 0 ? "0.25,0.30" : "0.70,0.60") << ",0.9,1\n";
    }
  std::ofstream(csv) << text.str();
  return csv;
}

// A dynamic trial's glare_window event for a 64 px gaze window on the 512 x 256 display at the
// tracker's gaze (x, y) sampled at sample_s, the window placed as the glare stage places it
// (glare/cpu/gaze_window_convolution.h: centred, clamped inside the display).
std::string window_event(int trial, double x, double y, double sample_s) {
  const long x0 = std::clamp(std::lround(x * 512 - 32), 0L, 512L - 64L);
  const long y0 = std::clamp(std::lround(y * 256 - 32), 0L, 256L - 64L);
  return "trial " + std::to_string(trial) + " (dynamic): gaze window 64x64 px at (" + std::to_string(x0) + ", " +
         std::to_string(y0) + "), centred on gaze (" + std::to_string(x) + ", " + std::to_string(y) +
         ") from the tracker at " + std::to_string(sample_s) + " s";
}

// The demo with a 64 px gaze window on the replayed gaze, its glare presented as `presentation`
// says ([glare] presentation; "auto" would settle it from this machine's measured cost, and the
// gaze a trial logs with it).
std::vector<std::string> gaze_windows(const test::ScratchDir& dir, const std::string& presentation) {
  const auto experiment = test::small_dynamic_demo(
      dir.path(), "backend = \"cpu\"\ngaze_window_px = 64\nmodel = \"ritschel\"\npresentation = \"" + presentation + "\"");
  const std::string db = (dir.path() / (presentation + ".db")).string();
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                       "--db", db, "--seed", "5", "--tracker",
                                       "replay:" + write_gaze_replay(dir.path()).string(), "--stop-after", "2"},
                                      dir.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  return test::session_event_messages(db, "glare_window");
}

// Prepared: the demo's trials have no inter-trial interval, so trial 0 is prepared before the
// session's first flip: the tracker is read then (t = 0 on the virtual clock), and its window is
// centred on the sample at 0 s. Trial 1, prepared after trial 0's flips at 0 and 1/60 s, takes the
// sample at 1/60 s.
TEST(SessionFirstTrial, GazeWindowIsCentredOnTheTrackersGazeFromTheFirstTrial) {
  test::ScratchDir dir;
  const std::vector<std::string> windows = gaze_windows(dir, "prepared");
  ASSERT_EQ(windows.size(), 2u);
  EXPECT_NE(windows[0].find(window_event(0, 0.25, 0.30, 0.0)), std::string::npos) << windows[0];
  EXPECT_EQ(windows[0].find("display centre"), std::string::npos) << windows[0];
  EXPECT_NE(windows[1].find(window_event(1, 0.70, 0.60, 2 / 120.0)), std::string::npos) << windows[1];
}

// Live: each frame takes the latest gaze before its own flip, and a trial's event names its last
// frame's. Trial 0's frames flip at 0 and 1/60 s, so its last frame is computed after the flip at
// 0 s; trial 1's at 2/60 and 3/60 s, so its last frame takes the sample at 2/60 s.
TEST(SessionFirstTrial, LiveGazeWindowTakesEachFramesLatestGaze) {
  test::ScratchDir dir;
  const std::vector<std::string> windows = gaze_windows(dir, "live");
  ASSERT_EQ(windows.size(), 2u);
  EXPECT_NE(windows[0].find(window_event(0, 0.25, 0.30, 0.0)), std::string::npos) << windows[0];
  EXPECT_NE(windows[1].find(window_event(1, 0.70, 0.60, 4 / 120.0)), std::string::npos) << windows[1];
}

// Luidolt 2020 Eq. 5.2-5.4 and Moon and Spencer's Eq. 2 (Ritschel 2009), written out here: the
// field luminance of an eye adapted to B that sees a constant Y from t1 on, and its mean pupil.
double field_after_cd_m2(double b_cd_m2, double y_cd_m2, double elapsed_s, const EyeParameters& eye) {
  const double sigma = eye.field_luminance_rod_half_sensitivity_cd_m2 /
                       (eye.field_luminance_rod_half_sensitivity_cd_m2 + y_cd_m2);  // Eq. 5.4
  const double tau_s = sigma * eye.field_luminance_rod_time_constant_s +
                       (1.0 - sigma) * eye.field_luminance_cone_time_constant_s;  // Eq. 5.3
  return y_cd_m2 + (b_cd_m2 - y_cd_m2) * std::exp(-elapsed_s / tau_s);          // Eq. 5.2
}
double moon_spencer_mm(double field_cd_m2) { return 4.9 - 3.0 * std::tanh(0.4 * (std::log10(field_cd_m2) + 1.0)); }

// A session's dynamic eye (the session's own SessionEye, as `run` and `render` make it) sees frames
// of mean Y = 40 cd/m2 from t1 = 0.5 s on a display whose background is B = 0.2 cd/m2: at the first
// frame its field luminance is B (not Y) and its mean pupil Eq. 2's for B; 0.3 s later both follow
// the closed form from B.
TEST(SessionFirstTrial, DynamicEyeStartsAdaptedToTheBackgroundWithoutPerceptionStages) {
  test::ScratchDir dir;
  Experiment experiment = load_experiment(test::small_dynamic_demo(dir.path(), "backend = \"cpu\""));
  experiment.display.background_cd_m2 = 0.2;
  const double b_cd_m2 = 0.2, y_cd_m2 = 40.0, t1_s = 0.5, frame_s = 1.0 / 60.0;
  const EyeParameters& parameters = experiment.glare.eye;

  SessionEye first(experiment, 512, 256, {});
  EyeState at_onset;
  // (The state is the eye's whether or not its lids let a PSF through at that moment.)
  first.engine.glare().display_psf(GlareMode::dynamic, t1_s, y_cd_m2, &at_onset);
  EXPECT_NEAR(at_onset.field_luminance_cd_m2, b_cd_m2, 1e-12);
  EXPECT_NEAR(at_onset.mean_pupil_diameter_mm, moon_spencer_mm(b_cd_m2), 1e-12);
  // The eye adapted to the frame itself (the finding) would have had Eq. 2's pupil for Y: 2.57 mm
  // against 4.54 mm.
  EXPECT_GT(at_onset.mean_pupil_diameter_mm - moon_spencer_mm(y_cd_m2), 1.9);

  // 18 frames later (0.3 s), the eye having seen each: the closed form, whatever the frame rate.
  SessionEye later(experiment, 512, 256, {});
  const int frames = 18;
  for (int k = 0; k < frames; ++k) later.engine.glare().record_dynamic_frame(t1_s + k * frame_s, y_cd_m2);
  EyeState after;
  const double t_s = t1_s + frames * frame_s;
  later.engine.glare().display_psf(GlareMode::dynamic, t_s, y_cd_m2, &after);
  const double expected_cd_m2 = field_after_cd_m2(b_cd_m2, y_cd_m2, t_s - t1_s, parameters);
  EXPECT_NEAR(after.field_luminance_cd_m2, expected_cd_m2, 1e-9 * expected_cd_m2);
  EXPECT_NEAR(after.mean_pupil_diameter_mm, moon_spencer_mm(expected_cd_m2), 1e-9);
  // Still on its way: neither B nor Y.
  EXPECT_GT(after.field_luminance_cd_m2, 1.0);
  EXPECT_LT(after.field_luminance_cd_m2, 0.99 * y_cd_m2);
}

}  // namespace
}  // namespace glarelab
