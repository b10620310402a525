#include "protocols/block_config.h"

#include <algorithm>
#include <limits>

#include "core/number_text.h"

namespace glarelab {
namespace {

const std::vector<std::string> kBlockProcedures = {"forced_choice", "rating", "adjustment", "staircase", "quest"};

// Staircase and QUEST blocks (protocols/adaptive_procedure.h): a block runs the tracks of its rows
// interleaved until they finish. A track whose row is in no block would never run, and one whose
// row is in two would have to be two tracks; repetitions have no meaning for a track that ends
// when it converges.
void check_adaptive_blocks(const Experiment& experiment) {
  const DesignSpec& design = experiment.design;
  for (const BlockSpec& block : design.blocks)
    if (block.repetitions)
      throw ConfigError(block.where, "blocks.repetitions",
                        "block '" + block.name + "': a " + experiment.procedure +
                            " block runs its tracks until they finish; repetitions apply to fixed designs");
  for (const AdaptiveTrackSpec& track : experiment.adaptive.tracks) {
    const std::string row = track.condition.empty() ? experiment.conditions.front().name() : track.condition;
    std::vector<std::string> holders;
    for (const BlockSpec& block : design.blocks)
      if (block.conditions.empty() || std::find(block.conditions.begin(), block.conditions.end(), row) != block.conditions.end())
        holders.push_back(block.name);
    const std::string name = experiment.procedure == "quest" ? track.quest.name : track.staircase.name;
    if (holders.empty())
      throw ConfigError(track.where, "condition",
                        "track '" + name + "' shows condition '" + row + "', which no block lists: it would never run");
    if (holders.size() > 1)
      throw ConfigError(track.where, "condition",
                        "track '" + name + "' shows condition '" + row + "', which blocks '" + holders[0] + "' and '" +
                            holders[1] + "' both list: a track runs in one block");
  }
}

}  // namespace

void read_block_keys(TableReader& procedure, Experiment& experiment) {
  DesignSpec& design = experiment.design;
  if (const std::optional<std::string> order = procedure.string("block_order")) {
    design.block_order_where = procedure.value_location("block_order");
    if (*order == "fixed") design.block_order = BlockOrder::fixed;
    else if (*order == "random") design.block_order = BlockOrder::random;
    else if (*order == "counterbalanced") design.block_order = BlockOrder::counterbalanced;
    else if (*order == "latin_square") design.block_order = BlockOrder::latin_square;
    else
      procedure.fail("block_order", "unsupported block order '" + *order +
                                        "' (supported: 'fixed', 'random', 'counterbalanced', 'latin_square')");
  }
  if (const std::optional<std::int64_t> number = procedure.integer("participant_number")) {
    if (*number < 1 || *number > std::numeric_limits<int>::max())
      procedure.fail("participant_number", "must be >= 1, found " + number_text(*number));
    design.participant_number = static_cast<int>(*number);
    design.participant_number_where = procedure.value_location("participant_number");
  }
}

void read_blocks_section(TableReader& top, Experiment& experiment) {
  const toml::array* blocks = top.array("blocks");
  if (blocks == nullptr) return;
  if (blocks->empty()) top.fail("blocks", "at least one [[blocks]] entry is required when the key is given");
  for (std::size_t i = 0; i < blocks->size(); ++i) {
    const toml::node& element = *blocks->get(i);
    const std::string key = "blocks[" + std::to_string(i) + "]";
    if (!element.is_table())
      throw ConfigError(to_location(element.source(), top.file()), key,
                        "expected a table with a name and the block's conditions, found " + describe_toml_type(element));
    TableReader reader(*element.as_table(), key, top.file());
    BlockSpec block;
    block.where = reader.table_location();
    const std::optional<std::string> name = reader.string("name");
    if (!name || name->empty()) reader.fail("name", "each block needs a non-empty name");
    for (const BlockSpec& other : experiment.design.blocks)
      if (other.name == *name) reader.fail("name", "duplicate block name '" + *name + "'");
    block.name = *name;
    if (const toml::node* conditions = reader.node("conditions")) {
      if (const auto* all = conditions->as_string()) {
        if (all->get() != "all")
          reader.fail("conditions", "expected \"all\" or an array of condition names, found the string '" +
                                        all->get() + "'");
      } else if (const auto* names = conditions->as_array()) {
        if (names->empty()) reader.fail("conditions", "a block needs at least one condition (or \"all\")");
        for (std::size_t c = 0; c < names->size(); ++c) {
          const toml::node& entry = *names->get(c);
          const std::string entry_key = reader.key_path("conditions") + "[" + std::to_string(c) + "]";
          block.conditions.push_back(expect_string(entry, entry_key, top.file()));
          block.condition_where.push_back(to_location(entry.source(), top.file()));
        }
      } else {
        reader.fail("conditions", "expected \"all\" or an array of condition names, found " +
                                      describe_toml_type(*conditions));
      }
    }
    if (reader.node("repetitions") != nullptr) block.repetitions = reader.repetitions("repetitions", 1);
    block.instructions = reader.string("instructions").value_or("");
    block.question = reader.string("question");
    if (const std::optional<std::string> order = reader.string("trial_order")) {
      if (*order == "random") block.trial_order = TrialOrder::random;
      else if (*order == "as_listed") block.trial_order = TrialOrder::as_listed;
      else reader.fail("trial_order", "unsupported trial order '" + *order + "' (supported: 'random', 'as_listed')");
    }
    reader.report_unused();
    experiment.design.blocks.push_back(std::move(block));
  }
}

void check_blocks(const Experiment& experiment) {
  const DesignSpec& design = experiment.design;
  if (design.blocks.empty()) {
    // An order for blocks that do not exist would silently do nothing: most likely a mistake.
    if (design.block_order != BlockOrder::fixed)
      throw ConfigError(design.block_order_where, "procedure.block_order", "block_order needs [[blocks]]");
    if (design.participant_number)
      throw ConfigError(design.participant_number_where, "procedure.participant_number",
                        "participant_number picks the order of [[blocks]]; this experiment has none "
                        "(give the participant number to `glarelab run --participant-number`)");
    return;
  }
  if (std::find(kBlockProcedures.begin(), kBlockProcedures.end(), experiment.procedure) == kBlockProcedures.end()) {
    // QUEST+ tracks choose among several rows themselves: a block could not split them.
    throw ConfigError(design.blocks.front().where, "blocks",
                      "[[blocks]] apply to forced_choice, rating, adjustment, staircase and quest; a " +
                          experiment.procedure + " interleaves its tracks with [[procedure.staircases]] instead");
  }
  if (design.block_order == BlockOrder::counterbalanced &&
      design.blocks.size() > static_cast<std::size_t>(kMaxCounterbalancedBlocks))
    throw ConfigError(design.block_order_where, "procedure.block_order",
                      "counterbalanced order of " + std::to_string(design.blocks.size()) +
                          " blocks: at most " + std::to_string(kMaxCounterbalancedBlocks) +
                          " (use latin_square for more)");
  for (const BlockSpec& block : design.blocks) {
    for (std::size_t c = 0; c < block.conditions.size(); ++c) {
      const std::string& name = block.conditions[c];
      const bool found = std::any_of(experiment.conditions.begin(), experiment.conditions.end(),
                                     [&](const ConditionRow& row) { return row.name() == name; });
      if (!found)
        throw ConfigError(block.condition_where[c], "blocks.conditions",
                          "block '" + block.name + "': no condition row named '" + name + "'");
      for (std::size_t d = 0; d < c; ++d)
        if (block.conditions[d] == name)
          throw ConfigError(block.condition_where[c], "blocks.conditions",
                            "block '" + block.name + "' names condition '" + name + "' twice (use repetitions)");
    }
  }
  if (experiment.procedure == "staircase" || experiment.procedure == "quest") check_adaptive_blocks(experiment);
}

void insert_block_keys(const DesignSpec& design, toml::table& procedure) {
  if (design.blocks.empty()) return;
  procedure.insert("block_order", to_string(design.block_order));
  procedure.insert("participant_number", participant_number_of(design));
}

toml::array blocks_toml(const DesignSpec& design) {
  toml::array blocks;
  for (const BlockSpec& block : design.blocks) {
    toml::table table{{"name", block.name}, {"instructions", block.instructions},
                      {"trial_order", to_string(block.trial_order)}};
    if (block.conditions.empty()) {
      table.insert("conditions", "all");
    } else {
      toml::array names;
      for (const std::string& name : block.conditions) names.push_back(name);
      table.insert("conditions", std::move(names));
    }
    if (block.repetitions) table.insert("repetitions", *block.repetitions);
    if (block.question) table.insert("question", *block.question);
    blocks.push_back(std::move(table));
  }
  return blocks;
}

}  // namespace glarelab
