// The GPU engine makes the CPU engine's frames: every shipped example run offscreen with
// --save-frames under `--engine gpu` (GL glare, GL perception stages) writes the frames `--engine cpu`
// writes (planned float32 glare, float32 perception stages), within 1e-3 relative and 1e-3 cd/m2
// where darker than 1 cd/m2. Kept short: each example copied with two frames per stimulus and run
// for its first few trials, the same trials under both engines (the seed fixes the order and the
// simulated observer's answers do not depend on the frames): two for demo and ritschel_2afc, whose
// first two show control, static and dynamic glare; eight for the Luidolt example, whose first six
// show the real lamp (its seventh has every perception stage and dynamic glare, its eighth tone
// mapping alone); three for the others. Each example's entry below lists the glare modes,
// spectacles and perception stages its trials show, and the test checks that they do
// (ritschel_adjustment's first control trial comes later; control frames are every other glared
// example's too). glare_quest_plus shows no glare (no glare column: every condition control), and
// the analytic models (spencer_staircase's) are integrated on the CPU in both engines: their frames
// are equal bit for bit. The GPU session's read-backs are counted too: with --save-frames each
// interval reads its shown frames back (acceptance 2's count, seen to count).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cli_process.h"
#include "analysis/loaded_database.h"
#include "core/exr_io.h"
#include "example_copies.h"
#include "read_back_events.h"
#include "runner/store/result_store.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

namespace fs = std::filesystem;

// The largest difference of `got` from `reference` over the colour channels, each scaled by the
// larger of 1 cd/m2 and the reference value (1e-3 relative, 1e-3 cd/m2 where darker), and where.
struct WorstDifference {
  double scaled = 0.0;
  std::size_t index = 0;
};
WorstDifference worst_scaled_difference(const ImageRGBA& got, const ImageRGBA& reference) {
  WorstDifference worst;
  for (std::size_t i = 0; i < reference.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const double scale = std::max(1.0, std::abs(static_cast<double>(reference.rgba[i])));
    const double scaled = std::abs(static_cast<double>(got.rgba[i]) - reference.rgba[i]) / scale;
    if (scaled > worst.scaled) worst = {scaled, i};
  }
  return worst;
}

// The glare modes, spectacles and perception stages a session's trials showed, as "glare <mode>",
// "spectacles <name>" and "perception <stages>", from each trial's stored condition JSON (its glare,
// glare_a and glare_b, left_glare and right_glare, spectacles and perception columns).
std::set<std::string> settings_shown(const std::string& database) {
  const ResultStore store(database);
  std::set<std::string> settings;
  for (const TrialRecord& trial : store.load_trials(store.load_sessions().at(0).id))
    for (const auto& [column, value] : analysis::parse_condition_json(trial.condition)) {
      if (column == "glare" || column == "glare_a" || column == "glare_b" || column == "left_glare" ||
          column == "right_glare")
        settings.insert("glare " + value);
      if (column == "spectacles" || column == "perception") settings.insert(column + " " + value);
    }
  return settings;
}

struct ShortExample {
  std::string file;
  std::string trials;             // --stop-after
  std::set<std::string> shown;  // what those trials show (settings_shown)
};

class GpuEngineFrames : public ::testing::TestWithParam<ShortExample> {};

TEST_P(GpuEngineFrames, EqualTheCpuEnginesWithinOnePerMille) {
  const test::ScratchDir scratch;
  const fs::path file = test::examples_with_frames(scratch.path(), 2) / GetParam().file;
  std::map<std::string, fs::path> frames;
  for (const std::string engine : {"cpu", "gpu"}) {
    frames[engine] = scratch.path() / ("frames_" + engine);
    const test::RunOutput run = test::run_glarelab(
        {"run", file.string(), "--display", "offscreen", "--observer", "simulated", "--seed", "1", "--db",
         (scratch.path() / (engine + ".db")).string(), "--stop-after", GetParam().trials, "--save-frames", frames[engine].string(),
         "--engine", engine},
        scratch.path());
    if (engine == std::string("gpu") && run.exit_code == 3) GTEST_SKIP() << "no OpenGL 4.5 context here: " << run.output;
    ASSERT_EQ(run.exit_code, 0) << engine << ": " << run.output;
  }
  // The trials run show what they are chosen to show (a change of the seed's order is seen here).
  EXPECT_EQ(settings_shown((scratch.path() / "cpu.db").string()), GetParam().shown);
  // --save-frames reads each shown frame back at its flip, after frame 0 was made: the GPU
  // session's read-back count (its `read_backs` events) shows it in every interval it logs, the
  // counterpart of tests/gpu_round_trip_test.cpp's sessions without it, which read back none.
  // Every example but glare_quest_plus (no glare, no perception stage) logs one per interval.
  const std::vector<test::IntervalReadBacks> read_backs = test::read_back_events((scratch.path() / "gpu.db").string());
  EXPECT_EQ(read_backs.empty(), GetParam().file == "glare_quest_plus.toml") << read_backs.size() << " read_backs events";
  for (const test::IntervalReadBacks& interval : read_backs) {
    ASSERT_GE(interval.frames_computed, 1) << interval.message;
    EXPECT_GE(interval.frames_after_first, 1u) << interval.message;
  }
  int compared = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(frames["cpu"])) {
    SCOPED_TRACE(entry.path().filename().string());
    const fs::path gpu_frame = frames["gpu"] / entry.path().filename();
    ASSERT_TRUE(fs::exists(gpu_frame)) << "the GPU engine's session wrote no such frame";
    const ImageRGBA reference = read_exr(entry.path().string()).image;
    const ImageRGBA got = read_exr(gpu_frame.string()).image;
    ASSERT_EQ(got.width_px, reference.width_px);
    ASSERT_EQ(got.height_px, reference.height_px);
    const WorstDifference worst = worst_scaled_difference(got, reference);
    const std::size_t pixel = worst.index / 4;
    std::cout << GetParam().file << " " << entry.path().filename().string() << ": gpu against cpu, worst "
              << worst.scaled << " (relative above 1 cd/m2, cd/m2 below)\n";
    EXPECT_LE(worst.scaled, 1e-3) << "at pixel (" << pixel % static_cast<std::size_t>(reference.width_px) << ", "
                                  << pixel / static_cast<std::size_t>(reference.width_px) << ") channel "
                                  << worst.index % 4 << ": gpu " << got.rgba[worst.index] << ", cpu "
                                  << reference.rgba[worst.index] << " cd/m2";
    ++compared;
  }
  EXPECT_GT(compared, 0);
}

INSTANTIATE_TEST_SUITE_P(Examples, GpuEngineFrames,
                         ::testing::Values(
                             ShortExample{"demo.toml", "2", {"glare control", "glare dynamic", "glare static"}},
                             ShortExample{"glare_brightness.toml", "3", {"glare control", "glare dynamic", "glare static"}},
                             ShortExample{"glare_quest_plus.toml", "3", {}},
                             ShortExample{"luidolt_ratings.toml", "8",
                                          {"glare control", "glare dynamic", "perception all", "perception tone_mapping"}},
                             ShortExample{"presbyope_reading_glasses.toml", "3", {"spectacles none", "spectacles reading"}},
                             ShortExample{"ritschel_2afc.toml", "2", {"glare control", "glare dynamic", "glare static"}},
                             ShortExample{"ritschel_adjustment.toml", "3", {"glare dynamic", "glare static"}},
                             ShortExample{"spencer_staircase.toml", "3", {"glare control", "glare static"}}),
                         [](const ::testing::TestParamInfo<ShortExample>& param) {
                           return param.param.file.substr(0, param.param.file.find('.'));
                         });

}  // namespace
}  // namespace glarelab
