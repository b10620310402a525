#include "protocols/blocked_design.h"

#include <stdexcept>

namespace glarelab {

std::vector<std::size_t> block_rows(const Experiment& experiment, const BlockSpec& block) {
  std::vector<std::size_t> rows;
  if (block.conditions.empty()) {
    for (std::size_t row = 0; row < experiment.conditions.size(); ++row) rows.push_back(row);
    return rows;
  }
  for (const std::string& name : block.conditions) {
    std::size_t row = 0;
    while (row < experiment.conditions.size() && experiment.conditions[row].name() != name) ++row;
    if (row == experiment.conditions.size())
      throw std::invalid_argument("block '" + block.name + "': no condition row named '" + name + "'");
    rows.push_back(row);
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
