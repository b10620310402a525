// design = "all_pairs" (Ritschel et al. 2009, 6.1): the generated rows equal the hand-written
// condition table the example used before, and the trial counts and side balance are the ones
// computed by hand from the design.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "protocols/forced_choice.h"

namespace glarelab {
namespace {

const std::string kExamples = std::string(GLARELAB_SOURCE_DIR) + "/examples/";

// Peaks of the example's stand-in images: lamp_N peaks at N cd/m2.
const std::map<std::string, double> kPeaks = {{"lamp_100", 100.0}, {"lamp_105", 105.0}, {"lamp_115", 115.0},
                                              {"lamp_130", 130.0}, {"lamp_160", 160.0}, {"lamp_200", 200.0}};

// The condition table examples/ritschel_2afc.toml used before the generator, written by hand.
const char* const kHandWrittenTable =
    "lamp_dim_dynamic_vs_static_brighter,lamp_dim,brighter,dynamic,static,lamp_115,lamp_105,Which image is brighter?,true\n"
    "lamp_dim_dynamic_vs_static_attractive,lamp_dim,attractive,dynamic,static,lamp_115,lamp_105,Which image is more attractive?,false\n"
    "lamp_dim_dynamic_vs_static_realistic,lamp_dim,realistic,dynamic,static,lamp_115,lamp_105,Which image looks more realistic?,false\n"
    "lamp_dim_dynamic_vs_control_brighter,lamp_dim,brighter,dynamic,control,lamp_115,lamp_100,Which image is brighter?,true\n"
    "lamp_dim_dynamic_vs_control_attractive,lamp_dim,attractive,dynamic,control,lamp_115,lamp_100,Which image is more attractive?,false\n"
    "lamp_dim_dynamic_vs_control_realistic,lamp_dim,realistic,dynamic,control,lamp_115,lamp_100,Which image looks more realistic?,false\n"
    "lamp_dim_static_vs_control_brighter,lamp_dim,brighter,static,control,lamp_105,lamp_100,Which image is brighter?,true\n"
    "lamp_dim_static_vs_control_attractive,lamp_dim,attractive,static,control,lamp_105,lamp_100,Which image is more attractive?,false\n"
    "lamp_dim_static_vs_control_realistic,lamp_dim,realistic,static,control,lamp_105,lamp_100,Which image looks more realistic?,false\n"
    "lamp_bright_dynamic_vs_static_brighter,lamp_bright,brighter,dynamic,static,lamp_200,lamp_160,Which image is brighter?,true\n"
    "lamp_bright_dynamic_vs_static_attractive,lamp_bright,attractive,dynamic,static,lamp_200,lamp_160,Which image is more attractive?,false\n"
    "lamp_bright_dynamic_vs_static_realistic,lamp_bright,realistic,dynamic,static,lamp_200,lamp_160,Which image looks more realistic?,false\n"
    "lamp_bright_dynamic_vs_control_brighter,lamp_bright,brighter,dynamic,control,lamp_200,lamp_130,Which image is brighter?,true\n"
    "lamp_bright_dynamic_vs_control_attractive,lamp_bright,attractive,dynamic,control,lamp_200,lamp_130,Which image is more attractive?,false\n"
    "lamp_bright_dynamic_vs_control_realistic,lamp_bright,realistic,dynamic,control,lamp_200,lamp_130,Which image looks more realistic?,false\n"
    "lamp_bright_static_vs_control_brighter,lamp_bright,brighter,static,control,lamp_160,lamp_130,Which image is brighter?,true\n"
    "lamp_bright_static_vs_control_attractive,lamp_bright,attractive,static,control,lamp_160,lamp_130,Which image is more attractive?,false\n"
    "lamp_bright_static_vs_control_realistic,lamp_bright,realistic,static,control,lamp_160,lamp_130,Which image looks more realistic?,false\n";

std::string row_text(const ConditionRow& row) {
  std::string text;
  for (const char* column : {"name", "scene", "instruction", "condition_a", "condition_b", "scene_a", "scene_b",
                             "question", "scored"}) {
    const std::string* value = row.find(column);
    text += (text.empty() ? "" : ",") + (value != nullptr ? *value : std::string("<missing>"));
  }
  return text;
}

// The study with pre-rendered stand-in images per mode ([procedure.mode_scenes]), as the example
// was before the glare engine rendered a mode per side.
Experiment stand_in_study() {
  const std::string text = R"(
[experiment]
name = "ritschel-stand-ins"
[scenes]
lamp_100 = { file = "scenes/lamp_100.exr" }
lamp_105 = { file = "scenes/lamp_105.exr" }
lamp_115 = { file = "scenes/lamp_115.exr" }
lamp_130 = { file = "scenes/lamp_130.exr" }
lamp_160 = { file = "scenes/lamp_160.exr" }
lamp_200 = { file = "scenes/lamp_200.exr" }
[procedure]
type = "forced_choice"
counterbalance_sides = true
design = "all_pairs"
glare_modes = ["dynamic", "static", "control"]
block_order = "random"
instructions = [
  { name = "brighter", question = "Which image is brighter?", instructions = "In the next trials: which image is brighter?" },
  { name = "attractive", question = "Which image is more attractive?", scored = false, instructions = "Next: attractive" },
  { name = "realistic", question = "Which image looks more realistic?", scored = false, instructions = "Next: realistic" },
]
[procedure.mode_scenes]
lamp_dim = { dynamic = "lamp_115", static = "lamp_105", control = "lamp_100" }
lamp_bright = { dynamic = "lamp_200", static = "lamp_160", control = "lamp_130" }
)";
  return parse_experiment_text(text, "stand_ins.toml", kExamples);
}

TEST(PairDesign, GeneratesTheHandWrittenRitschelTable) {
  const Experiment e = stand_in_study();
  std::set<std::string> generated, expected;
  for (const ConditionRow& row : e.conditions) generated.insert(row_text(row));
  std::istringstream lines(kHandWrittenTable);
  for (std::string line; std::getline(lines, line);) expected.insert(line);
  EXPECT_EQ(e.conditions.size(), 18u);
  EXPECT_EQ(generated, expected);
  // One block per instruction, each with its six rows (2 scenes x 3 pairs).
  ASSERT_EQ(e.design.blocks.size(), 3u);
  EXPECT_EQ(e.design.block_order, BlockOrder::random);
  for (const BlockSpec& block : e.design.blocks) {
    EXPECT_EQ(block.conditions.size(), 6u) << block.name;
    for (const std::string& name : block.conditions) EXPECT_NE(name.find("_" + block.name), std::string::npos);
    EXPECT_FALSE(block.instructions.empty());
  }
}

struct Counts {
  std::map<std::string, int> left, right;                                   // per condition
  std::map<std::tuple<std::string, std::string, std::string>, int> shown;  // (instruction, left, right)
};

Counts count_sides(const std::vector<TrialPlan>& trials) {
  Counts counts;
  for (const TrialPlan& plan : trials) {
    const std::string& left = plan.position_conditions.at(0);
    const std::string& right = plan.position_conditions.at(1);
    ++counts.left[left];
    ++counts.right[right];
    ++counts.shown[{plan.block_name, left, right}];
  }
  return counts;
}

// The example renders each mode with the glare engine (glare_scenes): every row shows one scene on
// both sides, with glare_a / glare_b the modes of condition_a / condition_b.
TEST(PairDesign, GlareScenesShowOneSceneUnderAModePerSide) {
  const Experiment e = load_experiment(kExamples + "ritschel_2afc.toml");
  ASSERT_EQ(e.conditions.size(), 18u);
  for (const ConditionRow& row : e.conditions) {
    EXPECT_EQ(*row.find("scene_a"), *row.find("scene"));
    EXPECT_EQ(*row.find("scene_b"), *row.find("scene"));
    EXPECT_EQ(*row.find("glare_a"), *row.find("condition_a"));
    EXPECT_EQ(*row.find("glare_b"), *row.find("condition_b"));
  }
  for (const TrialPlan& plan : build_forced_choice_trials(e, kPeaks)) {
    EXPECT_EQ(plan.position_glare, plan.position_conditions);  // the mode follows its side when swapped
    EXPECT_TRUE(plan.correct_response.empty());  // equal luminance: no answer is physically right
  }
}

TEST(PairDesign, RitschelCountsAndSideBalance) {
  const Experiment e = stand_in_study();
  const std::vector<TrialPlan> trials = build_forced_choice_trials(e, kPeaks);
  // 2 scenes x 3 pairs (dynamic-static, dynamic-control, static-control) x 3 instructions x 2 sides.
  ASSERT_EQ(trials.size(), 36u);
  // Each mode is in 2 of the 3 pairs, shown 1x left and 1x right per pair: 2 left and 2 right per
  // scene and instruction, so 2 x 2 x 3 = 12 on each side over the session.
  const Counts counts = count_sides(trials);
  for (const std::string mode : {"dynamic", "static", "control"}) {
    EXPECT_EQ(counts.left.at(mode), 12) << mode;
    EXPECT_EQ(counts.right.at(mode), 12) << mode;
  }
  // Every ordered pair of different modes, in every instruction block, exactly twice (once per scene).
  EXPECT_EQ(counts.shown.size(), 3u * 6u);
  for (const auto& [key, n] : counts.shown) EXPECT_EQ(n, 2) << std::get<0>(key) << " " << std::get<1>(key);
  // Blocks are contiguous runs of 12 trials, each instruction's question on its trials, the
  // instruction screen on the first trial of each block only.
  std::set<std::string> blocks;
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const TrialPlan& plan = trials[i];
    EXPECT_EQ(plan.block, static_cast<int>(i / 12));
    if (i % 12 != 0) {
      EXPECT_EQ(plan.block_name, trials[i - 1].block_name);
    }
    EXPECT_EQ(plan.screen_text.empty(), i % 12 != 0) << i;
    EXPECT_NE(plan.question.find(plan.block_name), std::string::npos) << plan.question;
    // Only the brightness question has a right answer.
    EXPECT_EQ(plan.correct_response.empty(), plan.block_name != "brighter");
    blocks.insert(plan.block_name);
  }
  EXPECT_EQ(blocks.size(), 3u);
}

TEST(PairDesign, FourModesAndThreeScenesBalanceToo) {
  const std::string text = R"(
[experiment]
name = "pairs"
[scenes]
s1 = { file = "/s1.exr" }
s2 = { file = "/s2.exr" }
[procedure]
type = "forced_choice"
repetitions = 2
design = "all_pairs"
glare_modes = ["m1", "m2", "m3", "m4"]
instructions = [{ name = "which", question = "Which?" }]
[procedure.mode_scenes]
x = { m1 = "s1", m2 = "s2", m3 = "s1", m4 = "s2" }
y = { m1 = "s1", m2 = "s1", m3 = "s2", m4 = "s2" }
z = { m1 = "s2", m2 = "s1", m3 = "s1", m4 = "s2" }
)";
  const Experiment e = parse_experiment_text(text, "p.toml", "/");
  // 3 scenes x C(4, 2) = 6 pairs.
  EXPECT_EQ(e.conditions.size(), 18u);
  const std::vector<TrialPlan> trials = build_forced_choice_trials(e, {{"s1", 1.0}, {"s2", 2.0}});
  // x 2 repetitions x 2 sides.
  ASSERT_EQ(trials.size(), 72u);
  // Each mode is in 3 pairs: per scene and repetition 3 left and 3 right; x 3 scenes x 2 repetitions.
  const Counts counts = count_sides(trials);
  for (const std::string mode : {"m1", "m2", "m3", "m4"}) {
    EXPECT_EQ(counts.left.at(mode), 18) << mode;
    EXPECT_EQ(counts.right.at(mode), 18) << mode;
  }
  for (const auto& [key, n] : counts.shown) EXPECT_EQ(n, 6);  // 3 scenes x 2 repetitions
  EXPECT_EQ(counts.shown.size(), 12u);                        // ordered pairs of 4 modes
}

TEST(PairDesign, SeededOrdersAreReproducibleAndDifferByParticipant) {
  Experiment e = load_experiment(kExamples + "ritschel_2afc.toml");
  std::set<std::vector<std::string>> block_orders;
  for (int participant = 1; participant <= 12; ++participant) {
    e.design.participant_number = participant;
    const std::vector<TrialPlan> first = build_forced_choice_trials(e, kPeaks);
    const std::vector<TrialPlan> again = build_forced_choice_trials(e, kPeaks);
    ASSERT_EQ(first.size(), again.size());
    std::vector<std::string> order;
    for (std::size_t i = 0; i < first.size(); ++i) {
      EXPECT_EQ(first[i].condition_json, again[i].condition_json);
      if (i % 12 == 0) order.push_back(first[i].block_name);
    }
    block_orders.insert(order);
  }
  // 12 participants drawing from the 6 orders of three blocks (fixed by the seed): several differ.
  EXPECT_GE(block_orders.size(), 3u);
}

TEST(PairDesign, ErrorsNameTheKey) {
  const std::string base = R"(
[experiment]
name = "pairs"
[scenes]
s1 = { file = "/s1.exr" }
[procedure]
type = "forced_choice"
design = "all_pairs"
glare_modes = ["a", "b"]
instructions = [{ name = "which", question = "Which?" }]
)";
  auto error = [](const std::string& text) -> std::string {
    try {
      parse_experiment_text(text, "p.toml", "/");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(error(base).find("mode_scenes"), std::string::npos) << error(base);
  EXPECT_NE(error(base + "[procedure.mode_scenes]\nx = { a = \"s1\" }\n").find("missing the image of glare mode 'b'"),
            std::string::npos);
  EXPECT_NE(error(base + "[procedure.mode_scenes]\nx = { a = \"s1\", b = \"s9\" }\n").find("p.toml:12:"),
            std::string::npos)
      << error(base + "[procedure.mode_scenes]\nx = { a = \"s1\", b = \"s9\" }\n");
  const std::string complete = base + "[procedure.mode_scenes]\nx = { a = \"s1\", b = \"s1\" }\n";
  EXPECT_EQ(error(complete), "no error");
  EXPECT_NE(error(complete + "[[conditions.rows]]\nscene_a = \"s1\"\nscene_b = \"s1\"\n").find("generates the condition rows"),
            std::string::npos);
  EXPECT_NE(error(complete + "[[blocks]]\nname = \"b\"\n").find("generates the blocks"), std::string::npos);
  std::string sides = complete;
  sides.replace(sides.find("design ="), 0, "counterbalance_sides = false\n");
  EXPECT_NE(error(sides).find("counterbalance_sides"), std::string::npos) << error(sides);
  std::string unknown = complete;
  unknown.replace(unknown.find("all_pairs"), 9, "latin");
  EXPECT_NE(error(unknown).find("unsupported design 'latin'"), std::string::npos);
  std::string one_mode = complete;
  one_mode.replace(one_mode.find("[\"a\", \"b\"]"), 10, "[\"a\"]");
  EXPECT_NE(error(one_mode).find("at least two glare modes"), std::string::npos) << error(one_mode);
  // glare_scenes: the engine's modes only, known scenes, not together with mode_scenes.
  const std::string rendered = base + "glare_scenes = [\"s1\"]\n";
  EXPECT_NE(error(rendered).find("'a' is not one"), std::string::npos) << error(rendered);
  std::string engine_modes = rendered;
  engine_modes.replace(engine_modes.find("[\"a\", \"b\"]"), 10, "[\"static\", \"control\"]");
  EXPECT_EQ(error(engine_modes), "no error");
  std::string unknown_scene = engine_modes;
  unknown_scene.replace(unknown_scene.find("[\"s1\"]"), 6, "[\"s9\"]");
  EXPECT_NE(error(unknown_scene).find("p.toml:11:"), std::string::npos) << error(unknown_scene);
  EXPECT_NE(error(unknown_scene).find("unknown scene 's9'"), std::string::npos) << error(unknown_scene);
  EXPECT_NE(error(engine_modes + "[procedure.mode_scenes]\nx = { static = \"s1\", control = \"s1\" }\n").find("not both"),
            std::string::npos);
}

// Hand-written rows with a glare mode per side: both columns, known modes, forced choice only.
TEST(PairDesign, GlareColumnsPerSideAreChecked) {
  const std::string head = R"(
[experiment]
name = "sides"
[scenes]
s1 = { file = "/s1.exr" }
[procedure]
type = "forced_choice"
[conditions]
rows = [
)";
  auto error = [&](const std::string& row) -> std::string {
    try {
      parse_experiment_text(head + row + "\n]\n", "g.toml", "/");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error(R"({ name = "r", scene_a = "s1", scene_b = "s1", glare_a = "dynamic", glare_b = "control" })"), "no error");
  EXPECT_NE(error(R"({ name = "r", scene_a = "s1", scene_b = "s1", glare_a = "dynamic" })").find("glare_b"), std::string::npos);
  EXPECT_NE(error(R"({ name = "r", scene_a = "s1", scene_b = "s1", glare_a = "dynamic", glare_b = "blurry" })")
                .find("unknown glare mode 'blurry'"),
            std::string::npos);
  const std::string both =
      error(R"({ name = "r", scene_a = "s1", scene_b = "s1", glare = "static", glare_a = "dynamic", glare_b = "static" })");
  EXPECT_NE(both.find("contradicts"), std::string::npos) << both;
}

}  // namespace
}  // namespace glarelab
