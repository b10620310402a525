#pragma once
// Accommodation microfluctuations (Ritschel et al. 2009, section 3.3, after Gray, Winn and
// Gilmartin 1993): during steady fixation accommodation fluctuates with two principal spectral
// components,
//  - a low-frequency component below 0.6 Hz whose power grows with pupil size: three-octave value
//    noise whose highest octave has a lattice rate of 0.6 Hz, with an RMS proportional to the Eq. 2
//    (mean) pupil diameter;
//  - a narrow high-frequency component between 1.3 and 2.1 Hz: a sinusoid at the centre frequency
//    whose phase wanders by value noise, scaled so the instantaneous frequency never leaves
//    centre +- half-width.
// Both are closed-form functions of time: no integration, any t is evaluated alone.
#include <cstdint>

#include "glare/eye/eye_parameters.h"
#include "glare/eye/value_noise.h"

namespace glarelab {

class AccommodationModel {
 public:
  AccommodationModel(const EyeParameters& parameters, std::uint64_t seed);

  double low_frequency_dioptres(double time_s, double mean_pupil_diameter_mm) const;
  double high_frequency_dioptres(double time_s) const;
  // Fluctuation about the demand (the defocus of a perfectly tracking mean response), dioptres.
  double fluctuation_dioptres(double time_s, double mean_pupil_diameter_mm) const;
  // Accommodation = demand + fluctuation, dioptres.
  double accommodation_dioptres(double time_s, double mean_pupil_diameter_mm) const;

  double low_frequency_rms_dioptres(double mean_pupil_diameter_mm) const;
  // Lattice rate of the low octave; octaves run at 1x, 2x and 4x it, the top at the 0.6 Hz limit.
  double low_frequency_lattice_hz() const { return low_max_hz_ / 4.0; }
  // Instantaneous frequency of the high-frequency component, Hz (stays within centre +- half-width).
  double high_frequency_instantaneous_hz(double time_s) const;

 private:
  double demand_dioptres_;
  double low_rms_per_mm_, low_max_hz_;
  double high_centre_hz_, high_half_width_hz_, high_rms_dioptres_;
  double phase_wander_rate_hz_;  // lattice rate of the phase noise
  double phase_wander_rad_;      // phase noise scale, from the half-width
  double start_phase_rad_;
  ValueNoise low_noise_;
  ValueNoise phase_noise_;
};

}  // namespace glarelab
