#pragma once
// Sub-streams of RandomStream::eye_model. Every random choice of the eye model is
// CounterRandom(seed, RandomStream::eye_model).uniform(index, channel * kEyeChannelStride + k):
// the channel keeps the components independent, k numbers the draws one element needs.
// Values are part of the reproducibility contract: never renumber them, only append.
#include <cstdint>

namespace glarelab {

enum class EyeChannel : std::uint32_t {
  hippus = 1,                      // Eq. 1 noise (three octaves)
  accommodation_low = 2,           // low-frequency microfluctuation noise
  accommodation_high_phase = 3,    // phase wander of the 1.3-2.1 Hz component
  accommodation_high_start = 4,    // its starting phase
  lens_particles = 5,              // position, angle and size of each lens particle
  lens_gratings = 6,               // position and orientation of each fibre grating
  vitreous_particles = 7,          // particle positions inside the vitreous body
  saccades = 8,                    // saccade onsets and impulses
  cornea_particles = 9,
  retina_particles = 10,
  blinks = 11,                     // blink onsets
  eyelashes = 12,                  // lash roots, tilt and overhang
  luidolt_particles = 13,          // Luidolt 2020's static particle pattern (glare/wave/luidolt_kernel.h)
};

inline constexpr std::uint32_t kEyeChannelStride = 16;

inline constexpr std::uint32_t eye_sub_index(EyeChannel channel, std::uint32_t k) {
  return static_cast<std::uint32_t>(channel) * kEyeChannelStride + k;
}

}  // namespace glarelab
