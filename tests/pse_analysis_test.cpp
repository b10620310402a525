// `glarelab analyze` on PSE staircases (analysis/pse_analysis.h): a session run offscreen with the
// simulated observer, whose PSE at glare gain g is 0.75 (1 + k g) of the display's peak, is
// analysed back to those PSEs; the report has the table and Spencer's figure with its 75 % line;
// PSE trials stay out of the threshold analysis.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "analysis/analysis_report.h"
#include "runner/store/result_store.h"
#include "cli_process.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

constexpr double kBrighteningPerGain = 0.05;
const std::vector<double> kGains = {0.0, 2.0, 4.0, 6.0};

std::string pse_session_file() {
  std::string text = R"([experiment]
name = "pse-analysis"
seed = 11
[display]
width_px = 256
height_px = 128
peak_luminance_cd_m2 = 200.0
[scenes]
disc = { generator = "disc_annulus", size_px = 100, disc_diameter_deg = 0.3, annulus_diameter_deg = 0.9, disc_fraction_of_peak = 1.0 }
source = { generator = "light_source", size_px = 100, disc_diameter_deg = 0.3, disc_fraction_of_peak = 0.75 }
[procedure]
type = "staircase"
alternatives = 3
responses = ["left", "right", "neither"]
stimulus_frames = 1
response_rule = "pse"
glare_on = "reference"
tracks_per_condition = true
step_type = "lin"
step_sizes = [40.0, 20.0, 10.0, 5.0]
n_up = 1
n_down = 1
n_reversals = 8
n_trials = 40
min_value = 0.0
max_value = 200.0
start_intensity = 100.0
[observer.simulated]
glare_brightening_per_gain = 0.05
appearance_sd_log10 = 0.02
neither_band_log10 = 0.01
[glare]
grid_px = 64
aperture_width_mm = 10.0
wavelength_samples = 4
)";
  for (std::size_t g = 0; g < kGains.size(); ++g)
    text += "[[conditions.rows]]\nname = \"gain_" + std::to_string(g) +
            "\"\nreference = \"source\"\ncomparison = \"disc\"\nglare = \"static\"\nglare_gain = \"" +
            std::to_string(kGains[g]) + "\"\n";
  return text;
}

TEST(PseAnalysis, SimulatedSessionRecoversTheKnownPsePerGlareStrength) {
  const ScratchDir scratch;
  const std::string experiment = scratch.write("pse.toml", pse_session_file());
  const std::string db = scratch.file("pse.db");
  const auto run = run_glarelab({"run", experiment, "--display", "offscreen", "--observer", "simulated", "--db", db},
                                scratch.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;

  analysis::AnalysisOptions options;
  options.bootstrap_samples = 100;
  const analysis::AnalysisReport report = analysis::analyse(analysis::load_databases({db}), options);
  const analysis::PseAnalysis& pse = report.pse;
  ASSERT_EQ(pse.tracks.size(), kGains.size());
  ASSERT_TRUE(pse.reference_fraction.has_value());
  EXPECT_NEAR(*pse.reference_fraction, 0.75, 1e-12);
  for (const analysis::PseTrack& track : pse.tracks) {
    const double gain = track.glare_gain;
    const double known = 0.75 * (1.0 + kBrighteningPerGain * gain);
    ASSERT_TRUE(track.pse_fraction.has_value()) << track.name << ": " << track.note;
    // Tolerance 0.04 of the peak: the observer's noise is 0.02 log10 (about 5 % of the PSE) and a
    // track has about 40 answers, of which the fit uses those naming a side.
    EXPECT_NEAR(*track.pse_fraction, known, 0.04) << track.name;
    ASSERT_TRUE(track.reversal_mean_fraction.has_value());
    EXPECT_NEAR(*track.reversal_mean_fraction, known, 0.05) << track.name;
    ASSERT_TRUE(track.pse_interval.has_value());
    EXPECT_LT(track.pse_interval->low, *track.pse_fraction);
    EXPECT_GT(track.pse_interval->high, *track.pse_fraction);
    EXPECT_GE(track.trials, 40);
    EXPECT_GT(track.neither, 0) << "the observer never answered 'neither'";
  }
  // One point per gain (one participant, no blocks), in gain order.
  ASSERT_EQ(pse.points.size(), kGains.size());
  for (std::size_t g = 0; g < kGains.size(); ++g) EXPECT_EQ(pse.points[g].glare_gain, kGains[g]);
  EXPECT_GT(pse.points.back().mean_pse_fraction, pse.points.front().mean_pse_fraction + 0.1);
  // PSE trials are unscored: the threshold analysis leaves them alone.
  EXPECT_TRUE(report.staircases.empty());
  // Spencer's figure: the perceived intensity in % of the peak, the 75 % line dashed.
  bool found = false;
  for (const analysis::Figure& figure : report.figures) {
    if (figure.file_stem != "pse") continue;
    found = true;
    EXPECT_NE(figure.svg.find("stroke-dasharray=\"5,4\""), std::string::npos) << "the 75 % line is dashed";
    EXPECT_NE(figure.svg.find("% of display peak"), std::string::npos);
  }
  EXPECT_TRUE(found);
  // The command prints a line per track.
  const auto analyse = run_glarelab({"analyze", db, "--out", scratch.file("out")}, scratch.path());
  ASSERT_EQ(analyse.exit_code, 0) << analyse.output;
  EXPECT_NE(analyse.output.find("pse "), std::string::npos) << analyse.output;
  EXPECT_NE(test::read_bytes(scratch.file("out") + "/report.html").find("Points of subjective equality"), std::string::npos);

  // A second participant (another seed): each point is the mean of the two PSEs with the
  // t interval, mean +- t(0.975, 1) SE, t = 12.7062 (Student's table).
  const auto second = run_glarelab(
      {"run", experiment, "--display", "offscreen", "--observer", "simulated", "--db", db, "--seed", "12"}, scratch.path());
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const analysis::PseAnalysis both = analysis::analyse(analysis::load_databases({db}), options).pse;
  ASSERT_EQ(both.tracks.size(), 2 * kGains.size());
  ASSERT_EQ(both.points.size(), kGains.size());
  for (const analysis::PsePoint& point : both.points) {
    std::vector<double> values;
    for (const analysis::PseTrack& track : both.tracks)
      if (track.glare_gain == point.glare_gain) values.push_back(*track.pse_fraction);
    ASSERT_EQ(values.size(), 2u);
    EXPECT_EQ(point.participants, 2);
    const double mean = 0.5 * (values[0] + values[1]);
    const double se = std::abs(values[0] - values[1]) / 2.0;  // sd / sqrt(2) with sd = |a - b| / sqrt(2)
    EXPECT_NEAR(point.mean_pse_fraction, mean, 1e-12);
    ASSERT_TRUE(point.interval.has_value());
    EXPECT_NEAR(point.interval->high - mean, 12.7062047 * se, 1e-6);
    EXPECT_NEAR(mean - point.interval->low, 12.7062047 * se, 1e-6);
  }
}

// Cut off and resumed, a session of PSE staircases in counterbalanced blocks runs exactly the
// trials of an uninterrupted one (the replay checks every stored condition record).
TEST(PseAnalysis, StopAndResumeRunsTheSameTrialsEndToEnd) {
  const ScratchDir scratch;
  std::string text = pse_session_file();
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("n_trials = 40", "n_trials = 6\nblock_order = \"counterbalanced\"");
  replace("n_reversals = 8", "n_reversals = 4");
  text += "[[blocks]]\nname = \"low\"\nconditions = [\"gain_0\", \"gain_1\"]\n"
          "[[blocks]]\nname = \"high\"\nconditions = [\"gain_2\", \"gain_3\"]\n";
  const std::string file = scratch.write("pse_blocks.toml", text);
  const std::string db = scratch.file("runs.db");
  const std::vector<std::string> base = {"run", file, "--display", "offscreen", "--observer", "simulated", "--db", db};
  for (const auto& extra : std::vector<std::vector<std::string>>{
           {"--participant-number", "2"}, {"--participant-number", "2", "--stop-after", "9"}, {"--resume", "2"}}) {
    std::vector<std::string> arguments = base;
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const auto result = run_glarelab(arguments, scratch.path());
    ASSERT_EQ(result.exit_code, 0) << result.output;
  }
  const ResultStore store(db);
  const auto sessions = store.load_sessions();
  ASSERT_EQ(sessions.size(), 2u);
  const auto whole = store.load_trials(sessions[0].id);
  const auto resumed = store.load_trials(sessions[1].id);
  EXPECT_EQ(sessions[1].status, "completed");
  ASSERT_GT(whole.size(), 9u);
  ASSERT_EQ(resumed.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(resumed[i].condition, whole[i].condition) << "trial " << i;
    EXPECT_EQ(resumed[i].intensity, whole[i].intensity) << "trial " << i;
    EXPECT_EQ(resumed[i].response, whole[i].response) << "trial " << i;
    EXPECT_EQ(resumed[i].reversal, whole[i].reversal) << "trial " << i;
  }
  // Participant 2 runs the second block first.
  EXPECT_NE(whole.front().condition.find("\"block_name\":\"high\""), std::string::npos) << whole.front().condition;
}

}  // namespace
}  // namespace glarelab
