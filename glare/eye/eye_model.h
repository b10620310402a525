#pragma once
// The dynamic eye of Ritschel et al. 2009 (sections 3-4): from (parameters, seed, time, history of
// frame luminances) to the aperture the glare engine diffracts (glare/eye/aperture_geometry.h).
//
//   field luminance  -- time-damped frame mean (glare/eye/pupil_model.h)
//   pupil            -- Eq. 2 mean, Eq. 1 hippus                      (glare/eye/pupil_model.h)
//   accommodation    -- microfluctuations (< 0.6 Hz, 1.3-2.1 Hz)      (glare/eye/accommodation_model.h)
//   lens             -- particles moved by the mass-spring deformation, fibre gratings (glare/eye/lens_model.h)
//   vitreous         -- rigid body, damped rotation, saccades         (glare/eye/vitreous_model.h)
//   cornea, retina   -- static particles                              (glare/eye/cornea_retina.h)
//   lids and lashes  -- blinks and squint                             (glare/eye/eyelids.h)
//
// Every output is a deterministic function of (parameters, seed, time, recorded frames up to that
// time): the same call gives bit-identical results whether or not other times were computed before.
// Not thread-safe (the vitreous keeps a cache of integration checkpoints); use one model per thread.
#include <cstdint>
#include <utility>
#include <vector>

#include "glare/eye/accommodation_model.h"
#include "glare/eye/aperture_geometry.h"
#include "glare/eye/cornea_retina.h"
#include "glare/eye/eye_parameters.h"
#include "glare/eye/eyelids.h"
#include "glare/eye/lens_model.h"
#include "glare/eye/pupil_model.h"
#include "glare/eye/vitreous_model.h"

namespace glarelab {

struct EyeState {
  double time_s = 0.0;                  // the time the eye is in (static_time_s for a static eye)
  double field_luminance_cd_m2 = 0.0;
  double mean_pupil_diameter_mm = 0.0;  // Eq. 2
  double pupil_diameter_mm = 0.0;       // Eq. 1, clamped
  double accommodation_dioptres = 0.0;  // demand + microfluctuations
  double defocus_dioptres = 0.0;        // accommodation - demand: the focus error of the eye
  double lens_equator_displacement_mm = 0.0;
  double vitreous_angle_rad = 0.0;
  double vitreous_angular_velocity_rad_s = 0.0;
  double blink_closure = 0.0;           // 0 open .. 1 closed (blinks only)
  double lid_closure = 0.0;             // with the constant squint
  bool gratings_in_pupil = false;       // whether any fibre grating reaches into the pupil
};

class EyeModel {
 public:
  // Validates the parameters (ConfigError naming the key).
  EyeModel(const EyeParameters& parameters, std::uint64_t seed);

  // The displayed frame shown from time_s on had this mean luminance. Frames in time order.
  void record_frame_luminance(double time_s, double mean_luminance_cd_m2);

  // Measured pupil (an eye tracker's filtered diameter): from time_s on, until the next
  // measurement, the pupil is this diameter (clamped to the model's [1.5, 9] mm) instead of Eq. 1-2.
  // Everything that depends on the pupil (gratings in the pupil, the aperture) follows; the
  // accommodation keeps Eq. 2's pupil (its field-luminance driver). Times in order. A static eye
  // ignores measurements (it is frozen at static_time_s, field luminance included).
  void record_measured_pupil(double time_s, double diameter_mm);
  // Blinks from an eye tracker instead of the lids' own schedule (glare/eye/eyelids.h).
  // Every blink so far as (onset_s, offset_s), offset +infinity while closed (glare/eye/eyelids.h).
  void set_recorded_blinks(std::vector<std::pair<double, double>> blinks) { eyelids_.set_recorded_blinks(std::move(blinks)); }

  EyeState state_at(double time_s) const;
  // The aperture at time_s. Control mode: glare_enabled = false and no scatterers (pupil only).
  // Fibre gratings that cannot reach into the pupil are left out (they change nothing: the aperture
  // is zero outside the pupil).
  ApertureGeometry geometry_at(double time_s) const;

  const EyeParameters& parameters() const { return parameters_; }
  const LensModel& lens() const { return lens_; }
  const VitreousModel& vitreous() const { return vitreous_; }
  const EyelidModel& eyelids() const { return eyelids_; }
  const PupilModel& pupil() const { return pupil_; }
  const AccommodationModel& accommodation() const { return accommodation_; }

 private:
  double model_time_s(double time_s) const;

  EyeParameters parameters_;
  std::uint64_t seed_;
  FieldLuminanceHistory field_;
  PupilModel pupil_;
  AccommodationModel accommodation_;
  LensModel lens_;
  VitreousModel vitreous_;
  CorneaRetinaParticles cornea_retina_;
  EyelidModel eyelids_;
  std::vector<std::pair<double, double>> measured_pupils_;  // (time_s, diameter_mm), time ascending
};

}  // namespace glarelab
