// The perception stages in a session, run as a user runs it (glarelab run --save-frames): a
// condition's saved frame equals run_perception_stages applied to the composed frame, a condition
// with perception = "none" is the composed frame bit for bit, and the session's eye adapts over
// its frames in time (Luidolt 2020, Eqs. 5.2-5.4) with the background between them.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "protocols/experiment.h"
#include "session_events.h"
#include "stimuli/glare_stage.h"
#include "stimuli/perception/perception_stages.h"

namespace glarelab {
namespace {

// Every trial shows lamp_100 beside lamp_130 (sides fixed), so all composed frames are the same.
// `perception_table`: the [perception] table's lines; `rows`: name,perception pairs, each shown
// `repetitions` times, under the [glare] mode `glare_mode`.
std::filesystem::path perception_demo(const std::filesystem::path& dir, const std::string& perception_table,
                                      const std::vector<std::pair<std::string, std::string>>& rows,
                                      int repetitions = 1, const std::string& glare_mode = "control") {
  std::filesystem::create_directories(dir);
  std::string csv = "name,scene_a,scene_b,perception\n";
  for (const auto& [name, perception] : rows) csv += name + ",lamp_100,lamp_130," + perception + "\n";
  test::write_bytes((dir / "conditions.csv").string(), csv);
  return test::demo_variant(dir, {{"file", "file = \"" + (dir / "conditions.csv").string() + "\""},
                                  {"width_px", "width_px = 512"},
                                  {"height_px", "height_px = 256"},
                                  {"stimulus_frames", "stimulus_frames = 2"},
                                  {"repetitions", "repetitions = " + std::to_string(repetitions)},
                                  {"counterbalance_sides", "counterbalance_sides = false"},
                                  {"question", "question = \"\""},
                                  {"mode", "mode = \"" + glare_mode + "\""},
                                  {"wavelength_samples", "wavelength_samples = 16\n" + perception_table}});
}

struct PerceptionRun {
  test::RunOutput output;
  std::filesystem::path frames, db;
  Experiment experiment;
};

PerceptionRun run_session(const std::filesystem::path& dir, const std::filesystem::path& experiment, int trials,
                          const std::vector<std::string>& extra = {}) {
  PerceptionRun run{{}, dir / "frames", dir / "session.db", load_experiment(experiment.string())};
  std::vector<std::string> arguments = {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                        "--db", run.db.string(), "--save-frames", run.frames.string(), "--stop-after",
                                        std::to_string(trials)};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  run.output = test::run_glarelab(arguments, dir);
  return run;
}

ImageRGBA saved_frame(const PerceptionRun& run, int trial) {
  char name[32];
  std::snprintf(name, sizeof name, "trial_%04d.exr", trial);
  return read_exr((run.frames / name).string()).image;
}

// Each trial's condition name and the flip time of its stimulus frame 0, by trial index.
struct TrialRow {
  std::string condition;
  double first_flip_s = 0.0;
};
std::vector<TrialRow> trial_rows(const std::filesystem::path& db) {
  std::vector<TrialRow> rows;
  sqlite3* handle = nullptr;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return rows;
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(handle,
                     "SELECT t.condition, f.flip_s FROM trials t JOIN frames f ON f.trial_id = t.id AND f.frame_index = 0 "
                     "ORDER BY t.trial_index",
                     -1, &statement, nullptr);
  while (sqlite3_step(statement) == SQLITE_ROW) {
    const std::string json = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
    const std::size_t at = json.find("\"name\":\"") + 8;
    rows.push_back({json.substr(at, json.find('"', at) - at), sqlite3_column_double(statement, 1)});
  }
  sqlite3_finalize(statement);
  sqlite3_close(handle);
  return rows;
}

const ConditionRow& row_named(const Experiment& experiment, const std::string& name) {
  for (const ConditionRow& row : experiment.conditions)
    if (row.name() == name) return row;
  throw std::runtime_error("no condition " + name);
}

// Colour values of `shown` differing from `expected` by more than float rounding (1e-5 relative):
// the stages run in double on the float frame, and the frame shown is float again.
std::size_t differing_values(const ImageRGBA& shown, const ImageRGBA& expected, double* largest = nullptr) {
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < shown.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const double a = shown.rgba[i], b = expected.rgba[i];
    const double error = std::abs(a - b) / std::max(std::abs(b), 1e-3);
    if (largest != nullptr) *largest = std::max(*largest, error);
    if (error > 1e-5) ++mismatches;
  }
  return mismatches;
}

void expect_frames_equal(const ImageRGBA& shown, const ImageRGBA& expected, const std::string& what) {
  ASSERT_EQ(shown.width_px, expected.width_px) << what;
  ASSERT_EQ(shown.height_px, expected.height_px) << what;
  double largest = 0.0;
  EXPECT_EQ(differing_values(shown, expected, &largest), 0u) << what << ": largest relative difference " << largest;
}

double mean_difference(const ImageRGBA& a, const ImageRGBA& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) sum += std::abs(static_cast<double>(a.rgba[i]) - b.rgba[i]);
  return sum / static_cast<double>(a.rgba.size());
}

constexpr const char* kTable =
    "\n[perception]\ntone_curve = \"aces_hill\"\nmax_sigma_px = 2\nscotopic_form = \"luidolt_tint\"\n";

TEST(PerceptionSession, SavedFramesAreTheStagesOnTheComposedFrameAndNoneIsUnchanged) {
  const test::ScratchDir scratch;
  // Today's session: no [perception] table, no column.
  const auto plain_dir = scratch.path() / "plain";
  const PerceptionRun plain = run_session(plain_dir, perception_demo(plain_dir, "", {{"only", ""}}), 1);
  ASSERT_EQ(plain.output.exit_code, 0) << plain.output.output;
  const ImageRGBA composed = saved_frame(plain, 0);

  const auto dir = scratch.path() / "stages";
  const PerceptionRun run = run_session(
      dir, perception_demo(dir, kTable, {{"none", "none"}, {"three", "acuity+tone_mapping+scotopic"}, {"scotopic", "scotopic"}}),
      3);
  ASSERT_EQ(run.output.exit_code, 0) << run.output.output;
  const std::vector<TrialRow> rows = trial_rows(run.db);
  ASSERT_EQ(rows.size(), 3u);
  const double period_s = 1.0 / run.experiment.display.refresh_hz;
  for (std::size_t t = 0; t < rows.size(); ++t) {
    const ImageRGBA shown = saved_frame(run, static_cast<int>(t));
    if (rows[t].condition == "none") {
      EXPECT_EQ(shown.rgba, composed.rgba) << "perception = \"none\" changed the frame";
      continue;
    }
    const PerceptionSettings settings =
        perception_for(run.experiment.perception, row_named(run.experiment, rows[t].condition));
    ASSERT_FALSE(settings.adaptation);
    TemporalAdaptation eye(1.0, settings.adaptation_time_constants);
    const PerceptionResult expected =
        run_perception_stages(composed, {0.5, 0.5, period_s}, eye, settings, run.experiment.display);
    expect_frames_equal(shown, expected.image, rows[t].condition);
    EXPECT_GT(mean_difference(shown, composed), 0.0) << rows[t].condition << " left the frame as it was";
  }
  const auto events = test::session_event_messages(run.db.string(), "perception_stages");
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].find("ms per frame"), std::string::npos) << events[0];
  EXPECT_NE(events[0].find("tone mapping: aces_hill"), std::string::npos) << events[0];
  // A session without the table logs nothing about perception.
  EXPECT_TRUE(test::session_event_messages(plain.db.string(), "perception_stages").empty());
}

// With adaptation the session's eye starts adapted to the display's background, what the
// participant saw before the first stimulus frame (issue 33: it was adapted to that frame), adapts frame by
// frame (Eq. 5.2 with the frame time), and sees the display's background (0 cd/m2 here) between
// trials (a fixation of 30 frames): the second trial is tone mapped for an eye that has adapted
// down in the meantime.
TEST(PerceptionSession, AdaptationFollowsTheSessionsFramesInTime) {
  const test::ScratchDir scratch;
  const auto plain_dir = scratch.path() / "plain";
  const PerceptionRun plain = run_session(plain_dir, perception_demo(plain_dir, "", {{"only", ""}}), 1);
  ASSERT_EQ(plain.output.exit_code, 0) << plain.output.output;
  const ImageRGBA composed = saved_frame(plain, 0);

  const auto dir = scratch.path() / "adapting";
  const PerceptionRun run =
      run_session(dir, perception_demo(dir, std::string(kTable) + "adaptation = true\ntone_mapping = true\n"
                                                    "\n[presentation]\nfixation_frames = 30\n",
                                      {{"all", ""}}, 2),
                  2);
  ASSERT_EQ(run.output.exit_code, 0) << run.output.output;
  const std::vector<TrialRow> rows = trial_rows(run.db);
  ASSERT_EQ(rows.size(), 2u);
  const PerceptionSettings& settings = run.experiment.perception;
  const double period_s = 1.0 / run.experiment.display.refresh_hz;
  const double frame_cd_m2 = frame_adaptation_luminance_cd_m2(composed, 0.5, 0.5, settings.adaptation_weighting);
  TemporalAdaptation eye(run.experiment.display.background_cd_m2, settings.adaptation_time_constants);
  const PerceptionResult first = run_perception_stages(composed, {0.5, 0.5, period_s}, eye, settings, run.experiment.display);
  expect_frames_equal(saved_frame(run, 0), first.image, "trial 0");
  eye.advance(frame_cd_m2, period_s);  // trial 0's second frame
  const double gap_s = rows[1].first_flip_s - (rows[0].first_flip_s + 2 * period_s);
  ASSERT_GT(gap_s, 0.0);
  eye.advance(run.experiment.display.background_cd_m2, gap_s);
  const double adapted_before_cd_m2 = eye.adapted_luminance_cd_m2();
  EXPECT_LT(adapted_before_cd_m2, 0.5 * frame_cd_m2) << "the eye should have adapted down over " << gap_s << " s";
  const PerceptionResult second = run_perception_stages(composed, {0.5, 0.5, period_s}, eye, settings, run.experiment.display);
  expect_frames_equal(saved_frame(run, 1), second.image, "trial 1");
  EXPECT_GT(mean_difference(saved_frame(run, 1), saved_frame(run, 0)), 0.0);
  const auto events = test::session_event_messages(run.db.string(), "perception_stages");
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].find("adaptation+tone_mapping"), std::string::npos) << events[0];
}

// With adaptation on, the glare of a static eye is computed for the eye's adapted luminance (after
// the first frame, from the background: Eq. 5.2 towards its gaze-weighted adaptation luminance,
// 5.1), not the frame's mean: the saved frame
// equals the glare stage's frame for that field luminance and differs from the mean's.
TEST(PerceptionSession, AdaptationSetsTheGlaresFieldLuminance) {
  const test::ScratchDir scratch;
  const auto plain_dir = scratch.path() / "plain";
  const PerceptionRun plain = run_session(plain_dir, perception_demo(plain_dir, "", {{"only", ""}}), 1);
  ASSERT_EQ(plain.output.exit_code, 0) << plain.output.output;
  const ImageRGBA composed = saved_frame(plain, 0);

  const auto dir = scratch.path() / "glare";
  const PerceptionRun run =
      run_session(dir, perception_demo(dir, "\n[perception]\nadaptation = true\n", {{"only", ""}}, 1, "static"), 1);
  ASSERT_EQ(run.output.exit_code, 0) << run.output.output;
  const ImageRGBA shown = saved_frame(run, 0);
  TemporalAdaptation eye(run.experiment.display.background_cd_m2, run.experiment.perception.adaptation_time_constants);
  const double field_cd_m2 =
      eye.advance(frame_adaptation_luminance_cd_m2(composed, 0.5, 0.5, run.experiment.perception.adaptation_weighting),
                  1.0 / run.experiment.display.refresh_hz);
  const double mean_cd_m2 = mean_luminance(composed);
  ASSERT_GT(std::abs(field_cd_m2 - mean_cd_m2), 0.05 * mean_cd_m2) << "the test needs a gaze-weighted luminance far from the mean";
  GlareStage glare(run.experiment.glare, run.experiment.display, run.experiment.seed);
  const ImageRGBA adapted = glare.apply(composed, GlareMode::static_eye, 0.0, nullptr, std::nullopt, field_cd_m2);
  const ImageRGBA by_mean = glare.apply(composed, GlareMode::static_eye, 0.0, nullptr, std::nullopt, mean_cd_m2);
  expect_frames_equal(shown, adapted, "static glare on the adapted eye");
  // The two field luminances give frames apart by more than the tolerance above.
  EXPECT_GT(differing_values(adapted, by_mean), 100u);
}

// The adaptation luminance is the frame weighted around the gaze (Eq. 5.1): with a tracker, the
// tracker's gaze, not the display centre. A replayed track holds the gaze on the left lamp, then
// (a second session) on the right one. An interval's frames are prepared before its onset with the
// gaze known then: the session's first interval is prepared at time 0, before any flip, when the
// tracker is read (issue 33: it used to adapt at the display centre there), so both trials equal
// the stages run for the eye adapted at the tracker's gaze point, and the two sessions' adapted
// luminances differ as the two lamps do.
TEST(PerceptionSession, AdaptationWeightsTheFrameAroundTheTrackersGaze) {
  const test::ScratchDir scratch;
  const auto plain_dir = scratch.path() / "plain";
  const PerceptionRun plain = run_session(plain_dir, perception_demo(plain_dir, "", {{"only", ""}}), 1);
  ASSERT_EQ(plain.output.exit_code, 0) << plain.output.output;
  const ImageRGBA composed = saved_frame(plain, 0);

  std::vector<double> adapted_cd_m2;
  double centre_cd_m2 = 0.0;
  for (const double gaze_x : {0.25, 0.75}) {
    const auto dir = scratch.path() / ("gaze_" + std::to_string(gaze_x));
    std::filesystem::create_directories(dir);
    std::string track = "eye,device_time_s,session_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid\n";
    for (int k = 0; k < 120 * 20; ++k) {
      const std::string t = std::to_string(k / 120.0);
      track += "0," + t + "," + t + ",4," + std::to_string(gaze_x) + ",0.5,0.95,1\n";
    }
    test::write_bytes((dir / "track.csv").string(), track);
    const PerceptionRun run =
        run_session(dir,
                    perception_demo(dir,
                                    std::string(kTable) + "adaptation = true\ntone_mapping = true\n"
                                                          "\n[presentation]\nfixation_frames = 30\n",
                                    {{"all", ""}}, 2),
                    2, {"--tracker", "replay:" + (dir / "track.csv").string()});
    ASSERT_EQ(run.output.exit_code, 0) << run.output.output;
    const std::vector<TrialRow> rows = trial_rows(run.db);
    ASSERT_EQ(rows.size(), 2u);
    const PerceptionSettings& settings = run.experiment.perception;
    const double period_s = 1.0 / run.experiment.display.refresh_hz;
    centre_cd_m2 = frame_adaptation_luminance_cd_m2(composed, 0.5, 0.5, settings.adaptation_weighting);
    const double at_gaze_cd_m2 = frame_adaptation_luminance_cd_m2(composed, gaze_x, 0.5, settings.adaptation_weighting);
    // Trial 0: the tracker's sample at t = 0, read when the trial was prepared; the eye comes from
    // the background.
    TemporalAdaptation eye(run.experiment.display.background_cd_m2, settings.adaptation_time_constants);
    const PerceptionResult first =
        run_perception_stages(composed, {gaze_x, 0.5, period_s}, eye, settings, run.experiment.display);
    expect_frames_equal(saved_frame(run, 0), first.image, "trial 0, gaze x " + std::to_string(gaze_x));
    eye.advance(at_gaze_cd_m2, period_s);  // trial 0's second frame
    const double gap_s = rows[1].first_flip_s - (rows[0].first_flip_s + 2 * period_s);
    ASSERT_GT(gap_s, 0.0);
    eye.advance(run.experiment.display.background_cd_m2, gap_s);
    // Trial 1: the tracker's gaze.
    const PerceptionResult second =
        run_perception_stages(composed, {gaze_x, 0.5, period_s}, eye, settings, run.experiment.display);
    expect_frames_equal(saved_frame(run, 1), second.image, "trial 1, gaze x " + std::to_string(gaze_x));
    adapted_cd_m2.push_back(at_gaze_cd_m2);
  }
  // lamp_100 on the left, lamp_130 on the right (sides fixed): the eye looking at the brighter lamp
  // adapts higher, and neither equals the display centre's weighting.
  EXPECT_GT(adapted_cd_m2[1], 1.1 * adapted_cd_m2[0]);
  EXPECT_GT(std::abs(adapted_cd_m2[0] - centre_cd_m2), 0.05 * centre_cd_m2);
}

}  // namespace
}  // namespace glarelab
