#include "protocols/blocked_design.h"

#include <stdexcept>
#include <unordered_map>

namespace glarelab {

std::vector<std::size_t> block_rows(const Experiment& experiment, const BlockSpec& block) {
  std::vector<std::size_t> rows;
  if (block.conditions.empty()) {
    for (std::size_t row = 0; row < experiment.conditions.size(); ++row) rows.push_back(row);
    return rows;
  }
  // Each name's first row, found once for the block: a block listing every row of a large table
  // costs a pass, not a pass per name.
  std::unordered_map<std::string, std::size_t> first_row;
  for (std::size_t row = experiment.conditions.size(); row-- > 0;) first_row[experiment.conditions[row].name()] = row;
  for (const std::string& name : block.conditions) {
    const auto found = first_row.find(name);
    if (found == first_row.end())
      throw std::invalid_argument("block '" + block.name + "': no condition row named '" + name + "'");
    rows.push_back(found->second);
  }
  return rows;
}

void apply_block_placement(const BlockPlacement& placement, bool row_has_question, TrialPlan& plan) {
  plan.block = placement.block;
  plan.block_name = placement.block_name;
  plan.screen_text = placement.screen_text;
  if (placement.question && !row_has_question) plan.question = *placement.question;
}

}  // namespace glarelab
