#pragma once
// Blocks of trials and their order across participants ([[blocks]] and the block keys of
// [procedure]; docs/EXPERIMENT_FILES.md, "Blocks").
//
// A block is a named subset of the condition rows with its own repetitions, an optional
// instruction screen before its first trial and an optional question. The order of the blocks
// depends on the participant number: fixed (as listed), random (seeded per participant),
// counterbalanced (all n! permutations cycled by participant number) or latin_square (balanced
// Williams design: n orders for even n, 2n for odd n, each block equally often in each position
// and each block immediately followed by every other equally often).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"

namespace glarelab {

enum class TrialOrder { random, as_listed };
enum class BlockOrder { fixed, random, counterbalanced, latin_square };

std::string to_string(TrialOrder order);
std::string to_string(BlockOrder order);

struct BlockSpec {
  std::string name;
  std::vector<std::string> conditions;              // condition row names; empty: every row
  std::vector<SourceLocation> condition_where;      // where each name was written
  std::optional<int> repetitions;                   // empty: the procedure's repetitions
  std::string instructions;                         // screen before the block's first trial
  std::optional<std::string> question;              // replaces the procedure's question
  TrialOrder trial_order = TrialOrder::random;
  SourceLocation where;
};

struct DesignSpec {
  std::vector<BlockSpec> blocks;  // empty: no blocks, the procedure's single shuffled list
  BlockOrder block_order = BlockOrder::fixed;
  SourceLocation block_order_where;
  // Picks the block order and seeds the orders within blocks. Set for a session from
  // --participant-number (or from the sessions already in the database); empty: 1.
  std::optional<int> participant_number;
  SourceLocation participant_number_where;
};

// Largest number of blocks a counterbalanced order accepts: 20! still fits 64 bits.
constexpr int kMaxCounterbalancedBlocks = 20;

// Permutation number k (0-based, lexicographic order) of 0..n-1 (factorial number system).
std::vector<int> nth_permutation(int n, std::uint64_t k);
// Row `row` of the balanced Latin square (Williams 1949) of n treatments: for even n, the n rows
// (j-th entry of row r: (a_j + r) mod n with a = 0, 1, n-1, 2, n-2, ...); for odd n, those rows
// followed by their reverses (2n rows). `row` is taken modulo the number of rows.
std::vector<int> williams_row(int n, std::uint64_t row);

// The order (indices into design.blocks) in which a participant runs the blocks. Random orders
// are shuffled with a seed drawn from (seed, RandomStream::block_order, participant number).
std::vector<int> block_sequence(const DesignSpec& design, std::uint64_t seed);

// The seed of the trial order within block `block_index` (its position in the file) for the
// design's participant: a Philox draw of (seed, RandomStream::block_trial_order, participant,
// block), so every participant gets their own order and each block is reproducible alone.
std::uint64_t block_trial_seed(const DesignSpec& design, std::uint64_t seed, int block_index);

int participant_number_of(const DesignSpec& design);

}  // namespace glarelab
