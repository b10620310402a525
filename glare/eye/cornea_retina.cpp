#include "glare/eye/cornea_retina.h"

#include <cmath>

#include "glare/eye/eye_random_channels.h"
#include "core/random.h"

namespace glarelab {

namespace {

std::vector<ApertureDisc> uniform_discs(std::uint64_t seed, EyeChannel channel, int count, double diameter_mm,
                                        double region_radius_mm) {
  const CounterRandom random(seed, RandomStream::eye_model);
  std::vector<ApertureDisc> discs;
  discs.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const auto index = static_cast<std::uint64_t>(k);
    // Uniform over the disc area: radius from the square root of a uniform deviate.
    const double r = region_radius_mm * std::sqrt(random.uniform(index, eye_sub_index(channel, 0)));
    const double angle = 2.0 * 3.14159265358979323846 * random.uniform(index, eye_sub_index(channel, 1));
    discs.push_back(ApertureDisc{r * std::cos(angle), r * std::sin(angle), 0.5 * diameter_mm, 0.0});
  }
  return discs;
}

}  // namespace

CorneaRetinaParticles::CorneaRetinaParticles(const EyeParameters& p, std::uint64_t seed)
    : cornea_(uniform_discs(seed, EyeChannel::cornea_particles, p.cornea_particle_count,
                            p.cornea_particle_diameter_mm, p.static_particle_region_radius_mm)),
      retina_(uniform_discs(seed, EyeChannel::retina_particles, p.retina_particle_count,
                            p.retina_particle_diameter_mm, p.static_particle_region_radius_mm)) {}

}  // namespace glarelab
