#pragma once
// Counter-based random numbers: every draw is a pure function of (seed, stream, index), so any
// trial or frame can be reproduced alone without replaying what came before. Philox4x32-10
// (Salmon et al. 2011, "Parallel random numbers: as easy as 1, 2, 3") from Random123.
#include <array>
#include <cstdint>

namespace glarelab {

// Named streams keep independent uses of one seed apart. Values are part of the reproducibility
// contract: never renumber them, only append.
enum class RandomStream : std::uint32_t {
  trial_order = 1,
  observer = 2,
  response_time = 3,
  eye_model = 4,
  tracker_simulation = 5,
  staircase = 6,
  adjustment_start = 7,
  analysis_bootstrap = 8,  // parametric bootstrap of psychometric fits (analysis/)
  glare_gl_test_input = 9,  // random test signals for the GL glare engine tests
  block_order = 10,          // random block orders, one seed per participant (protocols/block_design.h)
  block_trial_order = 11,    // trial orders within blocks, one seed per participant and block
  fuzz_mutation = 12,        // deterministic input mutations of the fuzz targets' replay runs (fuzz/)
  stereo_eye = 13,           // the seed of each eye's model in a stereo session (stimuli/stereo_layout.h)
  spencer_flare_lines = 14,  // Spencer's flare lines: azimuth and intensity of each line (glare/analytic/spencer_flare_lines.h)
};

class CounterRandom {
 public:
  CounterRandom(std::uint64_t seed, RandomStream stream) : seed_(seed), stream_(static_cast<std::uint32_t>(stream)) {}

  // Four raw 32-bit words for counter `index` (and an optional sub-index for more draws per index).
  std::array<std::uint32_t, 4> bits(std::uint64_t index, std::uint32_t sub_index = 0) const;

  // Uniform double in [0, 1) with 53 random bits, from the first two words.
  double uniform(std::uint64_t index, std::uint32_t sub_index = 0) const;
  // Uniform integer in [0, bound) without modulo bias (bound > 0).
  std::uint64_t below(std::uint64_t bound, std::uint64_t index, std::uint32_t sub_index = 0) const;
  // Standard normal deviate (Box-Muller on two uniforms of this counter).
  double normal(std::uint64_t index, std::uint32_t sub_index = 0) const;

  std::uint64_t seed() const { return seed_; }

 private:
  std::uint64_t seed_;
  std::uint32_t stream_;
};

// Fisher-Yates shuffle of [0, n) whose draws come from (stream, index_base + i).
template <typename Container>
void shuffle_in_place(Container& items, const CounterRandom& random, std::uint64_t index_base) {
  for (std::size_t i = items.size(); i > 1; --i) {
    const std::size_t j = static_cast<std::size_t>(random.below(i, index_base + (items.size() - i)));
    std::swap(items[i - 1], items[j]);
  }
}

}  // namespace glarelab
