#include "core/random.h"

#include <Random123/philox.h>

#include <cmath>
#include <numbers>

namespace glarelab {

std::array<std::uint32_t, 4> CounterRandom::bits(std::uint64_t index, std::uint32_t sub_index) const {
  // Key: the 64-bit seed. Counter: (index low, index high, stream, sub-index).
  r123::Philox4x32 generator;
  r123::Philox4x32::key_type key = {{static_cast<std::uint32_t>(seed_), static_cast<std::uint32_t>(seed_ >> 32)}};
  r123::Philox4x32::ctr_type counter = {
      {static_cast<std::uint32_t>(index), static_cast<std::uint32_t>(index >> 32), stream_, sub_index}};
  const auto out = generator(counter, key);
  return {out[0], out[1], out[2], out[3]};
}

double CounterRandom::uniform(std::uint64_t index, std::uint32_t sub_index) const {
  const auto words = bits(index, sub_index);
  const std::uint64_t mantissa = (static_cast<std::uint64_t>(words[0]) << 21) ^ (words[1] >> 11);
  return static_cast<double>(mantissa & ((1ULL << 53) - 1)) * 0x1.0p-53;
}

std::uint64_t CounterRandom::below(std::uint64_t bound, std::uint64_t index, std::uint32_t sub_index) const {
  // Rejection on the top of the 64-bit range removes modulo bias; each retry uses a fresh
  // sub-counter so the result stays a pure function of the inputs.
  const std::uint64_t limit = UINT64_MAX - (UINT64_MAX % bound);
  for (std::uint32_t attempt = 0;; ++attempt) {
    const auto words = bits(index, sub_index + (attempt << 16));
    const std::uint64_t value = (static_cast<std::uint64_t>(words[2]) << 32) | words[3];
    if (value < limit) return value % bound;
  }
}

double CounterRandom::normal(std::uint64_t index, std::uint32_t sub_index) const {
  const auto words = bits(index, sub_index);
  // Two uniforms in (0, 1]; the +1 keeps log() finite.
  const double u1 = (static_cast<double>(words[0]) + 1.0) * 0x1.0p-32;
  const double u2 = static_cast<double>(words[1]) * 0x1.0p-32;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace glarelab
