// [[blocks]]: which rows each block runs, how often, in what order, what the plan carries (block,
// block_name, screen_text, question), the block order across participants, config errors, and
// that experiments without blocks keep their order.
#include <gtest/gtest.h>

#include <map>

#include "protocols/adjustment_procedure.h"
#include "protocols/forced_choice.h"
#include "protocols/rating_procedure.h"
#include "core/random.h"

namespace glarelab {
namespace {

const std::map<std::string, double> kPeaks = {{"a", 100.0}, {"b", 200.0}, {"c", 50.0}};

// Lines 1-16 are fixed; `procedure_extra` is on line 9, `blocks` starts on line 17.
std::string blocked_text(const std::string& procedure_extra, const std::string& blocks) {
  return "[experiment]\n"                                             // 1
         "name = \"blocks\"\n"                                        // 2
         "seed = 11\n"                                                // 3
         "[scenes]\n"                                                 // 4
         "a = { file = \"/a.exr\" }\n"                                // 5
         "b = { file = \"/b.exr\" }\n"                                // 6
         "c = { file = \"/c.exr\" }\n"                                // 7
         "[procedure]\n"                                              // 8
         "type = \"forced_choice\"\n" + procedure_extra + "\n"        // 9, 10
         "[conditions]\n"                                             // 11
         "rows = [\n"                                                 // 12
         "  { name = \"ab\", scene_a = \"a\", scene_b = \"b\" },\n"   // 13
         "  { name = \"bc\", scene_a = \"b\", scene_b = \"c\" },\n"   // 14
         "  { name = \"ca\", scene_a = \"c\", scene_b = \"a\" },\n"   // 15
         "]\n"                                                        // 16
         + blocks;
}

const std::string kTwoBlocks =
    "[[blocks]]\n"
    "name = \"first\"\n"
    "conditions = [\"bc\", \"ab\"]\n"
    "trial_order = \"as_listed\"\n"
    "instructions = \"Part one\"\n"
    "question = \"Which is brighter, part one?\"\n"
    "[[blocks]]\n"
    "name = \"second\"\n"
    "conditions = \"all\"\n"
    "repetitions = 2\n";

std::string condition_of(const TrialPlan& plan) { return plan.condition_name; }

ConfigError error_of(const std::string& text) {
  try {
    parse_experiment_text(text, "b.toml", "/");
  } catch (const ConfigError& error) {
    return error;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return ConfigError({}, "", "");
}

TEST(ProcedureBlocks, BlocksRunTheirRowsInTheirOrderWithInstructionsOnTheFirstTrial) {
  const Experiment e = parse_experiment_text(blocked_text("", kTwoBlocks), "b.toml", "/");
  ASSERT_EQ(e.design.blocks.size(), 2u);
  const std::vector<TrialPlan> trials = build_forced_choice_trials(e, kPeaks);
  // first: 2 rows x 1 repetition x 2 sides; second: 3 rows x 2 repetitions x 2 sides.
  ASSERT_EQ(trials.size(), 4u + 12u);
  // As listed: bc, bc swapped, ab, ab swapped.
  const std::vector<std::vector<std::string>> listed = {{"b", "c"}, {"c", "b"}, {"a", "b"}, {"b", "a"}};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(trials[i].trial_index, static_cast<int>(i));
    EXPECT_EQ(trials[i].block, 0);
    EXPECT_EQ(trials[i].block_name, "first");
    EXPECT_EQ(trials[i].scenes, listed[i]) << i;
    EXPECT_EQ(trials[i].question, "Which is brighter, part one?");
    EXPECT_EQ(trials[i].screen_text, i == 0 ? "Part one" : "");
  }
  std::map<std::string, int> second_rows;
  for (std::size_t i = 4; i < trials.size(); ++i) {
    EXPECT_EQ(trials[i].trial_index, static_cast<int>(i));
    EXPECT_EQ(trials[i].block, 1);
    EXPECT_EQ(trials[i].block_name, "second");
    EXPECT_EQ(trials[i].question, ForcedChoiceSpec{}.question);
    EXPECT_EQ(trials[i].screen_text, "");  // the block has no instructions
    ++second_rows[condition_of(trials[i])];
  }
  EXPECT_EQ(second_rows, (std::map<std::string, int>{{"ab", 4}, {"bc", 4}, {"ca", 4}}));
}

TEST(ProcedureBlocks, RandomTrialOrderWithinABlockIsTheBlockSeedsShuffle) {
  const Experiment e = parse_experiment_text(blocked_text("", kTwoBlocks), "b.toml", "/");
  const std::vector<TrialPlan> trials = build_forced_choice_trials(e, kPeaks);
  // Second block (index 1 in the file): units row x repetition x side in table order, shuffled
  // with its own seed -- computed here from the documented recipe.
  std::vector<std::pair<std::string, bool>> units;
  for (const std::string row : {"ab", "bc", "ca"})
    for (int repetition = 0; repetition < 2; ++repetition) {
      units.emplace_back(row, false);
      units.emplace_back(row, true);
    }
  shuffle_in_place(units, CounterRandom(block_trial_seed(e.design, e.seed, 1), RandomStream::block_trial_order), 0);
  for (std::size_t i = 0; i < units.size(); ++i) {
    const TrialPlan& plan = trials[4 + i];
    EXPECT_EQ(plan.condition_name, units[i].first) << i;
    const std::string& scene_a = plan.condition_name == "ab" ? "a" : plan.condition_name == "bc" ? "b" : "c";
    EXPECT_EQ(plan.scenes[0] != scene_a, units[i].second) << i;
  }
}

TEST(ProcedureBlocks, LatinSquareOrderFollowsTheParticipantNumber) {
  const std::string four_blocks =
      "[[blocks]]\nname = \"p\"\nconditions = [\"ab\"]\n"
      "[[blocks]]\nname = \"q\"\nconditions = [\"bc\"]\n"
      "[[blocks]]\nname = \"r\"\nconditions = [\"ca\"]\n"
      "[[blocks]]\nname = \"s\"\nconditions = [\"ab\", \"ca\"]\n";
  // Williams square for n = 4 (rows 0 1 3 2, 1 2 0 3, 2 3 1 0, 3 0 2 1), by participant 1..4, then again.
  const std::vector<std::vector<std::string>> expected = {
      {"p", "q", "s", "r"}, {"q", "r", "p", "s"}, {"r", "s", "q", "p"}, {"s", "p", "r", "q"}, {"p", "q", "s", "r"}};
  for (int participant = 1; participant <= 5; ++participant) {
    const std::string text = blocked_text("block_order = \"latin_square\"\nparticipant_number = " +
                                              std::to_string(participant),
                                          four_blocks);
    const Experiment e = parse_experiment_text(text, "b.toml", "/");
    std::vector<std::string> order;
    for (const TrialPlan& plan : build_forced_choice_trials(e, kPeaks))
      if (order.empty() || order.back() != plan.block_name) order.push_back(plan.block_name);
    EXPECT_EQ(order, expected[static_cast<std::size_t>(participant - 1)]) << "participant " << participant;
  }
}

TEST(ProcedureBlocks, ExperimentsWithoutBlocksKeepTheirSingleShuffledList) {
  const Experiment e = parse_experiment_text(blocked_text("repetitions = 2", ""), "b.toml", "/");
  ASSERT_TRUE(e.design.blocks.empty());
  // The order every forced-choice session has had: rows x repetitions x sides, one Fisher-Yates
  // shuffle with (seed, trial_order) from index 0.
  std::vector<std::pair<std::size_t, bool>> units;
  for (std::size_t row = 0; row < 3; ++row)
    for (int repetition = 0; repetition < 2; ++repetition) {
      units.emplace_back(row, false);
      units.emplace_back(row, true);
    }
  shuffle_in_place(units, CounterRandom(e.seed, RandomStream::trial_order), 0);
  const std::vector<TrialPlan> trials = build_forced_choice_trials(e, kPeaks);
  ASSERT_EQ(trials.size(), units.size());
  for (std::size_t i = 0; i < units.size(); ++i) {
    EXPECT_EQ(trials[i].condition_name, e.conditions[units[i].first].name());
    EXPECT_EQ(trials[i].block, 0);
    EXPECT_EQ(trials[i].block_name, "");
    EXPECT_EQ(trials[i].screen_text, "");
  }
  // Nor does the stored configuration mention blocks.
  const std::string resolved = resolved_config_toml(e);
  EXPECT_EQ(resolved.find("block_order"), std::string::npos) << resolved;
  EXPECT_EQ(resolved.find("[[blocks]]"), std::string::npos) << resolved;
  EXPECT_EQ(resolved.find("participant_number"), std::string::npos) << resolved;
}

TEST(ProcedureBlocks, ResolvedConfigurationKeepsBlocksOrderAndParticipant) {
  Experiment e = parse_experiment_text(blocked_text("block_order = \"counterbalanced\"", kTwoBlocks), "b.toml", "/");
  e.design.participant_number = 2;
  const std::string resolved = resolved_config_toml(e);
  const Experiment again = parse_experiment_text(resolved, "<resolved>", "/");
  EXPECT_EQ(resolved_config_toml(again), resolved);
  EXPECT_EQ(again.design.participant_number, 2);
  EXPECT_EQ(again.design.block_order, BlockOrder::counterbalanced);
  ASSERT_EQ(again.design.blocks.size(), 2u);
  EXPECT_EQ(again.design.blocks[0].conditions, (std::vector<std::string>{"bc", "ab"}));
  EXPECT_EQ(again.design.blocks[0].trial_order, TrialOrder::as_listed);
  EXPECT_EQ(again.design.blocks[1].repetitions, 2);
  // Same trials from the stored configuration (what resume rebuilds).
  const auto original = build_forced_choice_trials(e, kPeaks);
  const auto replayed = build_forced_choice_trials(again, kPeaks);
  ASSERT_EQ(original.size(), replayed.size());
  for (std::size_t i = 0; i < original.size(); ++i) {
    EXPECT_EQ(original[i].condition_json, replayed[i].condition_json);
    EXPECT_EQ(original[i].block_name, replayed[i].block_name);
  }
  // Participant 2 of two counterbalanced blocks runs them the other way round.
  EXPECT_EQ(original.front().block_name, "second");
}

TEST(ProcedureBlocks, RatingAndAdjustmentTakeBlocks) {
  const std::string rating =
      "[experiment]\nname = \"r\"\n[scenes]\na = { file = \"/a.exr\" }\nb = { file = \"/b.exr\" }\n"
      "[procedure]\ntype = \"rating\"\ncategories = [\"glare\", \"overall\"]\nblock_order = \"fixed\"\n"
      "[[conditions.rows]]\nname = \"one\"\nscene = \"a\"\n[[conditions.rows]]\nname = \"two\"\nscene = \"b\"\n"
      "[[blocks]]\nname = \"only two\"\nconditions = [\"two\"]\nrepetitions = 3\ninstructions = \"Rate\"\n";
  const Experiment r = parse_experiment_text(rating, "r.toml", "/");
  const std::vector<TrialPlan> rated = build_rating_trials(r);
  ASSERT_EQ(rated.size(), 6u);  // 1 row x 2 categories x 3 repetitions
  for (const TrialPlan& plan : rated) {
    EXPECT_EQ(plan.condition_name, "two");
    EXPECT_EQ(plan.block_name, "only two");
  }
  EXPECT_EQ(rated[0].screen_text, "Rate");

  const std::string adjustment =
      "[experiment]\nname = \"a\"\n[scenes]\na = { file = \"/a.exr\" }\nb = { file = \"/b.exr\" }\n"
      "[procedure]\ntype = \"adjustment\"\nrepetitions = 2\n"
      "[[conditions.rows]]\nname = \"low\"\ntarget = \"a\"\ncomparison = \"a\"\n"
      "[[conditions.rows]]\nname = \"high\"\ntarget = \"b\"\ncomparison = \"a\"\n"
      "[[blocks]]\nname = \"high first\"\nconditions = [\"high\"]\n"
      "[[blocks]]\nname = \"then low\"\nconditions = [\"low\"]\nrepetitions = 1\n";
  const Experiment a = parse_experiment_text(adjustment, "a.toml", "/");
  const std::vector<TrialPlan> adjusted = build_adjustment_trials(a, kPeaks);
  ASSERT_EQ(adjusted.size(), 3u);  // high x 2 (the procedure's repetitions), low x 1
  EXPECT_EQ(adjusted[0].condition_name, "high");
  EXPECT_EQ(adjusted[1].condition_name, "high");
  EXPECT_EQ(adjusted[2].condition_name, "low");
  EXPECT_EQ(adjusted[2].block, 1);
}

TEST(ProcedureBlocks, ConfigErrorsNameTheLineAndKey) {
  // An unknown condition name, at the array element.
  ConfigError e = error_of(blocked_text("", "[[blocks]]\nname = \"x\"\nconditions = [\"ab\", \"zz\"]\n"));
  EXPECT_EQ(e.where().line, 19);
  EXPECT_NE(std::string(e.what()).find("no condition row named 'zz'"), std::string::npos) << e.what();
  e = error_of(blocked_text("", "[[blocks]]\nname = \"x\"\n[[blocks]]\nname = \"x\"\n"));
  EXPECT_EQ(e.where().line, 20);
  EXPECT_NE(std::string(e.what()).find("duplicate block name 'x'"), std::string::npos) << e.what();
  e = error_of(blocked_text("", "[[blocks]]\nname = \"x\"\nconditions = \"some\"\n"));
  EXPECT_EQ(e.where().line, 19);
  e = error_of(blocked_text("", "[[blocks]]\nname = \"x\"\ntrial_order = \"shuffled\"\n"));
  EXPECT_NE(std::string(e.what()).find("'random', 'as_listed'"), std::string::npos) << e.what();
  e = error_of(blocked_text("", "[[blocks]]\nname = \"x\"\nrepeats = 2\n"));
  EXPECT_NE(std::string(e.what()).find("unknown key 'repeats'"), std::string::npos) << e.what();
  e = error_of(blocked_text("block_order = \"random\"", ""));
  EXPECT_EQ(e.where().line, 10);
  EXPECT_NE(std::string(e.what()).find("block_order needs [[blocks]]"), std::string::npos) << e.what();
  e = error_of(blocked_text("block_order = \"shuffled\"", kTwoBlocks));
  EXPECT_EQ(e.where().line, 10);
  e = error_of(blocked_text("participant_number = 0", kTwoBlocks));
  EXPECT_EQ(e.where().line, 10);
  e = error_of(blocked_text("participant_number = 3", ""));
  EXPECT_NE(std::string(e.what()).find("--participant-number"), std::string::npos) << e.what();
}

// QUEST+ and Psi tracks choose among their rows themselves: blocks could not split them.
// (Staircase and QUEST blocks: tests/pse_staircase_test.cpp.)
TEST(ProcedureBlocks, QuestPlusRefusesBlocks) {
  const std::string psi =
      "[experiment]\nname = \"s\"\n[scenes]\na = { file = \"/a.exr\" }\n[procedure]\ntype = \"psi\"\n"
      "intensities = { from = 0.0, to = 2.0, step = 0.5 }\n"
      "[[conditions.rows]]\nname = \"lamp\"\nreference = \"a\"\ncomparison = \"a\"\n"
      "[[blocks]]\nname = \"context\"\n";
  const ConfigError e = error_of(psi);
  EXPECT_EQ(e.where().line, 12);
  EXPECT_NE(std::string(e.what()).find("[[blocks]] apply to forced_choice, rating, adjustment, staircase and quest"),
            std::string::npos)
      << e.what();
}

}  // namespace
}  // namespace glarelab
