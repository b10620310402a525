// PSE staircases (response_rule = "pse", Spencer et al. 1995, section 4): the three answers step
// the comparison, "neither" turns the track, interleaved tracks per glare strength converge on
// a simulated observer's known points of subjective equality, blocks run one after the other in
// the participant's order, the glare goes to the reference's side only, a replay restores the
// state (resume), and bad keys are refused at file:line:column.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "protocols/adaptive_procedure.h"
#include "protocols/observer.h"

namespace glarelab {
namespace {

constexpr double kPeakCdM2 = 200.0;
constexpr double kSourceFraction = 0.75;  // Spencer: the glare image's maximum at 75 % of the peak
const std::map<std::string, double> kPeaks = {{"source", kSourceFraction * kPeakCdM2},
                                              {"lamp", kSourceFraction * kPeakCdM2},
                                              {"disc", kPeakCdM2}};
const std::vector<double> kGains = {0.0, 0.5, 1.0, 2.0, 4.0, 6.0};

// An experiment file: one row per glare gain (and group), a PSE staircase per row.
std::string pse_text(const std::string& extra_procedure = "", bool blocks = false) {
  std::string text = R"([experiment]
name = "pse"
seed = 7
[display]
peak_luminance_cd_m2 = 200.0
[scenes]
disc = { generator = "disc_annulus", disc_diameter_deg = 0.5, annulus_diameter_deg = 1.5, disc_fraction_of_peak = 1.0 }
source = { generator = "light_source", disc_diameter_deg = 0.3, disc_fraction_of_peak = 0.75 }
lamp = { generator = "desk_lamp", disc_diameter_deg = 0.3, disc_fraction_of_peak = 0.75 }
[procedure]
type = "staircase"
alternatives = 3
responses = ["left", "right", "neither"]
response_rule = "pse"
glare_on = "reference"
tracks_per_condition = true
step_type = "lin"
step_sizes = [40.0, 20.0, 10.0, 5.0]
n_up = 1
n_down = 1
n_reversals = 10
n_trials = 40
min_value = 0.0
max_value = 200.0
start_intensity = 100.0
)";
  text += extra_procedure;
  const std::vector<std::string> groups = blocks ? std::vector<std::string>{"alone", "context"} : std::vector<std::string>{"alone"};
  for (const std::string& group : groups) {
    for (std::size_t g = 0; g < kGains.size(); ++g) {
      text += "[[conditions.rows]]\nname = \"" + group + "_g" + std::to_string(g) + "\"\nreference = \"" +
              (group == "alone" ? "source" : "lamp") + "\"\ncomparison = \"disc\"\nglare = \"static\"\nglare_gain = \"" +
              std::to_string(kGains[g]) + "\"\n";
    }
  }
  if (blocks) {
    text += "[[blocks]]\nname = \"without_context\"\ninstructions = \"The light alone.\"\nconditions = [";
    for (std::size_t g = 0; g < kGains.size(); ++g) text += (g ? ", " : "") + std::string("\"alone_g") + std::to_string(g) + "\"";
    text += "]\n[[blocks]]\nname = \"with_context\"\ninstructions = \"The lamp on a desk.\"\nconditions = [";
    for (std::size_t g = 0; g < kGains.size(); ++g) text += (g ? ", " : "") + std::string("\"context_g") + std::to_string(g) + "\"";
    text += "]\n";
  }
  text += "[observer.simulated]\nglare_brightening_per_gain = 0.05\nappearance_sd_log10 = 0.02\nneither_band_log10 = 0.01\n";
  return text;
}

Experiment pse_experiment(const std::string& extra = "", bool blocks = false) {
  return parse_experiment_text(pse_text(extra, blocks), "pse.toml", ".");
}

// The known PSE of a row, as a fraction of the display peak: 0.75 (1 + k g).
double known_pse_fraction(double gain) { return kSourceFraction * (1.0 + 0.05 * gain); }

TEST(PseStaircase, TracksPerConditionAreNamedAfterTheirRows) {
  const Experiment e = pse_experiment();
  ASSERT_EQ(e.adaptive.tracks.size(), kGains.size());
  EXPECT_EQ(e.adaptive.tracks[2].staircase.name, "alone_g2");
  EXPECT_EQ(e.adaptive.tracks[2].condition, "alone_g2");
  EXPECT_EQ(e.adaptive.response_rule, AdaptiveResponseRule::pse);
  // The stored configuration lists the expanded tracks and reads back to the same design.
  const Experiment again = parse_experiment_text(resolved_config_toml(e), "stored.toml", ".");
  ASSERT_EQ(again.adaptive.tracks.size(), kGains.size());
  EXPECT_EQ(again.adaptive.tracks[5].staircase.name, "alone_g5");
  EXPECT_TRUE(again.adaptive.glare_reference_only);
  EXPECT_EQ(again.adaptive.response_rule, AdaptiveResponseRule::pse);
  EXPECT_EQ(resolved_config_toml(again), resolved_config_toml(e));
}

TEST(PseStaircase, AnswersStepTheComparisonAndNeitherTurnsTheTrack) {
  const Experiment e = pse_experiment();
  AdaptiveProcedure procedure(e, kPeaks);
  // Follow one track: its trials and what each answer did to the next intensity.
  std::map<std::string, double> last;        // track -> intensity of its previous trial
  std::map<std::string, int> last_direction;  // track -> +1 up, -1 down
  int trial = 0;
  while (!procedure.finished() && trial < 300) {
    const TrialPlan plan = procedure.next_trial();
    ASSERT_TRUE(plan.appearance_judgement);
    EXPECT_TRUE(plan.correct_response.empty());
    const std::size_t cmp = static_cast<std::size_t>(plan.comparison_positions.at(0));
    // A fixed cycle of answers: comparison brighter, reference brighter, neither.
    const int kind = (trial * 5 + 1) % 3;
    const std::string answer = kind == 0 ? plan.allowed_responses[cmp] : kind == 1 ? plan.allowed_responses[1 - cmp] : "neither";
    const double shown = *plan.intensity;
    const TrialOutcome outcome = procedure.record_response(plan, {answer, 0.5});
    EXPECT_FALSE(outcome.correct.has_value()) << "PSE trials are unscored";
    std::size_t index = 0;
    while (procedure.staircase(index)->spec().name != plan.staircase) ++index;
    const Staircase& s = *procedure.staircase(index);
    if (s.finished()) break;
    const double next = s.next_intensity();
    // The direction each answer asks for: comparison brighter down, reference brighter up,
    // neither the reverse of the track's last step. A track's first "neither" is at its start,
    // 100 cd/m2, the middle of [0, 200]: not above the middle, so up.
    int expected = kind == 0 ? -1 : 1;
    if (kind == 2 && last_direction.count(plan.staircase)) expected = -last_direction[plan.staircase];
    last_direction[plan.staircase] = expected;
    const int direction = next > shown ? 1 : next < shown ? -1 : 0;
    if (direction != 0) {
      EXPECT_EQ(direction, expected) << "answer kind " << kind << " at " << shown;
    } else {
      EXPECT_TRUE(shown == 0.0 || shown == 200.0) << "a step that did not move must be clamped at 0 or 200";
    }
    ++trial;
  }
}

// Runs a whole session with the simulated observer; returns per track the mean of its last 6
// reversals as a fraction of the peak.
std::map<std::string, double> run_with_simulated_observer(const Experiment& e, std::vector<TrialPlan>* plans = nullptr,
                                                          std::vector<std::string>* answers = nullptr) {
  AdaptiveProcedure procedure(e, kPeaks);
  const auto observer = make_simulated_observer(e.simulated_observer, e.seed);
  while (!procedure.finished()) {
    const TrialPlan plan = procedure.next_trial();
    const Response response = observer->respond(plan);
    if (plans) plans->push_back(plan);
    if (answers) answers->push_back(response.value);
    procedure.record_response(plan, response);
  }
  std::map<std::string, double> pse;
  for (std::size_t t = 0; t < procedure.track_count(); ++t) {
    const Staircase& s = *procedure.staircase(t);
    pse[s.spec().name] = s.mean_of_last_reversals(6) / kPeakCdM2;
  }
  return pse;
}

TEST(PseStaircase, InterleavedTracksConvergeOnTheKnownPsePerGlareStrength) {
  const Experiment e = pse_experiment();
  std::vector<std::string> answers;
  const std::map<std::string, double> pse = run_with_simulated_observer(e, nullptr, &answers);
  ASSERT_EQ(pse.size(), kGains.size());
  for (std::size_t g = 0; g < kGains.size(); ++g) {
    // The last step is 5 cd/m2 (0.025 of the peak); the observer's noise is 0.02 log10 units
    // (about 5 % of the PSE). The mean of 6 reversals lands within 0.04 of the peak.
    EXPECT_NEAR(pse.at("alone_g" + std::to_string(g)), known_pse_fraction(kGains[g]), 0.04) << "gain " << kGains[g];
  }
  // The PSE rises with the glare strength: the highest gain's exceeds the lowest's.
  EXPECT_GT(pse.at("alone_g5"), pse.at("alone_g0") + 0.1);
  EXPECT_TRUE(std::count(answers.begin(), answers.end(), "neither") > 0) << "the observer never answered 'neither'";
}

TEST(PseStaircase, GlareGoesToTheReferenceSideWhicheverSideItIsDrawn) {
  const Experiment e = pse_experiment();
  AdaptiveProcedure procedure(e, kPeaks);
  std::set<int> comparison_sides;
  for (int i = 0; i < 30; ++i) {
    const TrialPlan plan = procedure.next_trial();
    const int cmp = plan.comparison_positions.at(0);
    comparison_sides.insert(cmp);
    ASSERT_EQ(plan.position_glare.size(), 2u);
    EXPECT_EQ(plan.position_glare[static_cast<std::size_t>(cmp)], "control");
    EXPECT_EQ(plan.position_glare[static_cast<std::size_t>(1 - cmp)], "static");
    EXPECT_EQ(plan.scenes[static_cast<std::size_t>(cmp)], "disc");
    EXPECT_EQ(plan.position_glare_gain[static_cast<std::size_t>(cmp)], 0.0);
    EXPECT_FALSE(plan.glare_keeps_peak);  // not asked for in this file
    procedure.record_response(plan, {"neither", 0.4});
  }
  EXPECT_EQ(comparison_sides.size(), 2u) << "the disc must appear on both sides";
}

// The glare gain a trial shows the reference with: the row's glare_gain, 0 when its glare is
// control (no glare to brighten it), 1 without the column.
TEST(PseStaircase, TheReferencesGlareGainFollowsItsRow) {
  std::string text = pse_text();
  const auto cut = text.find("[[conditions.rows]]");
  text = text.substr(0, cut) +
         "[[conditions.rows]]\nname = \"off\"\nreference = \"source\"\ncomparison = \"disc\"\nglare = \"control\"\n"
         "glare_gain = \"3\"\n"
         "[[conditions.rows]]\nname = \"plain\"\nreference = \"source\"\ncomparison = \"disc\"\nglare = \"static\"\n";
  const Experiment e = parse_experiment_text(text, "gain.toml", ".");
  AdaptiveProcedure procedure(e, kPeaks);
  std::map<std::string, double> gain_of;
  for (int i = 0; i < 6; ++i) {
    const TrialPlan plan = procedure.next_trial();
    const auto reference = static_cast<std::size_t>(1 - plan.comparison_positions.at(0));
    gain_of[plan.staircase] = plan.position_glare_gain.at(reference);
    EXPECT_NE(plan.condition_json.find("\"reference_glare_gain\":\"" +
                                       std::string(plan.staircase == "off" ? "0" : "1") + "\""),
              std::string::npos)
        << plan.condition_json;
    procedure.record_response(plan, {"neither", 0.5});
  }
  EXPECT_EQ(gain_of.at("off"), 0.0);
  EXPECT_EQ(gain_of.at("plain"), 1.0);
}

TEST(PseStaircase, BlocksRunInTheParticipantsOrderEachUntilItsTracksFinish) {
  for (const int participant : {1, 2}) {
    const Experiment e = pse_experiment("block_order = \"counterbalanced\"\nparticipant_number = " +
                                            std::to_string(participant) + "\n",
                                        true);
    std::vector<TrialPlan> plans;
    const std::map<std::string, double> pse = run_with_simulated_observer(e, &plans);
    ASSERT_EQ(pse.size(), 2 * kGains.size());
    const std::string first = participant == 1 ? "without_context" : "with_context";
    const std::string second = participant == 1 ? "with_context" : "without_context";
    std::size_t switch_at = 0;
    while (switch_at < plans.size() && plans[switch_at].block_name == first) ++switch_at;
    ASSERT_GT(switch_at, 0u);
    ASSERT_LT(switch_at, plans.size());
    for (std::size_t i = switch_at; i < plans.size(); ++i) {
      ASSERT_EQ(plans[i].block_name, second) << "trial " << i << ": the blocks interleave";
      EXPECT_EQ(plans[i].block, 1);
    }
    EXPECT_EQ(plans[0].block, 0);
    EXPECT_FALSE(plans[0].screen_text.empty());
    EXPECT_TRUE(plans[1].screen_text.empty());
    EXPECT_FALSE(plans[switch_at].screen_text.empty());
    EXPECT_NE(plans[0].condition_json.find("\"block_name\":\"" + first + "\""), std::string::npos);
    for (std::size_t g = 0; g < kGains.size(); ++g)
      EXPECT_NEAR(pse.at("context_g" + std::to_string(g)), known_pse_fraction(kGains[g]), 0.04);
  }
}

TEST(PseStaircase, ReplayedAnswersRestoreTheStateAsAResumeDoes) {
  const Experiment e = pse_experiment("block_order = \"counterbalanced\"\nparticipant_number = 2\n", true);
  std::vector<TrialPlan> whole;
  std::vector<std::string> answers;
  run_with_simulated_observer(e, &whole, &answers);
  for (const std::size_t cut : {std::size_t{1}, whole.size() / 3, whole.size() / 2 + 7}) {
    AdaptiveProcedure resumed(e, kPeaks);
    for (std::size_t i = 0; i < cut; ++i) resumed.record_response(resumed.next_trial(), {answers[i], 0.5});
    for (std::size_t i = cut; i < whole.size(); ++i) {
      const TrialPlan plan = resumed.next_trial();
      ASSERT_EQ(plan.condition_json, whole[i].condition_json) << "cut " << cut << " trial " << i;
      ASSERT_EQ(plan.intensity, whole[i].intensity);
      ASSERT_EQ(plan.screen_text, whole[i].screen_text);
      resumed.record_response(plan, {answers[i], 0.5});
    }
    EXPECT_TRUE(resumed.finished());
  }
}

std::string pse_error(const std::string& from, const std::string& to, bool blocks = false) {
  std::string text = pse_text("", blocks);
  const auto at = text.find(from);
  if (at == std::string::npos) return "test error: '" + from + "' not in the file";
  text.replace(at, from.size(), to);
  try {
    parse_experiment_text(text, "pse.toml", ".");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(PseStaircase, BadKeysAreRefusedAtFileLineColumnAndKey) {
  // [procedure] starts on line 10; response_rule is on 14, n_down on 20.
  std::string e = pse_error("n_down = 1", "n_down = 2");
  EXPECT_NE(e.find("pse.toml:20:10: key 'procedure.n_down'"), std::string::npos) << e;
  EXPECT_NE(e.find("1-up/1-down"), std::string::npos) << e;
  e = pse_error("min_value = 0.0\n", "");
  EXPECT_NE(e.find("procedure.min_value"), std::string::npos) << e;
  e = pse_error("response_rule = \"pse\"", "response_rule = \"equal\"");
  EXPECT_NE(e.find("pse.toml:14:17: key 'procedure.response_rule'"), std::string::npos) << e;
  e = pse_error("glare_on = \"reference\"", "glare_on = \"disc\"");
  EXPECT_NE(e.find("pse.toml:15:12: key 'procedure.glare_on'"), std::string::npos) << e;
  e = pse_error("glare_on = \"reference\"", "glare_on = \"frame\"\nglare_keeps_peak = true");
  EXPECT_NE(e.find("pse.toml:16:20: key 'procedure.glare_keeps_peak'"), std::string::npos) << e;
  EXPECT_NE(e.find("needs glare_on = \"reference\""), std::string::npos) << e;
  e = pse_error("tracks_per_condition = true", "tracks_per_condition = 1");
  EXPECT_NE(e.find("pse.toml:16:24: key 'procedure.tracks_per_condition'"), std::string::npos) << e;
  e = pse_error("start_intensity = 100.0", "start_intensity = 300.0");
  EXPECT_NE(e.find("procedure.start_intensity"), std::string::npos) << e;
  e = pse_error("neither_band_log10 = 0.01", "neither_band_log10 = -0.01");
  EXPECT_NE(e.find("observer.simulated.neither_band_log10"), std::string::npos) << e;
  e = pse_error("glare_brightening_per_gain", "glare_brightening");
  EXPECT_NE(e.find("unknown key 'glare_brightening'"), std::string::npos) << e;
  // A track's row in no block would never run.
  e = pse_error(", \"context_g5\"]", "]", true);
  EXPECT_NE(e.find("context_g5"), std::string::npos) << e;
  EXPECT_NE(e.find("no block lists"), std::string::npos) << e;
  e = pse_error("instructions = \"The lamp on a desk.\"", "repetitions = 2", true);
  EXPECT_NE(e.find("blocks.repetitions"), std::string::npos) << e;
}

}  // namespace
}  // namespace glarelab
