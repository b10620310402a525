// The final QUEST+ posterior per track that `glarelab analyze` reports, rebuilt from a
// results database by replaying the stored design and trials as resume does
// (runner/cli/quest_plus_posteriors.h), checked against independent references:
//   - a QuestPlus fed directly with each stored trial's stimulus (found on the grid from the
//     stored intensity and condition columns) and its stored correctness: the same joint posterior
//     to 1e-12, and the same mode/mean/SD;
//   - the last trial's logged summary (the posterior *before* it) equals that QuestPlus's summary
//     before the last answer;
//   - each marginal sums to 1 and its mean and SD, summed here over the grid, equal the summary's;
//   - `glarelab analyze` writes one figure per track and parameter, the table and the CSV.
//   - a Psi track likewise, in log10 cd/m2; a session whose scene file moved gives a note.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "analysis/analysis_report.h"
#include "analysis/loaded_database.h"
#include "analysis/report_output.h"
#include "cli_process.h"
#include "protocols/adaptive_procedure.h"
#include "protocols/experiment.h"
#include "runner/cli/quest_plus_posteriors.h"
#include "tests/example_dry_run.h"

namespace glarelab {
namespace {

const std::string kExample = std::string(GLARELAB_SOURCE_DIR) + "/examples/glare_quest_plus.toml";

// The grid index of the stimulus a stored trial showed: the intensity and the track's stimulus
// columns read back from its condition record.
std::size_t stimulus_index_of(const QuestPlus& q, const analysis::LoadedTrial& trial,
                              const std::vector<std::string>& columns) {
  std::vector<double> shown = {std::stod(*trial.condition_value("intensity"))};
  for (const std::string& column : columns) shown.push_back(std::stod(*trial.condition_value(column)));
  for (std::size_t s = 0; s < q.stimulus_count(); ++s) {
    const std::vector<double> at = q.stimulus_at(s);
    bool same = true;
    for (std::size_t d = 0; d < at.size(); ++d) same = same && std::abs(at[d] - shown[d]) <= 1e-9;
    if (same) return s;
  }
  ADD_FAILURE() << "stimulus of trial " << trial.record.trial_index << " is not on the grid";
  return 0;
}

double logged(const analysis::LoadedTrial& trial, const std::string& key) {
  const std::string* text = trial.condition_value(key);
  EXPECT_NE(text, nullptr) << key;
  return text ? std::stod(*text) : NAN;
}

class QuestPlusPosteriorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // The example's own procedure answered by its simulated observer, stored as a session stores
    // it (tests/example_dry_run.h): 24 trials on each of its two tracks.
    test::dry_run_example(kExample, scratch_.file("runs.db"), {3});
    data_ = analysis::load_databases({scratch_.file("runs.db")});
  }
  test::ScratchDir scratch_;
  analysis::LoadedData data_;
};

TEST_F(QuestPlusPosteriorTest, RebuiltPosteriorEqualsAQuestPlusFedTheStoredTrials) {
  ASSERT_EQ(data_.sessions.size(), 1u);
  const analysis::LoadedSession& session = data_.sessions[0];
  ASSERT_TRUE(runs_quest_plus(session));
  const ReplayedSession replayed = replay_stored_session(session);
  const auto* procedure = dynamic_cast<const AdaptiveProcedure*>(replayed.procedure.get());
  ASSERT_NE(procedure, nullptr);
  const std::vector<analysis::QuestPlusPosterior> report =
      quest_plus_posteriors_of(*procedure, replayed.experiment, session.label);
  ASSERT_EQ(report.size(), 2u);

  const Experiment experiment = load_experiment(kExample);
  for (std::size_t t = 0; t < experiment.adaptive.tracks.size(); ++t) {
    const AdaptiveTrackSpec& track = experiment.adaptive.tracks[t];
    QuestPlus reference(quest_plus_track_grid(experiment, track).spec);
    std::vector<const analysis::LoadedTrial*> trials;
    for (const analysis::LoadedTrial& trial : session.trials)
      if (trial.record.staircase == track.quest_plus.spec.name) trials.push_back(&trial);
    ASSERT_EQ(trials.size(), 24u);
    for (std::size_t k = 0; k < trials.size(); ++k) {
      const analysis::LoadedTrial& trial = *trials[k];
      ASSERT_EQ(trial.record.procedure, "quest");
      ASSERT_TRUE(trial.record.correct.has_value());
      if (k + 1 == trials.size()) {
        // The last trial logged the posterior it was chosen from: the reference's before its answer.
        for (const ParameterSummary& p : reference.summary()) {
          EXPECT_NEAR(logged(trial, "posterior_" + p.name + "_mode"), p.mode, 1e-12) << p.name;
          EXPECT_NEAR(logged(trial, "posterior_" + p.name + "_mean"), p.mean, 1e-12) << p.name;
          EXPECT_NEAR(logged(trial, "posterior_" + p.name + "_sd"), p.sd, 1e-12) << p.name;
        }
      }
      reference.add_response(stimulus_index_of(reference, trial, track.quest_plus.stimulus_columns),
                             *trial.record.correct == 1);
    }

    const analysis::QuestPlusPosterior& rebuilt = report[t];
    EXPECT_EQ(rebuilt.track, track.quest_plus.spec.name);
    EXPECT_EQ(rebuilt.method, "quest_plus");
    EXPECT_EQ(rebuilt.trials, 24);
    const std::vector<double>& joint = procedure->quest_plus(t)->posterior();
    ASSERT_EQ(joint.size(), reference.posterior().size());
    for (std::size_t p = 0; p < joint.size(); ++p) ASSERT_NEAR(joint[p], reference.posterior()[p], 1e-12) << p;

    const std::vector<ParameterSummary> summary = reference.summary();
    ASSERT_EQ(rebuilt.marginals.size(), summary.size());
    for (std::size_t p = 0; p < summary.size(); ++p) {
      const analysis::MarginalPosterior& m = rebuilt.marginals[p];
      EXPECT_EQ(m.parameter, summary[p].name);
      EXPECT_NEAR(m.mode, summary[p].mode, 1e-12) << m.parameter;
      EXPECT_NEAR(m.mean, summary[p].mean, 1e-12) << m.parameter;
      EXPECT_NEAR(m.sd, summary[p].sd, 1e-12) << m.parameter;
      // The marginal, summed over the grid here: total 1, first and second moments.
      ASSERT_EQ(m.probabilities.size(), m.values.size());
      double total = 0.0, mean = 0.0, square = 0.0;
      for (std::size_t i = 0; i < m.values.size(); ++i) {
        total += m.probabilities[i];
        mean += m.probabilities[i] * m.values[i];
        square += m.probabilities[i] * m.values[i] * m.values[i];
      }
      EXPECT_NEAR(total, 1.0, 1e-12) << m.parameter;
      EXPECT_NEAR(mean, summary[p].mean, 1e-9) << m.parameter;
      EXPECT_NEAR(std::sqrt(std::max(0.0, square - mean * mean)), summary[p].sd, 1e-6) << m.parameter;
    }
  }
  // Units on the threshold, the coefficient and the probabilities (the figures' axis labels).
  EXPECT_EQ(analysis::parameter_axis_label(report[0].marginals[0]), "threshold (dB cd/m2)");
  EXPECT_EQ(report[0].marginals.back().unit, "probability");
  const auto& second = report[1].marginals;
  const auto coefficient = std::find_if(second.begin(), second.end(), [](const analysis::MarginalPosterior& m) {
    return m.parameter == "threshold_per_reference_gain_db";
  });
  ASSERT_NE(coefficient, second.end());
  EXPECT_EQ(coefficient->unit, "dB cd/m2 per reference_gain_db");
  EXPECT_EQ(coefficient->values, (std::vector<double>{0.8, 0.9, 1.0, 1.1, 1.2}));
}

TEST_F(QuestPlusPosteriorTest, AnalyzeWritesOneFigurePerTrackAndParameter) {
  const auto result = test::run_glarelab({"analyze", scratch_.file("runs.db"), "--out", scratch_.file("out"),
                                          "--bootstrap", "0", "--threads", "1"},
                                         scratch_.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("quest_plus P3"), std::string::npos) << result.output;
  std::vector<std::string> notes;
  const std::vector<analysis::QuestPlusPosterior> tracks = rebuild_quest_plus_posteriors(data_, notes);
  EXPECT_TRUE(notes.empty());
  ASSERT_EQ(tracks.size(), 2u);
  const std::filesystem::path out = scratch_.file("out");
  const std::string html = test::read_bytes((out / "report.html").string());
  EXPECT_NE(html.find("QUEST+ and Psi posteriors"), std::string::npos);
  std::size_t rows = 0;
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    for (std::size_t p = 0; p < tracks[t].marginals.size(); ++p) {
      const auto figure = out / "figures" / ("quest_plus_" + std::to_string(t + 1) + "_" + std::to_string(p + 1) + ".svg");
      ASSERT_TRUE(std::filesystem::exists(figure)) << figure;
      const std::string svg = test::read_bytes(figure.string());
      // One curve: the marginal as one solid line (grids of more than one value), and the mean as
      // one dashed line; the axis names the parameter.
      const analysis::MarginalPosterior& m = tracks[t].marginals[p];
      const std::regex solid("<polyline fill=\"none\" stroke=\"" + analysis::series_colour(0) + "\" stroke-width=\"[^\"]*\" points=");
      const std::regex dashed("<polyline [^>]*stroke-dasharray");
      const auto count = [&](const std::regex& pattern) {
        return std::distance(std::sregex_iterator(svg.begin(), svg.end(), pattern), std::sregex_iterator());
      };
      EXPECT_EQ(count(solid), m.values.size() > 1 ? 1 : 0) << figure;
      EXPECT_EQ(count(dashed), 1) << figure;
      EXPECT_NE(svg.find(m.parameter), std::string::npos) << figure;
      EXPECT_NE(svg.find("marginal posterior probability"), std::string::npos) << figure;
      rows += m.values.size();
    }
    EXPECT_FALSE(std::filesystem::exists(out / "figures" /
                                         ("quest_plus_" + std::to_string(t + 1) + "_" +
                                          std::to_string(tracks[t].marginals.size() + 1) + ".svg")));
  }
  const std::string csv = test::read_bytes((out / "quest_plus_posteriors.csv").string());
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), rows + 1);  // header + grid points
  // The probabilities read back exactly (shortest round-trip text): the first row is the first
  // track's first marginal at its first grid value.
  const std::size_t second_line = csv.find("\r\n") + 2;
  const std::string first_row = csv.substr(second_line, csv.find("\r\n", second_line) - second_line);
  EXPECT_EQ(std::stod(first_row.substr(first_row.rfind(',') + 1)), tracks[0].marginals[0].probabilities[0]) << first_row;
}

// A Psi study (log10 cd/m2) whose scene is a copy in the scratch directory, so that it can be moved.
std::string psi_study(const test::ScratchDir& scratch) {
  std::filesystem::copy_file(std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/lamp_100.exr", scratch.file("lamp.exr"));
  return scratch.write("psi.toml", R"([experiment]
name = "psi"
seed = 1999

[display]
width_px = 128
height_px = 64
refresh_hz = 60.0
viewing_distance_mm = 600.0
pixel_pitch_mm = 0.25
peak_luminance_cd_m2 = 250.0

[scenes]
lamp_100 = { file = "lamp.exr" }

[procedure]
type = "psi"
intensities = { from = 2.0, to = 2.4, step = 0.02 }   # log10 cd/m2
max_trials = 12

[[conditions.rows]]
name = "lamp"
reference = "lamp_100"
comparison = "lamp_100"

[observer.simulated]
threshold_log10 = 0.1
slope = 3.5
lapse = 0.02
)");
}

TEST(QuestPlusPosterior, PsiTrackIsRebuiltInLog10Units) {
  const test::ScratchDir scratch;
  const std::string study = psi_study(scratch);
  test::dry_run_example(study, scratch.file("psi.db"), {5});
  const analysis::LoadedData data = analysis::load_databases({scratch.file("psi.db")});
  std::vector<std::string> notes;
  const std::vector<analysis::QuestPlusPosterior> tracks = rebuild_quest_plus_posteriors(data, notes);
  EXPECT_TRUE(notes.empty());
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].method, "psi");
  EXPECT_EQ(tracks[0].trials, 12);
  ASSERT_EQ(tracks[0].marginals.size(), 4u);  // threshold, slope, guess, lapse (Palamedes' defaults)
  EXPECT_EQ(analysis::parameter_axis_label(tracks[0].marginals[0]), "threshold (log10 cd/m2)");
  EXPECT_EQ(tracks[0].marginals[1].unit, "no unit");

  const Experiment experiment = load_experiment(study);
  QuestPlus reference(quest_plus_track_grid(experiment, experiment.adaptive.tracks[0]).spec);
  for (const analysis::LoadedTrial& trial : data.sessions[0].trials)
    reference.add_response(stimulus_index_of(reference, trial, {}), *trial.record.correct == 1);
  const std::vector<ParameterSummary> summary = reference.summary();
  for (std::size_t p = 0; p < summary.size(); ++p) {
    EXPECT_NEAR(tracks[0].marginals[p].mean, summary[p].mean, 1e-12);
    EXPECT_NEAR(tracks[0].marginals[p].sd, summary[p].sd, 1e-12);
    const std::vector<double> marginal = reference.marginal(p);
    for (std::size_t i = 0; i < marginal.size(); ++i) EXPECT_NEAR(tracks[0].marginals[p].probabilities[i], marginal[i], 1e-12);
  }
}

// A session whose design can no longer be built (its scene file moved) loses its posterior, with a
// note naming it and why; the rest of the report is unaffected.
TEST(QuestPlusPosterior, AMovedSceneFileLeavesANoteNotAFailure) {
  const test::ScratchDir scratch;
  test::dry_run_example(psi_study(scratch), scratch.file("psi.db"), {5});
  std::filesystem::remove(scratch.file("lamp.exr"));
  const analysis::LoadedData data = analysis::load_databases({scratch.file("psi.db")});
  std::vector<std::string> notes;
  EXPECT_TRUE(rebuild_quest_plus_posteriors(data, notes).empty());
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("session " + data.sessions[0].label + ": the QUEST+ posterior was not rebuilt"),
            std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("lamp.exr"), std::string::npos) << notes[0];
}

}  // namespace
}  // namespace glarelab
