// Block orders across participants (protocols/block_design.h): permutations in lexicographic
// order, balanced Latin squares (Williams 1949) checked by their defining properties, and seeded
// random orders that are reproducible per participant.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "protocols/block_design.h"

namespace glarelab {
namespace {

using Order = std::vector<int>;

DesignSpec blocks_design(int n, BlockOrder order, int participant) {
  DesignSpec design;
  for (int i = 0; i < n; ++i) {
    BlockSpec block;
    block.name = "b" + std::to_string(i);
    design.blocks.push_back(block);
  }
  design.block_order = order;
  design.participant_number = participant;
  return design;
}

TEST(BlockOrder, PermutationsInLexicographicOrder) {
  // The six orders of three blocks, written out by hand.
  const std::vector<Order> expected = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (std::uint64_t k = 0; k < 6; ++k) EXPECT_EQ(nth_permutation(3, k), expected[k]) << k;
  EXPECT_EQ(nth_permutation(3, 6), expected[0]) << "cycles after n!";
  EXPECT_EQ(nth_permutation(4, 23), (Order{3, 2, 1, 0}));
  EXPECT_EQ(nth_permutation(1, 5), (Order{0}));
  EXPECT_THROW(nth_permutation(21, 0), std::invalid_argument);
}

TEST(BlockOrder, CounterbalancedCyclesThroughEveryOrderByParticipant) {
  std::set<Order> seen;
  for (int participant = 1; participant <= 24; ++participant)
    seen.insert(block_sequence(blocks_design(4, BlockOrder::counterbalanced, participant), 1));
  EXPECT_EQ(seen.size(), 24u);  // 4! orders, each once
  EXPECT_EQ(block_sequence(blocks_design(4, BlockOrder::counterbalanced, 25), 1),
            block_sequence(blocks_design(4, BlockOrder::counterbalanced, 1), 1));
  EXPECT_EQ(block_sequence(blocks_design(3, BlockOrder::counterbalanced, 2), 1), (Order{0, 2, 1}));
}

TEST(BlockOrder, WilliamsSquaresWrittenOutByHand) {
  // n = 4: first row 0 1 3 2, then cyclic shifts.
  EXPECT_EQ(williams_row(4, 0), (Order{0, 1, 3, 2}));
  EXPECT_EQ(williams_row(4, 1), (Order{1, 2, 0, 3}));
  EXPECT_EQ(williams_row(4, 2), (Order{2, 3, 1, 0}));
  EXPECT_EQ(williams_row(4, 3), (Order{3, 0, 2, 1}));
  EXPECT_EQ(williams_row(4, 4), (Order{0, 1, 3, 2}));
  // n = 3: the three shifts of 0 2 1 ... are not balanced alone; with their reverses they are.
  EXPECT_EQ(williams_row(3, 0), (Order{0, 1, 2}));
  EXPECT_EQ(williams_row(3, 1), (Order{1, 2, 0}));
  EXPECT_EQ(williams_row(3, 2), (Order{2, 0, 1}));
  EXPECT_EQ(williams_row(3, 3), (Order{2, 1, 0}));
  EXPECT_EQ(williams_row(3, 4), (Order{0, 2, 1}));
  EXPECT_EQ(williams_row(3, 5), (Order{1, 0, 2}));
}

// The defining properties, counted over all rows: every block in every position equally often,
// and every ordered pair of different blocks adjacent equally often (once for even n, twice for
// odd n, whose square has 2n rows).
TEST(BlockOrder, WilliamsSquaresAreBalancedForCarryOver) {
  for (int n = 1; n <= 10; ++n) {
    const int rows = n % 2 == 0 ? n : 2 * n;
    std::map<std::pair<int, int>, int> position_count, neighbour_count;
    for (int participant = 1; participant <= rows; ++participant) {
      const Order order = block_sequence(blocks_design(n, BlockOrder::latin_square, participant), 1);
      Order sorted = order;
      std::sort(sorted.begin(), sorted.end());
      for (int i = 0; i < n; ++i) ASSERT_EQ(sorted[static_cast<std::size_t>(i)], i) << "not a permutation, n = " << n;
      for (int p = 0; p < n; ++p) ++position_count[{order[static_cast<std::size_t>(p)], p}];
      for (int p = 0; p + 1 < n; ++p) ++neighbour_count[{order[static_cast<std::size_t>(p)], order[static_cast<std::size_t>(p + 1)]}];
    }
    for (int block = 0; block < n; ++block)
      for (int p = 0; p < n; ++p) EXPECT_EQ((position_count[{block, p}]), rows / n) << "n = " << n;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        if (a != b) {
          EXPECT_EQ((neighbour_count[{a, b}]), n % 2 == 0 ? 1 : 2) << "n = " << n << ": " << a << " -> " << b;
        }
  }
}

TEST(BlockOrder, RandomOrderIsSeededPerParticipant) {
  std::set<Order> seen;
  for (int participant = 1; participant <= 30; ++participant) {
    const Order order = block_sequence(blocks_design(4, BlockOrder::random, participant), 77);
    EXPECT_EQ(order, block_sequence(blocks_design(4, BlockOrder::random, participant), 77)) << "reproducible";
    Order sorted = order;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, (Order{0, 1, 2, 3}));
    seen.insert(order);
  }
  // 30 draws from 24 orders: the chance of fewer than 10 distinct ones is negligible, and the
  // draws are fixed by the seed, so this cannot flake.
  EXPECT_GE(seen.size(), 10u);
  EXPECT_EQ(block_sequence(blocks_design(3, BlockOrder::fixed, 5), 77), (Order{0, 1, 2}));
}

TEST(BlockOrder, TrialSeedsDifferBetweenParticipantsAndBlocks) {
  const DesignSpec first = blocks_design(2, BlockOrder::fixed, 1);
  const DesignSpec second = blocks_design(2, BlockOrder::fixed, 2);
  EXPECT_EQ(block_trial_seed(first, 5, 0), block_trial_seed(first, 5, 0));
  EXPECT_NE(block_trial_seed(first, 5, 0), block_trial_seed(first, 5, 1));
  EXPECT_NE(block_trial_seed(first, 5, 0), block_trial_seed(second, 5, 0));
  EXPECT_NE(block_trial_seed(first, 5, 0), block_trial_seed(first, 6, 0));
  // Without a participant number the design is participant 1's.
  DesignSpec unset = first;
  unset.participant_number.reset();
  EXPECT_EQ(block_trial_seed(unset, 5, 1), block_trial_seed(first, 5, 1));
}

}  // namespace
}  // namespace glarelab
