// The study files in examples/ run end to end offscreen with the simulated observer, and their
// trials land in the database as the procedures define them.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/exr_io.h"
#include "protocols/json_text.h"
#include "protocols/staircase.h"
#include "runner/store/result_store.h"
#include "cli_process.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

struct StudyRun {
  std::vector<TrialRecord> trials;
  std::vector<std::string> events;  // "kind: message"
  std::string analysis_summary;     // what `glarelab analyze` printed for the study's database
  std::string report_html;          // the report it wrote
};

// Every study's database goes through `glarelab analyze` as a lab would run it.
void analyse_study(const std::filesystem::path& db, const ScratchDir& scratch, StudyRun& run) {
  const auto out = scratch.path() / "analysis";
  const auto result = run_glarelab({"analyze", db.string(), "--out", out.string()}, scratch.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  run.analysis_summary = result.output;
  run.report_html = test::read_bytes((out / "report.html").string());
  EXPECT_NE(run.report_html.find("<h2>Timing quality</h2>"), std::string::npos);
  // Offscreen on the virtual clock: the report says so where the dropped frames are counted.
  EXPECT_NE(run.report_html.find("<td>virtual: one refresh period per flip, so no frame can drop</td>"),
            std::string::npos);
  EXPECT_NE(run.analysis_summary.find(" dropped on the virtual clock"), std::string::npos) << run.analysis_summary;
  // No statistic printed as NaN or inf ("nan" as a word of its own, as printf and to_string write it).
  for (const std::string word : {"nan", "NaN", "inf"}) {
    for (std::size_t at = run.report_html.find(word); at != std::string::npos; at = run.report_html.find(word, at + 1)) {
      const auto letter = [&](std::size_t i) { return i < run.report_html.size() && std::isalpha(static_cast<unsigned char>(run.report_html[i])); };
      EXPECT_TRUE((at > 0 && letter(at - 1)) || letter(at + word.size()))
          << "'" << word << "' in the report: " << run.report_html.substr(at > 60 ? at - 60 : 0, 120);
    }
  }
  EXPECT_TRUE(std::filesystem::exists(out / "trials.csv"));
}

StudyRun run_example(const std::string& file, const ScratchDir& scratch) {
  const auto db = scratch.path() / "study.db";
  const auto result = run_glarelab({"run", std::string(GLARELAB_SOURCE_DIR) + "/examples/" + file, "--display",
                                    "offscreen", "--observer", "simulated", "--db", db.string()},
                                   scratch.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  const ResultStore store(db.string());
  const auto sessions = store.load_sessions();
  StudyRun run;
  if (sessions.size() != 1) {
    ADD_FAILURE() << "expected one session, found " << sessions.size();
    return run;
  }
  EXPECT_EQ(sessions[0].status, "completed");
  run.trials = store.load_trials(sessions[0].id);
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(store.handle(), "SELECT kind || ': ' || message FROM session_events ORDER BY id", -1, &statement,
                     nullptr);
  while (sqlite3_step(statement) == SQLITE_ROW)
    run.events.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(statement, 0)));
  sqlite3_finalize(statement);
  analyse_study(db, scratch, run);
  return run;
}

// The value of a "key":"value" member of a flat JSON object written by JsonObjectWriter.
std::string json_member(const std::string& json, const std::string& key) {
  const std::string needle = "\"" + key + "\":\"";
  const auto start = json.find(needle);
  if (start == std::string::npos) return "";
  const auto end = json.find('"', start + needle.size());
  return json.substr(start + needle.size(), end - start - needle.size());
}

// Spencer et al. 1995, section 4: a PSE staircase per glare strength (12) and group (2 blocks),
// the three answers stepping the disc, the glare image and the disc swapping sides, the glare on
// the glare image's side only, and the analysis's PSE per track.
TEST(ExampleStudies, SpencerStaircaseFindsAPsePerGlareStrengthInBothGroups) {
  const ScratchDir scratch;
  const StudyRun run = run_example("spencer_staircase.toml", scratch);
  EXPECT_NE(run.report_html.find("<h2>Points of subjective equality</h2>"), std::string::npos);
  // Replay each track's recorded answers through the Staircase class with the PSE rule worked out
  // here: comparison brighter steps down, reference brighter up, neither reverses the last step
  // (the first one steps toward the middle of [0, 200]).
  StaircaseSpec base;
  base.step_sizes = {40.0, 20.0, 10.0};
  base.step_type = StepType::lin;
  base.n_up = 1;
  base.n_down = 1;
  base.n_reversals = 3;
  base.n_trials = 8;
  base.min_value = 0.0;
  base.max_value = 200.0;
  base.start_value = 100.0;
  std::map<std::string, Staircase> tracks;
  std::map<std::string, bool> last_down;
  std::set<std::string> comparison_sides, responses;
  std::vector<std::string> block_of_trial;
  for (const TrialRecord& trial : run.trials) {
    EXPECT_EQ(trial.procedure, "staircase");
    EXPECT_EQ(json_member(trial.condition, "response_rule"), "pse");
    EXPECT_FALSE(trial.correct.has_value()) << "PSE trials are unscored";
    const std::string side = json_member(trial.condition, "comparison_position");
    comparison_sides.insert(side);
    const std::string other = side == "left" ? "right" : "left";
    EXPECT_EQ(json_member(trial.condition, side + "_glare"), "control") << "the disc is shown without glare";
    EXPECT_EQ(json_member(trial.condition, other + "_glare"), "static");
    EXPECT_EQ(json_member(trial.condition, side), "disc");
    EXPECT_EQ(json_member(trial.condition, "glare_keeps_peak"), "true");
    block_of_trial.push_back(json_member(trial.condition, "block_name"));
    auto found = tracks.try_emplace(trial.staircase, base).first;
    Staircase& staircase = found->second;
    ASSERT_TRUE(trial.intensity.has_value());
    EXPECT_NEAR(*trial.intensity, staircase.next_intensity(), 1e-9) << "trial " << trial.trial_index;
    bool down = false;
    if (trial.response == side) down = true;
    else if (trial.response == other) down = false;
    else if (last_down.count(trial.staircase)) down = !last_down[trial.staircase];
    else down = staircase.next_intensity() > 100.0;
    last_down[trial.staircase] = down;
    ASSERT_TRUE(trial.reversal.has_value());
    EXPECT_EQ(*trial.reversal, staircase.add_response(down) ? 1 : 0) << "trial " << trial.trial_index;
    responses.insert(trial.response);
  }
  EXPECT_EQ(tracks.size(), 24u) << "12 glare strengths in 2 groups";
  for (const auto& [name, staircase] : tracks) EXPECT_TRUE(staircase.finished()) << name;
  EXPECT_EQ(comparison_sides, (std::set<std::string>{"left", "right"}));
  EXPECT_EQ(responses, (std::set<std::string>{"left", "right", "neither"}));
  // Participant 1 (the first session in the database) runs the group without context first, all
  // of it, then the group with context.
  ASSERT_FALSE(block_of_trial.empty());
  EXPECT_EQ(block_of_trial.front(), "without_context");
  EXPECT_EQ(block_of_trial.back(), "with_context");
  EXPECT_TRUE(std::is_partitioned(block_of_trial.begin(), block_of_trial.end(),
                                  [](const std::string& b) { return b == "without_context"; }));
  // The analysis has a PSE line per track.
  std::size_t pse_lines = 0;
  for (std::size_t at = run.analysis_summary.find("  pse "); at != std::string::npos;
       at = run.analysis_summary.find("  pse ", at + 1))
    ++pse_lines;
  EXPECT_EQ(pse_lines, 24u) << run.analysis_summary;
  bool rounding_logged = false;
  for (const std::string& event : run.events)
    rounding_logged = rounding_logged || event.find("duration_rounding: stimulus_duration_s 0.4 s -> 24 frames") == 0;
  EXPECT_TRUE(rounding_logged);
}

TEST(ExampleStudies, RitschelTwoAfcHasEveryPairBothWaysRound) {
  const ScratchDir scratch;
  const StudyRun run = run_example("ritschel_2afc.toml", scratch);
  // The analysis compares the glare modes (not the scenes, which are the same on both sides), per
  // instruction pooled over scenes as Ritschel's Fig. 12.
  EXPECT_NE(run.report_html.find("<h2>Forced choice</h2>"), std::string::npos);
  for (const std::string instruction : {"brighter", "attractive", "realistic"})
    EXPECT_NE(run.analysis_summary.find("forced choice pooled: instruction=" + instruction), std::string::npos)
        << run.analysis_summary;
  EXPECT_EQ(run.analysis_summary.find("'lamp_"), std::string::npos) << run.analysis_summary;
  // 2 scenes x 3 condition pairs x 3 instructions x 2 side assignments.
  ASSERT_EQ(run.trials.size(), 36u);
  std::map<std::string, int> left_count, right_count;
  std::map<std::string, int> per_row;
  for (const TrialRecord& trial : run.trials) {
    EXPECT_EQ(trial.procedure, "forced_choice");
    EXPECT_FALSE(trial.intensity.has_value());
    const std::string& c = trial.condition;
    // One scene on both sides, each side under its own glare mode (rendered by the glare engine).
    EXPECT_EQ(json_member(c, "left"), json_member(c, "scene")) << c;
    EXPECT_EQ(json_member(c, "right"), json_member(c, "scene")) << c;
    const std::string condition_left = json_member(c, "left_glare");
    const std::string condition_right = json_member(c, "right_glare");
    EXPECT_NE(condition_left, condition_right) << c;
    const std::set<std::string> pair = {json_member(c, "condition_a"), json_member(c, "condition_b")};
    EXPECT_EQ(pair, (std::set<std::string>{condition_left, condition_right})) << c;
    ++left_count[condition_left];
    ++right_count[condition_right];
    ++per_row[json_member(c, "name")];
    // The same luminance on both sides: no answer is physically right, not even "brighter".
    EXPECT_FALSE(trial.correct.has_value()) << c;
  }
  EXPECT_EQ(per_row.size(), 18u);
  for (const auto& [row, count] : per_row) EXPECT_EQ(count, 2) << row;
  for (const std::string condition : {"control", "static", "dynamic"}) {
    EXPECT_EQ(left_count[condition], 12) << condition;
    EXPECT_EQ(right_count[condition], 12) << condition;
  }
  // Each instruction is a block of 12 consecutive trials, numbered in the order they ran.
  std::set<std::string> instructions;
  for (std::size_t i = 0; i < run.trials.size(); ++i) {
    EXPECT_EQ(run.trials[i].block, static_cast<int>(i / 12));
    const std::string instruction = json_member(run.trials[i].condition, "instruction");
    if (i % 12 != 0) {
      EXPECT_EQ(instruction, json_member(run.trials[i - 1].condition, "instruction"));
    }
    instructions.insert(instruction);
  }
  EXPECT_EQ(instructions, (std::set<std::string>{"brighter", "attractive", "realistic"}));
  // [presentation]: the instruction screen opens the session, each block's instruction screen
  // opens its first trial (60 flips each, the minimum), and 0.5 s between trials is 30 frames.
  const auto logged = [&](const std::string& prefix) {
    return std::any_of(run.events.begin(), run.events.end(), [&](const std::string& e) { return e.rfind(prefix, 0) == 0; });
  };
  EXPECT_TRUE(logged("screen: trial 0, instructions: 'Two images of the same scene are shown ...' shown 60 flips"));
  EXPECT_TRUE(logged("screen: trial 0, block: 'In the next trials: which image "));
  EXPECT_TRUE(logged("screen: trial 12, block: 'In the next trials: which image "));
  EXPECT_TRUE(logged("duration_rounding: presentation.isi_duration_s 0.5 s -> 30 frames"));
  EXPECT_TRUE(logged("trial_phases: trial 0: screen 120, interval 1 15 (frames 0-14) flips"));
  EXPECT_TRUE(logged("trial_phases: trial 1: inter-trial 30, interval 1 15 (frames 0-14) flips"));
  EXPECT_TRUE(logged("trial_phases: trial 12: inter-trial 30, screen 60, interval 1 15 (frames 0-14) flips"));
  // Glare was applied per side and said so (the backend once, the held PSF through blinks per trial).
  bool backend_logged = false, per_side_logged = false;
  // "auto" settles each glare layout on its first interval, prepared or live by this machine's
  // measured cost per frame: one event for a dynamic source beside a control, one for a dynamic
  // beside a static (a static layout computes one frame an interval and is always prepared).
  std::map<std::string, int> layouts_settled;
  for (const std::string& event : run.events) {
    backend_logged = backend_logged || event.rfind("glare_backend: glare backend", 0) == 0;
    per_side_logged = per_side_logged || (event.rfind("glare_skipped: trial", 0) == 0 &&
                                          event.find("glare layer frame(s)") != std::string::npos);
    if (event.rfind("presentation_mode: glare trials: ", 0) != 0) continue;
    EXPECT_TRUE(event.rfind("presentation_mode: glare trials: frames prepared before onset where the glare is ", 0) == 0 ||
                event.rfind("presentation_mode: glare trials: live from trial ", 0) == 0)
        << event;
    EXPECT_NE(event.find(" ms per glare frame on this machine and "), std::string::npos) << event;
    for (const std::string layout : {"control + dynamic", "dynamic + static", "control + static"})
      if (event.find("where the glare is " + layout + ";") != std::string::npos ||
          event.find("where the glare is " + layout + ",") != std::string::npos)
        ++layouts_settled[layout];
  }
  EXPECT_TRUE(backend_logged);
  EXPECT_TRUE(per_side_logged);
  EXPECT_EQ(layouts_settled, (std::map<std::string, int>{{"control + dynamic", 1}, {"dynamic + static", 1}}));
  // First session in a new database: participant number 1, and the session says how it was chosen.
  bool participant_logged = false;
  for (const std::string& event : run.events)
    participant_logged = participant_logged || event.find("participant_number: 1 (1 + 0 earlier session(s)") == 0;
  EXPECT_TRUE(participant_logged);
}

// Participants in one database: the second session is participant 2 by default; a session given
// --participant-number 2 explicitly, cut off and resumed, runs exactly participant 2's trials.
TEST(ExampleStudies, RitschelBlockOrderFollowsTheParticipantNumber) {
  const ScratchDir scratch;
  const auto db = scratch.path() / "participants.db";
  // The study as it is, on a small display with one frame per trial: this test is about orders.
  const std::string examples = std::string(GLARELAB_SOURCE_DIR) + "/examples/";
  std::istringstream study(test::read_bytes(examples + "ritschel_2afc.toml"));
  std::string text, line;
  while (std::getline(study, line)) {
    if (line.rfind("width_px", 0) == 0) line = "width_px = 128";
    if (line.rfind("height_px", 0) == 0) line = "height_px = 64";
    if (line.rfind("stimulus_duration_s", 0) == 0) line = "stimulus_frames = 1";
    if (const auto at = line.find("\"scenes/"); at != std::string::npos) line.insert(at + 1, examples);
    text += line + "\n";
  }
  const std::string file = scratch.write("ritschel_small.toml", text);
  const std::vector<std::string> base = {"run", file, "--display", "offscreen", "--observer", "simulated", "--db",
                                         db.string()};
  for (const auto& extra : std::vector<std::vector<std::string>>{
           {}, {}, {"--participant-number", "2", "--stop-after", "14"}, {"--resume", "3"}}) {
    std::vector<std::string> arguments = base;
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const auto result = run_glarelab(arguments, scratch.path());
    ASSERT_EQ(result.exit_code, 0) << result.output;
  }
  const ResultStore store(db.string());
  const auto sessions = store.load_sessions();
  ASSERT_EQ(sessions.size(), 3u);
  std::vector<std::vector<std::string>> conditions;
  std::vector<std::string> orders;
  for (const auto& session : sessions) {
    EXPECT_EQ(session.status, "completed");
    const auto trials = store.load_trials(session.id);
    ASSERT_EQ(trials.size(), 36u);
    std::string order;
    conditions.emplace_back();
    for (std::size_t i = 0; i < trials.size(); ++i) {
      if (i % 12 == 0) order += json_member(trials[i].condition, "instruction") + " ";
      conditions.back().push_back(trials[i].condition);
    }
    orders.push_back(order);
    const int participant = session.id == sessions[0].id ? 1 : 2;
    EXPECT_NE(session.config.find("participant_number = " + std::to_string(participant)), std::string::npos);
  }
  EXPECT_EQ(conditions[1], conditions[2]) << "participant 2, uninterrupted and resumed";
  // Participant 2's random order is fixed by the seed; with three blocks the chance it repeats
  // participant 1's is 1/6, and it does not for this seed.
  EXPECT_NE(orders[0], orders[1]);
}

// Kakimoto et al. 2007, section 4.4: a 60-year-old (0.5 D of amplitude) reads a page 0.4 m away
// with a lamp behind it at 1 m (scenes/reading_desk.exr, with a Z channel: the depth of field is on).
// Accommodated on the page, the naked eye is left with -2 D there and -0.5 D on the lamp; through
// +2.50 D readers the page is sharp and the lamp 1.6 D too near. Within one session the "spectacles"
// column switches between them: the text's contrast is higher with the readers, the bulb (0.1
// degrees, 2.8 px) brighter without them; every frame of a condition is the same (static glare),
// and each condition's refraction is recorded in an observer_refraction event.
TEST(ExampleStudies, PresbyopeReadingGlassesSwitchWithinOneSession) {
  const ScratchDir scratch;
  const auto db = scratch.path() / "study.db";
  const auto frames = scratch.path() / "frames";
  const auto result = run_glarelab({"run", std::string(GLARELAB_SOURCE_DIR) + "/examples/presbyope_reading_glasses.toml",
                                    "--display", "offscreen", "--observer", "simulated", "--db", db.string(),
                                    "--save-frames", frames.string()},
                                   scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const ResultStore store(db.string());
  const auto sessions = store.load_sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].status, "completed");
  const auto trials = store.load_trials(sessions[0].id);
  ASSERT_EQ(trials.size(), 8u);  // 2 conditions x 2 categories x 2 repetitions
  std::map<std::string, std::vector<ImageRGBA>> by_condition;
  for (const TrialRecord& trial : trials) {
    const std::string name = json_member(trial.condition, "name");
    EXPECT_EQ(json_member(trial.condition, "spectacles"), name == "without_glasses" ? "none" : "reading");
    char file[32];
    std::snprintf(file, sizeof file, "trial_%04d.exr", trial.trial_index);
    by_condition[name].push_back(read_exr((frames / file).string()).image);
  }
  ASSERT_EQ(by_condition.size(), 2u);
  // The lamp and the page (rows 40-320 of the 512 x 384 frame; the question text is drawn below),
  // the brightest green value within 12 px of the bulb at (256, 74), and the standard deviation of
  // the page's text lines (x 116-396, y 120-300): its legibility.
  const auto scene_pixels = [](const ImageRGBA& image) {
    std::vector<float> pixels;
    for (int y = 40; y < 320; ++y)
      for (int x = 0; x < 512; ++x) pixels.insert(pixels.end(), image.pixel(x, y), image.pixel(x, y) + 4);
    return pixels;
  };
  const auto bulb_peak = [](const ImageRGBA& image) {
    float peak = 0.0f;
    for (int y = 74 - 12; y < 74 + 12; ++y)
      for (int x = 256 - 12; x < 256 + 12; ++x) peak = std::max(peak, image.pixel(x, y)[1]);
    return peak;
  };
  const auto text_contrast = [](const ImageRGBA& image) {
    double sum = 0.0, sum2 = 0.0, n = 0.0;
    for (int y = 120; y < 300; ++y)
      for (int x = 116; x < 396; ++x) {
        const double g = image.pixel(x, y)[1];
        sum += g, sum2 += g * g, n += 1.0;
      }
    return std::sqrt(sum2 / n - (sum / n) * (sum / n));
  };
  for (const auto& [name, images] : by_condition) {
    ASSERT_EQ(images.size(), 4u) << name;
    for (const ImageRGBA& image : images)
      EXPECT_EQ(scene_pixels(image), scene_pixels(images[0])) << name << ": static glare shows one frame";
  }
  const ImageRGBA& naked_frame = by_condition.at("without_glasses")[0];
  const ImageRGBA& readers_frame = by_condition.at("with_reading_glasses")[0];
  std::printf("bulb peak %.1f cd/m2 naked, %.1f with readers; text sd %.2f naked, %.2f with readers\n",
              bulb_peak(naked_frame), bulb_peak(readers_frame), text_contrast(naked_frame), text_contrast(readers_frame));
  EXPECT_GT(text_contrast(readers_frame), 1.5 * text_contrast(naked_frame));
  EXPECT_GT(bulb_peak(naked_frame), 1.5f * bulb_peak(readers_frame));
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(store.handle(), "SELECT kind || ': ' || message FROM session_events ORDER BY id", -1, &statement,
                     nullptr);
  std::vector<std::string> refraction_events;
  std::string backend;
  while (sqlite3_step(statement) == SQLITE_ROW) {
    const std::string event = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
    if (event.rfind("observer_refraction: ", 0) == 0) refraction_events.push_back(event);
    if (event.rfind("glare_backend: ", 0) == 0) backend = event;
  }
  sqlite3_finalize(statement);
  ASSERT_EQ(refraction_events.size(), 2u);
  EXPECT_NE(refraction_events[0].find("condition 'without_glasses': spectacles 'none'"), std::string::npos);
  EXPECT_NE(refraction_events[0].find("accommodation 0.5 D, residual sphere -2 D, cylinder 0 D"), std::string::npos)
      << refraction_events[0];
  EXPECT_NE(refraction_events[1].find("condition 'with_reading_glasses': spectacles 'reading'"), std::string::npos);
  EXPECT_NE(refraction_events[1].find("residual sphere 0 D, cylinder 0 D"), std::string::npos) << refraction_events[1];
  // The frames' own backend computes them: on a CPU the planned float32 path "auto" takes.
  EXPECT_NE(backend.find("PSFs with the observer's refraction: cpu float32 planned"), std::string::npos) << backend;
}

// Every runnable file in examples/ runs offscreen with the simulated observer: the study files in
// their own tests above, demo.toml in RunCommand.DemoRunsOffscreenAndStoresEveryTrial,
// glare_brightness.toml in PseGradedChoice.ExampleRunsOffscreenAndTheReportFitsEachGlareMode, and any
// other file here, so a new example cannot go untested.
TEST(ExampleStudies, EveryExampleRunsOffscreen) {
  const std::set<std::string> tested_elsewhere = {"spencer_staircase.toml", "ritschel_2afc.toml",
                                                  "luidolt_ratings.toml", "ritschel_adjustment.toml", "demo.toml",
                                                  "presbyope_reading_glasses.toml",
                                                  // tests/pse_graded_choice_test.cpp, at 2 frames per trial
                                                  "glare_brightness.toml",
                                                  // tests/straylight_session_test.cpp, one after the other (the
                                                  // second takes the first's measurement), shortened
                                                  "straylight.toml", "straylight_glare.toml",
                                                  // tests/openxr_display_test.cpp, shortened, offscreen and
                                                  // in Monado's headset
                                                  "luidolt_ratings_headset.toml"};
  std::set<std::string> found;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(GLARELAB_SOURCE_DIR) + "/examples")) {
    if (entry.path().extension() != ".toml") continue;
    const std::string name = entry.path().filename().string();
    found.insert(name);
    if (tested_elsewhere.count(name)) continue;
    const ScratchDir scratch;
    const StudyRun run = run_example(name, scratch);
    EXPECT_FALSE(run.trials.empty()) << name;
  }
  for (const std::string& name : tested_elsewhere) EXPECT_TRUE(found.count(name)) << name << " is gone from examples/";
}

// Ritschel's pairs with the hybrid eye (wave optics near each lamp, Spencer's far field): the per-side
// glare of the pair design takes the model, the session logs the far kernel it integrated.
TEST(ExampleStudies, RitschelPairsRunWithTheHybridEye) {
  const ScratchDir scratch;
  std::string text = test::read_bytes(std::string(GLARELAB_SOURCE_DIR) + "/examples/ritschel_2afc.toml");
  const auto replace = [&](const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
      text.replace(at, from.size(), to);
  };
  replace("[glare]\n", "[glare]\nmodel = \"hybrid\"\n");
  replace("file = \"scenes/", "file = \"" + std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/");
  replace("glare_scenes = [\"lamp_130\", \"lamp_200\"]", "glare_scenes = [\"lamp_200\"]");
  const auto file = scratch.path() / "hybrid_pairs.toml";
  std::ofstream(file) << text;
  const auto db = scratch.path() / "hybrid.db";
  const auto result = run_glarelab({"run", file.string(), "--display", "offscreen", "--observer", "simulated", "--db", db.string()},
                                   scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const ResultStore store(db.string());
  const auto sessions = store.load_sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].status, "completed");
  EXPECT_NE(sessions[0].config.find("model = 'hybrid'"), std::string::npos) << sessions[0].config;
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(store.handle(), "SELECT message FROM session_events WHERE kind = 'glare_model'", -1, &statement, nullptr);
  std::vector<std::string> models;
  while (sqlite3_step(statement) == SQLITE_ROW) models.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(statement, 0)));
  sqlite3_finalize(statement);
  ASSERT_EQ(models.size(), 1u);
  EXPECT_NE(models[0].find("hybrid (far field spencer"), std::string::npos) << models[0];
  // Every pair of modes both ways round, for 3 instructions: 3 pairs x 2 orders x 3 blocks.
  EXPECT_EQ(store.load_trials(sessions[0].id).size(), 18u);
}

TEST(ExampleStudies, LuidoltRatingsRateEverySceneOnEveryCategory) {
  const ScratchDir scratch;
  const StudyRun run = run_example("luidolt_ratings.toml", scratch);
  ASSERT_EQ(run.trials.size(), 24u);  // 4 conditions x 6 categories
  EXPECT_NE(run.report_html.find("<h2>Ratings</h2>"), std::string::npos);
  for (const std::string condition : {"real_lamp", "standard", "glare", "full"})
    EXPECT_NE(run.analysis_summary.find("rating " + condition + ": 6 answers"), std::string::npos) << run.analysis_summary;
  std::set<std::string> seen;
  std::map<std::string, double> sum;
  for (std::size_t t = 0; t < run.trials.size(); ++t) {
    const TrialRecord& trial = run.trials[t];
    EXPECT_EQ(trial.procedure, "rating");
    EXPECT_FALSE(trial.correct.has_value());
    const int rating = std::stoi(trial.response);
    EXPECT_GE(rating, 1);
    EXPECT_LE(rating, 7);  // Luidolt 2020, 7.2.1: a 7-point scale
    const std::string name = json_member(trial.condition, "name");
    seen.insert(name + "/" + json_member(trial.condition, "category"));
    sum[name] += rating;
    // Luidolt's order: the real lamp's six categories first (block 0), then the simulations.
    EXPECT_EQ(name == "real_lamp", t < 6) << t << " " << trial.condition;
    EXPECT_EQ(trial.block, t < 6 ? 0 : 1);
    EXPECT_EQ(trial.condition.find("\"stimulus\":\"real\"") != std::string::npos, name == "real_lamp");
  }
  EXPECT_EQ(seen.size(), 24u) << "every condition x category exactly once";
  // Means 3.0 (standard) and 5.0 (full) with noise sd 0.7 over six ratings each: the order
  // survives the noise (the difference of the sums has sd 2.4, against 12).
  EXPECT_LT(sum["standard"], sum["full"]);
}

TEST(ExampleStudies, RitschelAdjustmentStoresBothSettingsAndTheirMean) {
  const ScratchDir scratch;
  const auto db = scratch.path() / "study.db";
  const StudyRun run = run_example("ritschel_adjustment.toml", scratch);
  // The analysis groups the settings by target level and glare mode (Ritschel's Fig. 12, right).
  EXPECT_NE(run.report_html.find("<h2>Double adjustment</h2>"), std::string::npos);
  for (const std::string level : {"low", "high"})
    for (const std::string mode : {"control", "static", "dynamic"})
      EXPECT_NE(run.report_html.find("<td>" + mode + "</td><td>" + level + "</td>"), std::string::npos) << mode << " " << level;
  ASSERT_EQ(run.trials.size(), 12u);  // 6 condition rows x 2 repetitions
  const ResultStore store(db.string());
  for (const TrialRecord& trial : run.trials) {
    EXPECT_EQ(trial.procedure, "adjustment");
    EXPECT_FALSE(trial.correct.has_value());
    const auto settings = store.load_adjustments(trial.id);
    ASSERT_EQ(settings.size(), 2u);
    EXPECT_EQ(settings[0].spot, 0);
    EXPECT_EQ(settings[1].spot, 1);
    ASSERT_TRUE(trial.intensity.has_value());
    EXPECT_DOUBLE_EQ(*trial.intensity, 0.5 * (settings[0].value_cd_m2 + settings[1].value_cd_m2));
    // The scenes lamp_N peak at N cd/m2; the matching observer's settings scatter with
    // sd 0.05 log10 around the target, so 0.25 log10 is five standard deviations.
    const std::string target = json_member(trial.condition, "target");
    const double target_cd_m2 = std::stod(target.substr(target.find('_') + 1));
    for (const auto& setting : settings)
      EXPECT_LT(std::abs(std::log10(setting.value_cd_m2 / target_cd_m2)), 0.25) << trial.condition;
    // Start values lie within start_range_log10 = 0.3 of the target and differ between spots.
    const double start_left = std::stod(json_member(trial.condition, "start_left_cd_m2"));
    const double start_right = std::stod(json_member(trial.condition, "start_right_cd_m2"));
    EXPECT_LE(std::abs(std::log10(start_left / target_cd_m2)), 0.3 + 1e-9);
    EXPECT_LE(std::abs(std::log10(start_right / target_cd_m2)), 0.3 + 1e-9);
    EXPECT_NE(start_left, start_right);
  }
}

}  // namespace
}  // namespace glarelab
