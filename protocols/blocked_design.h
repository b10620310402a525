#pragma once
// The trial order of a fixed design (forced choice, ratings, adjustment) with or without blocks.
// A procedure describes its design as units (forced choice: a condition row shown one way round;
// ratings: a row on one category; adjustment: a row) made for a set of rows and a number of
// repetitions; this file orders them:
// - without [[blocks]]: every row, the procedure's repetitions, one list shuffled with
//   (seed, RandomStream::trial_order) -- exactly the order these procedures always had;
// - with [[blocks]]: block after block in the participant's block order (protocols/block_design.h),
//   each block's units for its own rows and repetitions, shuffled with the block's own seed
//   (block_trial_seed) or kept as listed.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/trial_plan.h"
#include "core/random.h"

namespace glarelab {

// Where a unit runs: the block's position in the session's order and what the block shows.
struct BlockPlacement {
  int block = 0;
  std::string block_name;
  std::string screen_text;              // the block's instructions, on its first trial only
  std::optional<std::string> question;  // the block's question, when it has one
};

// The units in the order the session runs them, each with the index of its placement: a block's
// placement is held twice (its first unit's, with the instructions, and the rest's), not once per
// unit, so a design of millions of units stays a few bytes each.
template <typename Unit>
struct OrderedUnit {
  Unit unit;
  std::uint32_t placement = 0;  // index into OrderedDesign::placements
};

template <typename Unit>
struct OrderedDesign {
  std::vector<OrderedUnit<Unit>> units;
  std::vector<BlockPlacement> placements;

  std::size_t size() const { return units.size(); }
  const Unit& unit(std::size_t index) const { return units[index].unit; }
  const BlockPlacement& placement(std::size_t index) const { return placements[units[index].placement]; }
};

// Indices of the condition rows a block uses, in the order the block lists them (all rows in
// table order when it lists none).
std::vector<std::size_t> block_rows(const Experiment& experiment, const BlockSpec& block);

// Copies block, block_name and screen_text into the plan; the block's question replaces the
// plan's unless `row_has_question` (a forced-choice row's own "question" column wins).
void apply_block_placement(const BlockPlacement& placement, bool row_has_question, TrialPlan& plan);

// make_units(const std::vector<std::size_t>& rows, int repetitions) -> std::vector<Unit>.
template <typename Unit, typename MakeUnits>
OrderedDesign<Unit> order_fixed_design(const Experiment& experiment, int repetitions, MakeUnits make_units) {
  OrderedDesign<Unit> ordered;
  const DesignSpec& design = experiment.design;
  if (design.blocks.empty()) {
    std::vector<std::size_t> rows;
    for (std::size_t row = 0; row < experiment.conditions.size(); ++row) rows.push_back(row);
    std::vector<Unit> units = make_units(rows, repetitions);
    shuffle_in_place(units, CounterRandom(experiment.seed, RandomStream::trial_order), 0);
    ordered.placements.push_back(BlockPlacement{});
    ordered.units.reserve(units.size());
    for (Unit& unit : units) ordered.units.push_back({std::move(unit), 0});
    return ordered;
  }
  int position = 0;
  for (const int index : block_sequence(design, experiment.seed)) {
    const BlockSpec& block = design.blocks[static_cast<std::size_t>(index)];
    std::vector<Unit> units = make_units(block_rows(experiment, block), block.repetitions.value_or(repetitions));
    if (block.trial_order == TrialOrder::random)
      shuffle_in_place(units, CounterRandom(block_trial_seed(design, experiment.seed, index), RandomStream::block_trial_order),
                       0);
    const auto first = static_cast<std::uint32_t>(ordered.placements.size());
    ordered.placements.push_back(BlockPlacement{position, block.name, block.instructions, block.question});
    ordered.placements.push_back(BlockPlacement{position, block.name, std::string(), block.question});
    for (std::size_t i = 0; i < units.size(); ++i) ordered.units.push_back({std::move(units[i]), i == 0 ? first : first + 1});
    ++position;
  }
  return ordered;
}

}  // namespace glarelab
