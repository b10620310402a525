#include "glare/eye/accommodation_model.h"

#include <cmath>

namespace glarelab {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

AccommodationModel::AccommodationModel(const EyeParameters& p, std::uint64_t seed)
    : demand_dioptres_(p.accommodative_demand_dioptres),
      low_rms_per_mm_(p.accommodation_low_frequency_rms_dioptres_per_mm),
      low_max_hz_(p.accommodation_low_frequency_max_hz),
      high_centre_hz_(p.accommodation_high_frequency_centre_hz),
      high_half_width_hz_(p.accommodation_high_frequency_half_width_hz),
      high_rms_dioptres_(p.accommodation_high_frequency_rms_dioptres),
      // The phase wanders slowly (its fastest octave at 4 x 0.25 = 1 Hz) so the band stays narrow.
      phase_wander_rate_hz_(0.25),
      // Instantaneous frequency deviation = scale * rate * noise'(x) / (2 pi) <= half-width, using the
      // bound on |noise'|.
      phase_wander_rad_(2.0 * kPi * p.accommodation_high_frequency_half_width_hz /
                        (0.25 * ValueNoise::kMaxDerivative)),
      start_phase_rad_(2.0 * kPi *
                       CounterRandom(seed, RandomStream::eye_model)
                           .uniform(0, eye_sub_index(EyeChannel::accommodation_high_start, 0))),
      low_noise_(seed, EyeChannel::accommodation_low),
      phase_noise_(seed, EyeChannel::accommodation_high_phase) {}

double AccommodationModel::low_frequency_rms_dioptres(double mean_pupil_diameter_mm) const {
  return low_rms_per_mm_ * mean_pupil_diameter_mm;
}

double AccommodationModel::low_frequency_dioptres(double time_s, double mean_pupil_diameter_mm) const {
  // Normalised to unit standard deviation, then scaled to the pupil-dependent RMS.
  const double unit = low_noise_(time_s * low_frequency_lattice_hz()) / ValueNoise::standard_deviation();
  return unit * low_frequency_rms_dioptres(mean_pupil_diameter_mm);
}

double AccommodationModel::high_frequency_dioptres(double time_s) const {
  const double phase = 2.0 * kPi * high_centre_hz_ * time_s + start_phase_rad_ +
                       phase_wander_rad_ * phase_noise_(time_s * phase_wander_rate_hz_);
  return std::sqrt(2.0) * high_rms_dioptres_ * std::sin(phase);  // a sinusoid's RMS is amplitude / sqrt 2
}

double AccommodationModel::high_frequency_instantaneous_hz(double time_s) const {
  return high_centre_hz_ +
         phase_wander_rad_ * phase_wander_rate_hz_ * phase_noise_.derivative(time_s * phase_wander_rate_hz_) / (2.0 * kPi);
}

double AccommodationModel::fluctuation_dioptres(double time_s, double mean_pupil_diameter_mm) const {
  return low_frequency_dioptres(time_s, mean_pupil_diameter_mm) + high_frequency_dioptres(time_s);
}

double AccommodationModel::accommodation_dioptres(double time_s, double mean_pupil_diameter_mm) const {
  return demand_dioptres_ + fluctuation_dioptres(time_s, mean_pupil_diameter_mm);
}

}  // namespace glarelab
