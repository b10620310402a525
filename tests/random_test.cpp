#include <gtest/gtest.h>

#include "core/random.h"

namespace glarelab {
namespace {

TEST(CounterRandom, SameInputsGiveSameDraws) {
  CounterRandom a(42, RandomStream::observer);
  CounterRandom b(42, RandomStream::observer);
  EXPECT_EQ(a.uniform(17), b.uniform(17));
  EXPECT_NE(a.uniform(17), a.uniform(18));
  CounterRandom other_stream(42, RandomStream::trial_order);
  EXPECT_NE(a.uniform(17), other_stream.uniform(17));
}

}  // namespace
}  // namespace glarelab

#include <Random123/philox.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace glarelab {
namespace {

// Known-answer test from Random123's kat_vectors: philox4x32_10 with counter and key all zero.
// CounterRandom puts its stream into counter word 2, so the raw generator is checked here and
// CounterRandom is checked against it below.
TEST(CounterRandom, Philox4x32KnownAnswer) {
  r123::Philox4x32 generator;
  const r123::Philox4x32::ctr_type counter = {{0, 0, 0, 0}};
  const r123::Philox4x32::key_type key = {{0, 0}};
  const auto out = generator(counter, key);
  EXPECT_EQ(out[0], 0x6627e8d5u);
  EXPECT_EQ(out[1], 0xe169c58du);
  EXPECT_EQ(out[2], 0xbc57ac4cu);
  EXPECT_EQ(out[3], 0x9b00dbd8u);
}

// Second vector of the same file: counter all ones, key all ones.
TEST(CounterRandom, Philox4x32KnownAnswerAllOnes) {
  r123::Philox4x32 generator;
  const r123::Philox4x32::ctr_type counter = {{0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu}};
  const r123::Philox4x32::key_type key = {{0xffffffffu, 0xffffffffu}};
  const auto out = generator(counter, key);
  EXPECT_EQ(out[0], 0x408f276du);
  EXPECT_EQ(out[1], 0x41c83b0eu);
  EXPECT_EQ(out[2], 0xa20bc7c6u);
  EXPECT_EQ(out[3], 0x6d5451fdu);
}

// Third vector: distinct words (digits of pi), which catches a swapped word order.
TEST(CounterRandom, Philox4x32KnownAnswerPiDigits) {
  r123::Philox4x32 generator;
  const r123::Philox4x32::ctr_type counter = {{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u}};
  const r123::Philox4x32::key_type key = {{0xa4093822u, 0x299f31d0u}};
  const auto out = generator(counter, key);
  EXPECT_EQ(out[0], 0xd16cfe09u);
  EXPECT_EQ(out[1], 0x94fdccebu);
  EXPECT_EQ(out[2], 0x5001e420u);
  EXPECT_EQ(out[3], 0x24126ea1u);
}

TEST(CounterRandom, BitsAreThePhiloxBlockOfSeedStreamAndIndex) {
  const std::uint64_t seed = 0x0123456789abcdefULL;
  const std::uint64_t index = 0x00000005deadbeefULL;
  const CounterRandom random(seed, RandomStream::staircase);
  r123::Philox4x32 generator;
  const r123::Philox4x32::ctr_type counter = {{0xdeadbeefu, 0x5u, 6u, 9u}};
  const r123::Philox4x32::key_type key = {{0x89abcdefu, 0x01234567u}};
  const auto expected = generator(counter, key);
  const auto bits = random.bits(index, 9);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(bits[static_cast<std::size_t>(i)], expected[i]) << "word " << i;
}

constexpr int kDraws = 100000;

TEST(CounterRandom, UniformIsInUnitIntervalWithMeanOneHalf) {
  const CounterRandom random(7, RandomStream::observer);
  double sum = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const double u = random.uniform(static_cast<std::uint64_t>(i));
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
  }
  // Standard error of the mean is 1/sqrt(12 * 1e5) = 0.0009; 0.005 is over 5 of them.
  EXPECT_NEAR(sum / kDraws, 0.5, 0.005);
}

TEST(CounterRandom, NormalHasZeroMeanAndUnitVariance) {
  const CounterRandom random(11, RandomStream::response_time);
  double sum = 0.0;
  double sum_squares = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const double z = random.normal(static_cast<std::uint64_t>(i));
    ASSERT_TRUE(std::isfinite(z));
    sum += z;
    sum_squares += z * z;
  }
  const double mean = sum / kDraws;
  const double variance = sum_squares / kDraws - mean * mean;
  EXPECT_NEAR(mean, 0.0, 0.02);
  EXPECT_NEAR(variance, 1.0, 0.02);
}

TEST(CounterRandom, BelowIsUniformOverItsRange) {
  const CounterRandom random(3, RandomStream::trial_order);
  std::vector<int> counts(10, 0);
  for (int i = 0; i < kDraws; ++i) {
    const std::uint64_t value = random.below(10, static_cast<std::uint64_t>(i));
    ASSERT_LT(value, 10u);
    ++counts[value];
  }
  // Chi-square with 9 degrees of freedom: 30 is beyond the 99.9th percentile (27.9).
  const double expected = kDraws / 10.0;
  double chi_square = 0.0;
  for (const int count : counts) chi_square += (count - expected) * (count - expected) / expected;
  EXPECT_LT(chi_square, 30.0);
  EXPECT_EQ(random.below(1, 12345), 0u);
}

TEST(CounterRandom, ShuffleIsAReproduciblePermutation) {
  const CounterRandom random(99, RandomStream::trial_order);
  std::vector<int> items(50);
  std::iota(items.begin(), items.end(), 0);
  std::vector<int> first = items;
  shuffle_in_place(first, random, 1000);
  std::vector<int> sorted = first;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, items) << "not a permutation";
  EXPECT_NE(first, items) << "50 items left in order (probability 1/50!)";

  std::vector<int> again = items;
  shuffle_in_place(again, CounterRandom(99, RandomStream::trial_order), 1000);
  EXPECT_EQ(again, first);
  std::vector<int> other_base = items;
  shuffle_in_place(other_base, random, 2000);
  EXPECT_NE(other_base, first);
}

TEST(CounterRandom, DrawsDoNotDependOnEarlierDraws) {
  const CounterRandom fresh(2024, RandomStream::eye_model);
  const double alone = fresh.uniform(777);
  const double normal_alone = fresh.normal(778);
  const std::uint64_t below_alone = fresh.below(1000, 779);

  const CounterRandom used(2024, RandomStream::eye_model);
  for (std::uint64_t i = 0; i < 777; ++i) (void)used.uniform(i);
  EXPECT_EQ(used.uniform(777), alone);
  EXPECT_EQ(used.normal(778), normal_alone);
  EXPECT_EQ(used.below(1000, 779), below_alone);
  // Drawing in reverse order gives the same values.
  EXPECT_EQ(fresh.below(1000, 779), below_alone);
  EXPECT_EQ(fresh.uniform(777), alone);
}

}  // namespace
}  // namespace glarelab
