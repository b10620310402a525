#include "protocols/block_design.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "core/random.h"

namespace glarelab {
namespace {

// A 64-bit seed drawn from (seed, stream, index, sub_index): independent orders for every
// participant (and block) without any state.
std::uint64_t derived_seed(std::uint64_t seed, RandomStream stream, std::uint64_t index, std::uint32_t sub_index) {
  const auto words = CounterRandom(seed, stream).bits(index, sub_index);
  return (static_cast<std::uint64_t>(words[0]) << 32) | words[1];
}

std::uint64_t participant_index(const DesignSpec& design) {
  return static_cast<std::uint64_t>(participant_number_of(design) - 1);
}

}  // namespace

std::string to_string(TrialOrder order) { return order == TrialOrder::random ? "random" : "as_listed"; }

std::string to_string(BlockOrder order) {
  switch (order) {
    case BlockOrder::fixed: return "fixed";
    case BlockOrder::random: return "random";
    case BlockOrder::counterbalanced: return "counterbalanced";
    case BlockOrder::latin_square: return "latin_square";
  }
  return "fixed";
}

int participant_number_of(const DesignSpec& design) { return design.participant_number.value_or(1); }

std::vector<int> nth_permutation(int n, std::uint64_t k) {
  if (n < 0 || n > kMaxCounterbalancedBlocks)
    throw std::invalid_argument("counterbalanced order: " + std::to_string(n) + " blocks (at most " +
                                std::to_string(kMaxCounterbalancedBlocks) + ")");
  std::vector<std::uint64_t> factorial(static_cast<std::size_t>(n) + 1, 1);
  for (int i = 1; i <= n; ++i) factorial[static_cast<std::size_t>(i)] = factorial[static_cast<std::size_t>(i - 1)] * static_cast<std::uint64_t>(i);
  k %= factorial[static_cast<std::size_t>(n)];
  std::vector<int> remaining(static_cast<std::size_t>(n));
  std::iota(remaining.begin(), remaining.end(), 0);
  std::vector<int> permutation;
  // Digit i of k in the factorial number system picks among the n - i items still unused.
  for (int i = n; i >= 1; --i) {
    const std::uint64_t digit = k / factorial[static_cast<std::size_t>(i - 1)];
    k %= factorial[static_cast<std::size_t>(i - 1)];
    permutation.push_back(remaining[static_cast<std::size_t>(digit)]);
    remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(digit));
  }
  return permutation;
}

std::vector<int> williams_row(int n, std::uint64_t row) {
  if (n < 1) throw std::invalid_argument("latin square: needs at least one block");
  const std::uint64_t rows = n % 2 == 0 ? static_cast<std::uint64_t>(n) : 2 * static_cast<std::uint64_t>(n);
  row %= rows;
  const bool mirrored = row >= static_cast<std::uint64_t>(n);
  const int shift = static_cast<int>(mirrored ? row - static_cast<std::uint64_t>(n) : row);
  std::vector<int> order;
  // First row 0, 1, n-1, 2, n-2, ...: the successive differences run through every non-zero
  // residue once, so in the n cyclic shifts every ordered pair of neighbours occurs exactly once
  // (even n). For odd n that fails; adding the reversed rows makes every pair occur twice.
  for (int j = 0; j < n; ++j) {
    const int a = j == 0 ? 0 : (j % 2 == 1 ? (j + 1) / 2 : n - j / 2);
    order.push_back((a + shift) % n);
  }
  if (mirrored) std::reverse(order.begin(), order.end());
  return order;
}

std::vector<int> block_sequence(const DesignSpec& design, std::uint64_t seed) {
  const int n = static_cast<int>(design.blocks.size());
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  switch (design.block_order) {
    case BlockOrder::fixed: return order;
    case BlockOrder::random:
      shuffle_in_place(order, CounterRandom(derived_seed(seed, RandomStream::block_order, participant_index(design), 0),
                                            RandomStream::block_order),
                       0);
      return order;
    case BlockOrder::counterbalanced: return nth_permutation(n, participant_index(design));
    case BlockOrder::latin_square: return williams_row(n, participant_index(design));
  }
  return order;
}

std::uint64_t block_trial_seed(const DesignSpec& design, std::uint64_t seed, int block_index) {
  return derived_seed(seed, RandomStream::block_trial_order, participant_index(design),
                      static_cast<std::uint32_t>(block_index));
}

}  // namespace glarelab
