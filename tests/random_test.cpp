#include <gtest/gtest.h>

#include "runner/random.h"

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
