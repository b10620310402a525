// Stereo sessions run as a user runs them ([display] stereo = "side_by_side"): each half of a
// saved frame is, bit for bit, the frame a mono session on a display of the half's size shows
// (the same trials, the same glare and adaptation); a binocular track with a different pupil per
// eye gives each half its own pupil (the right eye's pupil changes the right half alone); `render` shows both eyes; a layout that does not fit an
// eye's half is refused at the key with exit 2 before anything is written.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "session_events.h"
#include "stimuli/stereo_layout.h"

namespace glarelab {
namespace {

// The demo (two 256 x 256 lamps side by side) on a display `width_px` x 256, every row under
// [glare] `glare_lines`, with `more` appended after the [glare] table; `stereo` adds the key.
std::filesystem::path stereo_demo(const std::filesystem::path& dir, int width_px, bool stereo,
                                  const std::string& glare_lines, const std::string& more = "",
                                  const std::string& stereo_value = "side_by_side") {
  std::filesystem::create_directories(dir);
  test::write_demo_conditions_without_glare(dir / "conditions.csv");
  return test::demo_variant(
      dir, {{"file", "file = \"" + (dir / "conditions.csv").string() + "\""},
            {"width_px", "width_px = " + std::to_string(width_px)},
            {"height_px", "height_px = 256"},
            {"encoding", std::string("encoding = \"srgb\"") + (stereo ? "\nstereo = \"" + stereo_value + "\"" : "")},
            {"stimulus_frames", "stimulus_frames = 2"},
            {"counterbalance_sides", "counterbalance_sides = false"},
            {"question", "question = \"\""},
            {"mode", glare_lines},
            {"wavelength_samples", "wavelength_samples = 8\n" + more}});
}

struct SessionRun {
  test::RunOutput output;
  std::filesystem::path frames, db;
};

SessionRun run_session(const std::filesystem::path& dir, const std::filesystem::path& experiment, int trials,
        const std::vector<std::string>& extra = {}) {
  SessionRun result{{}, dir / "frames", dir / "session.db"};
  std::vector<std::string> arguments = {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                        "--db", result.db.string(), "--save-frames", result.frames.string(),
                                        "--stop-after", std::to_string(trials)};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  result.output = test::run_glarelab(arguments, dir);
  return result;
}

ImageRGBA saved_frame(const SessionRun& run, int trial) {
  char name[32];
  std::snprintf(name, sizeof name, "trial_%04d.exr", trial);
  return read_exr((run.frames / name).string()).image;
}

ImageRGBA half(const ImageRGBA& frame, int which) {
  return crop_view(frame, {which * frame.width_px / 2, 0, frame.width_px / 2, frame.height_px});
}

// Analytic glare (Spencer et al. 1995: no random eye) and adaptation: both eyes see the same
// inputs, so both halves must be the mono frame of a display the size of one half.
TEST(StereoSessionTest, EachHalfIsTheMonoFrameOfItsViewBitForBit) {
  const test::ScratchDir scratch;
  const std::string glare = "mode = \"static\"\nmodel = \"spencer\"";
  const std::string perception = "\n[perception]\nadaptation = true\ntone_curve = \"aces_hill\"\n";
  const SessionRun mono = run_session(scratch.path() / "mono", stereo_demo(scratch.path() / "mono", 512, false, glare, perception), 2);
  ASSERT_EQ(mono.output.exit_code, 0) << mono.output.output;
  const SessionRun stereo =
      run_session(scratch.path() / "stereo", stereo_demo(scratch.path() / "stereo", 1024, true, glare, perception), 2);
  ASSERT_EQ(stereo.output.exit_code, 0) << stereo.output.output;
  for (int trial = 0; trial < 2; ++trial) {
    const ImageRGBA reference = saved_frame(mono, trial);
    const ImageRGBA both = saved_frame(stereo, trial);
    ASSERT_EQ(both.width_px, 1024);
    EXPECT_EQ(half(both, 0).rgba, reference.rgba) << "left half, trial " << trial;
    EXPECT_EQ(half(both, 1).rgba, reference.rgba) << "right half, trial " << trial;
  }
  const std::vector<std::string> setup = test::session_event_messages(stereo.db.string(), "stereo");
  ASSERT_EQ(setup.size(), 1u);
  EXPECT_NE(setup[0].find("left eye (tracker eye 1) in pixels x 0..511"), std::string::npos) << setup[0];
  EXPECT_NE(setup[0].find("right eye (tracker eye 0) in pixels x 512..1023"), std::string::npos) << setup[0];
  EXPECT_TRUE(test::session_event_messages(mono.db.string(), "stereo").empty());
}

// A binocular track: the left eye (id 1) at 3 mm, the right eye (id 0) at `right_mm`.
std::string binocular_track(const test::ScratchDir& scratch, const std::string& name, double right_mm) {
  std::ostringstream csv;
  csv << "eye,device_time_s,session_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid\n";
  for (int k = 0; k < 120 * 20; ++k) {
    const double t = k / 120.0;
    csv << "0," << t << "," << t << "," << right_mm << ",0.5,0.5,0.95,1\n1," << t << "," << t << ",3,0.5,0.5,0.95,1\n";
  }
  return scratch.write(name, csv.str());
}

// The dynamic eye of each half takes its own eye's pupil: changing the right eye's pupil changes
// the right half alone, bit for bit.
TEST(StereoSessionTest, EachEyeTakesItsOwnPupilFromABinocularTracker) {
  const test::ScratchDir scratch;
  // Two trials; trial 1's frames and stereo_eyes event are compared (trial 0 reads the tracker at
  // t = 0, before the session's first flip).
  const auto run_with = [&](const std::string& name, double right_mm) {
    const std::filesystem::path dir = scratch.path() / name;
    const std::string track = binocular_track(scratch, name + ".csv", right_mm);
    return run_session(dir, stereo_demo(dir, 1024, true, "mode = \"dynamic\""), 2, {"--tracker", "replay:" + track});
  };
  const SessionRun different = run_with("different", 6.0);
  ASSERT_EQ(different.output.exit_code, 0) << different.output.output;
  const SessionRun same = run_with("same", 3.0);
  ASSERT_EQ(same.output.exit_code, 0) << same.output.output;
  const std::vector<std::string> eyes = test::session_event_messages(different.db.string(), "stereo_eyes");
  ASSERT_EQ(eyes.size(), 2u);
  EXPECT_NE(eyes[1].find("left eye (tracker eye 1): pupil mean 3 mm"), std::string::npos) << eyes[1];
  EXPECT_NE(eyes[1].find("right eye (tracker eye 0): pupil mean 6 mm"), std::string::npos) << eyes[1];
  EXPECT_NE(eyes[1].find("gaze (0.5, 0.5) from the tracker"), std::string::npos) << eyes[1];
  const ImageRGBA a = saved_frame(different, 1), b = saved_frame(same, 1);
  EXPECT_EQ(half(a, 0).rgba, half(b, 0).rgba) << "the left eye's inputs are the same";
  EXPECT_NE(half(a, 1).rgba, half(b, 1).rgba) << "the right eye's pupil differs";
  // Per-eye samples in the database, as recorded.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(different.db.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(db, "SELECT eye, MIN(pupil_diameter_mm), MAX(pupil_diameter_mm) FROM tracker_samples GROUP BY eye ORDER BY eye",
                     -1, &statement, nullptr);
  std::vector<double> pupils;
  while (sqlite3_step(statement) == SQLITE_ROW) {
    pupils.push_back(sqlite3_column_double(statement, 1));
    pupils.push_back(sqlite3_column_double(statement, 2));
  }
  sqlite3_finalize(statement);
  sqlite3_close(db);
  EXPECT_EQ(pupils, (std::vector<double>{6.0, 6.0, 3.0, 3.0}));
}

TEST(StereoSessionTest, RenderShowsBothEyes) {
  const test::ScratchDir scratch;
  const auto experiment = stereo_demo(scratch.path(), 1024, true, "mode = \"static\"\nmodel = \"spencer\"");
  const std::string out = scratch.file("frame.exr");
  const test::RunOutput rendered =
      test::run_glarelab({"render", experiment.string(), "--condition", "ratio_1.30", "--out", out}, scratch.path());
  ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
  const ImageRGBA frame = read_exr(out).image;
  ASSERT_EQ(frame.width_px, 1024);
  EXPECT_EQ(half(frame, 0).rgba, half(frame, 1).rgba);
  // The lamp's scene, not the background, in each eye's columns: the left eye's first lamp at
  // x 0..255, the right eye's at 512..767, both bright at their centres.
  EXPECT_GT(frame.pixel(128, 128)[1], 1.0f);
  EXPECT_GT(frame.pixel(512 + 128, 128)[1], 1.0f);
}

// A glare mode per side (glare_a, glare_b): each half is the frame of a mono display of its size
// with the same sides, bit for bit (Spencer's glare: no random eye), so each eye's glared side is
// the same position in its view.
TEST(StereoSessionTest, AGlareModePerSideIsTheSamePositionInEachEye) {
  const test::ScratchDir scratch;
  const auto render = [&](int width_px, bool stereo, const std::string& name) {
    const std::filesystem::path dir = scratch.path() / name;
    const auto experiment = stereo_demo(dir, width_px, stereo, "mode = \"control\"\nmodel = \"spencer\"");
    test::write_bytes((dir / "conditions.csv").string(),
                      "name,scene_a,scene_b,glare_a,glare_b\nsides,lamp_100,lamp_130,static,control\n");
    const std::string out = (dir / "frame.exr").string();
    const test::RunOutput output =
        test::run_glarelab({"render", experiment.string(), "--condition", "sides", "--out", out}, dir);
    EXPECT_EQ(output.exit_code, 0) << output.output;
    return read_exr(out).image;
  };
  const ImageRGBA mono = render(512, false, "mono");
  const ImageRGBA both = render(1024, true, "stereo");
  ASSERT_EQ(both.width_px, 1024);
  EXPECT_EQ(half(both, 0).rgba, mono.rgba);
  EXPECT_EQ(half(both, 1).rgba, mono.rgba);
}

// Bad input: exit 2 naming FILE:LINE:COLUMN of the stereo key, no database written.
void expect_refused(const std::filesystem::path& dir, const std::filesystem::path& experiment, const std::string& why) {
  for (const std::string command : {"run", "validate"}) {
    const std::filesystem::path db = dir / (command + ".db");
    std::vector<std::string> arguments = {command, experiment.string()};
    if (command == "run")
      arguments.insert(arguments.end(), {"--display", "offscreen", "--observer", "simulated", "--db", db.string()});
    const test::RunOutput output = test::run_glarelab(arguments, dir);
    EXPECT_EQ(output.exit_code, 2) << command << ": " << output.output;
    // The key's value: the line after encoding in the variant, column 10.
    const std::string text = test::read_bytes(experiment.string());
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(text.find("\nstereo = ")) + 1, '\n');
    EXPECT_NE(output.output.find(experiment.string() + ":" + std::to_string(line) + ":10: key 'display.stereo'"),
              std::string::npos)
        << command << ": " << output.output;
    EXPECT_NE(output.output.find(why), std::string::npos) << command << ": " << output.output;
    EXPECT_FALSE(std::filesystem::exists(db)) << command;
  }
}

TEST(StereoSessionTest, ALayoutThatDoesNotFitAnEyesHalfIsRefused) {
  const test::ScratchDir scratch;
  // 768 px: each eye's half is 384 px, two columns of 192 px for the 256 px lamps.
  expect_refused(scratch.path() / "narrow", stereo_demo(scratch.path() / "narrow", 768, true, "mode = \"control\""),
                 "(256 x 256 px) does not fit its column of 192 x 256 px");
  expect_refused(scratch.path() / "odd", stereo_demo(scratch.path() / "odd", 1026 + 1, true, "mode = \"control\""),
                 "width_px must be even, found 1027");
  expect_refused(scratch.path() / "word",
                 stereo_demo(scratch.path() / "word", 1024, true, "mode = \"control\"", "", "top_bottom"),
                 "must be \"none\" or \"side_by_side\"");
  // The same display without stereo runs (the lamps are cropped to their columns, as always).
  const auto mono = stereo_demo(scratch.path() / "mono", 768, false, "mode = \"control\"");
  EXPECT_EQ(test::run_glarelab({"validate", mono.string()}, scratch.path()).exit_code, 0);
}

}  // namespace
}  // namespace glarelab
