#include "protocols/pair_design.h"

#include <algorithm>

namespace glarelab {
namespace {

std::string join_quoted(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "'" : ", '") + item + "'";
  return text;
}

struct Instruction {
  std::string name;
  std::string question;
  bool scored = true;
  std::string instructions;
};

std::vector<std::string> read_glare_modes(TableReader& procedure) {
  const auto modes = procedure.distinct_names("glare_modes", "glare mode");
  if (!modes) procedure.fail("glare_modes", "missing required key for design = \"all_pairs\" (e.g. [\"dynamic\", \"static\", \"control\"])");
  std::vector<std::string> names;
  for (const ArrayString& mode : *modes) names.push_back(mode.value);
  if (names.size() < 2) procedure.fail("glare_modes", "at least two glare modes are needed to form pairs");
  return names;
}

std::vector<Instruction> read_instructions(TableReader& procedure) {
  const toml::array* array = procedure.array("instructions");
  if (array == nullptr)
    procedure.fail("instructions", "missing required key for design = \"all_pairs\" (e.g. [{ name = \"brighter\", "
                                   "question = \"Which image is brighter?\" }])");
  std::vector<Instruction> instructions;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    const std::string key = procedure.key_path("instructions") + "[" + std::to_string(i) + "]";
    if (!element.is_table())
      throw ConfigError(to_location(element.source(), procedure.file()), key,
                        "expected a table such as { name = \"brighter\", question = \"Which image is brighter?\" }, "
                        "found " + describe_toml_type(element));
    TableReader reader(*element.as_table(), key, procedure.file());
    Instruction instruction;
    const std::optional<std::string> name = reader.string("name");
    if (!name || name->empty()) reader.fail("name", "each instruction needs a non-empty name");
    for (const Instruction& other : instructions)
      if (other.name == *name) reader.fail("name", "duplicate instruction '" + *name + "'");
    instruction.name = *name;
    const std::optional<std::string> question = reader.string("question");
    if (!question || question->empty()) reader.fail("question", "each instruction needs its question (shown with every trial)");
    instruction.question = *question;
    instruction.scored = reader.boolean("scored").value_or(true);
    instruction.instructions = reader.string("instructions").value_or("");
    reader.report_unused();
    instructions.push_back(std::move(instruction));
  }
  if (instructions.empty()) procedure.fail("instructions", "at least one instruction is required");
  return instructions;
}

// mode_scenes: each design scene (a key) maps every glare mode to the [scenes] image showing it.
std::vector<std::pair<std::string, std::vector<std::string>>> read_mode_scenes(TableReader& procedure,
                                                                              const Experiment& experiment,
                                                                              const std::vector<std::string>& modes) {
  const toml::table* table = procedure.table("mode_scenes");
  TableReader scenes(*table, procedure.key_path("mode_scenes"), procedure.file());
  scenes.consume_all();  // the keys are the experimenter's scene names
  if (table->empty()) scenes.fail("", "at least one scene is required");
  // toml++ keeps keys sorted; generate in the order the experimenter wrote them.
  std::vector<const toml::key*> keys;
  for (const auto& entry : *table) keys.push_back(&entry.first);
  std::sort(keys.begin(), keys.end(),
            [](const toml::key* a, const toml::key* b) { return a->source().begin < b->source().begin; });
  std::vector<std::string> known;
  for (const auto& entry : experiment.scenes) known.push_back(entry.first);
  std::vector<std::pair<std::string, std::vector<std::string>>> result;
  for (const toml::key* key : keys) {
    const std::string scene(key->str());
    const toml::node& node = *table->get(scene);
    if (!node.is_table())
      scenes.fail(scene, "expected a table naming the image of each glare mode, found " + describe_toml_type(node));
    TableReader reader(*node.as_table(), scenes.key_path(scene), procedure.file());
    std::vector<std::string> images;
    for (const std::string& mode : modes) {
      const std::optional<std::string> image = reader.string(mode);
      if (!image) reader.fail(mode, "missing the image of glare mode '" + mode + "' for scene '" + scene + "'");
      if (experiment.scenes.count(*image) == 0)
        reader.fail(mode, "unknown scene '" + *image + "' (scenes in [scenes]: " + join_quoted(known) + ")");
      images.push_back(*image);
    }
    reader.report_unused();
    result.emplace_back(scene, std::move(images));
  }
  return result;
}

// glare_scenes: each listed [scenes] image is its own design scene, shown under every glare mode
// by the glare engine, so the modes must be the engine's: dynamic, static, control.
std::vector<std::pair<std::string, std::vector<std::string>>> read_glare_scenes(TableReader& procedure,
                                                                               const Experiment& experiment,
                                                                               const std::vector<std::string>& modes) {
  for (const std::string& mode : modes)
    if (mode != "dynamic" && mode != "static" && mode != "control")
      procedure.fail("glare_modes", "glare_scenes renders the glare engine's modes ('dynamic', 'static', 'control'); '" +
                                        mode + "' is not one (use mode_scenes to show an image for it)");
  std::vector<std::string> known;
  for (const auto& entry : experiment.scenes) known.push_back(entry.first);
  const auto scenes = procedure.distinct_names("glare_scenes", "scene", [&](const ArrayString& scene) {
    if (experiment.scenes.count(scene.value) == 0)
      throw ConfigError(scene.where, scene.key,
                        "unknown scene '" + scene.value + "' (scenes in [scenes]: " + join_quoted(known) + ")");
  });
  std::vector<std::pair<std::string, std::vector<std::string>>> result;
  for (const ArrayString& scene : *scenes) result.emplace_back(scene.value, std::vector<std::string>(modes.size(), scene.value));
  if (result.empty()) procedure.fail("glare_scenes", "at least one scene is required");
  return result;
}

}  // namespace

std::optional<GeneratedDesign> read_pair_design(TableReader& procedure, const Experiment& experiment) {
  const std::optional<std::string> design = procedure.string("design");
  if (!design || *design == "rows") return std::nullopt;
  if (*design != "all_pairs")
    procedure.fail("design", "unsupported design '" + *design + "' (supported: 'rows', 'all_pairs')");
  GeneratedDesign generated;
  generated.where = procedure.value_location("design");
  const std::vector<std::string> modes = read_glare_modes(procedure);
  const std::vector<Instruction> instructions = read_instructions(procedure);
  // Either the glare engine renders each mode (glare_scenes: one [scenes] image per design scene,
  // a glare mode per side) or pre-rendered images stand for the modes (mode_scenes).
  const bool rendered = procedure.node("glare_scenes") != nullptr;
  if (rendered && procedure.node("mode_scenes") != nullptr)
    procedure.fail("mode_scenes", "give either glare_scenes (the glare engine renders each mode) or mode_scenes "
                                  "(an image for each mode), not both");
  if (!rendered && procedure.node("mode_scenes") == nullptr)
    procedure.fail("glare_scenes", "missing required key for design = \"all_pairs\": the scenes to show under each "
                                   "glare mode, e.g. glare_scenes = [\"park\"] (rendered by the glare engine), or "
                                   "[procedure.mode_scenes] park = { dynamic = \"park_dynamic\", ... } (an image per mode)");
  const auto mode_scenes =
      rendered ? read_glare_scenes(procedure, experiment, modes) : read_mode_scenes(procedure, experiment, modes);

  for (const Instruction& instruction : instructions) {
    BlockSpec block;
    block.name = instruction.name;
    block.instructions = instruction.instructions;
    block.where = generated.where;
    for (const auto& [scene, images] : mode_scenes) {
      for (std::size_t a = 0; a < modes.size(); ++a) {
        for (std::size_t b = a + 1; b < modes.size(); ++b) {
          ConditionRow row;
          row.where = generated.where;
          row.number = static_cast<int>(generated.rows.size() + 1);
          const std::string name = scene + "_" + modes[a] + "_vs_" + modes[b] + "_" + instruction.name;
          row.fields = {{"name", name},
                        {"scene", scene},
                        {"instruction", instruction.name},
                        {"condition_a", modes[a]},
                        {"condition_b", modes[b]},
                        {"scene_a", images[a]},
                        {"scene_b", images[b]}};
          if (rendered) row.fields.insert(row.fields.end(), {{"glare_a", modes[a]}, {"glare_b", modes[b]}});
          row.fields.insert(row.fields.end(), {{"question", instruction.question},
                                               {"scored", instruction.scored ? "true" : "false"}});
          block.conditions.push_back(name);
          block.condition_where.push_back(generated.where);
          generated.rows.push_back(std::move(row));
        }
      }
    }
    generated.blocks.push_back(std::move(block));
  }
  return generated;
}

}  // namespace glarelab
