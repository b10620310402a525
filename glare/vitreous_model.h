#pragma once
// The vitreous humour (Ritschel et al. 2009, section 3.4): a viscoelastic body that lags behind the
// eye's saccades and comes to rest by strong damping (Zimmerman 1980 measured it overdamped).
// Modelled as one rigid body rotating about the eye's vertical axis through its centre of rotation,
// with state (angle theta, angular velocity omega) relative to the globe:
//   theta'' = -w0^2 theta - 2 zeta w0 theta' + tau(t),
// driven by damped random saccade forces tau(t) = sum_k J_k / T exp(-(t - t_k) / T) (t >= t_k), and
// integrated by forward Euler with a fixed step from t = 0. The force is integrated exactly over each
// step (an impulse J_k (e^{-(t_n - t_k)/T} - e^{-(t_{n+1} - t_k)/T})), so short saccades are not lost
// between steps. Particles sit at fixed random places in the body and are projected orthographically.
//
// Reproducibility: state_at(t) depends only on (parameters, saccades, t). Checkpoints every 1024 steps
// are cached; continuing from one performs the same operations in the same order as integrating from
// t = 0, so the result is bit-identical whether or not earlier times were asked for. Not thread-safe.
#include <cstdint>
#include <vector>

#include "glare/aperture_geometry.h"
#include "glare/eye_parameters.h"

namespace glarelab {

struct Saccade {
  double onset_s = 0.0;
  double impulse_rad_s = 0.0;  // total angular velocity change J given to the vitreous
};

struct VitreousState {
  double angle_rad = 0.0;
  double angular_velocity_rad_s = 0.0;
};

class VitreousDynamics {
 public:
  // Random saccades from the seed: one per interval of saccade_mean_interval_s at a uniform random
  // offset (a jittered-periodic train), impulse normal with sd saccade_impulse_sd_rad_s.
  VitreousDynamics(const EyeParameters& parameters, std::uint64_t seed);
  // Explicit saccades (a measured eye-movement record, or a single test impulse); sorted by onset.
  VitreousDynamics(const EyeParameters& parameters, std::vector<Saccade> saccades);

  VitreousState state_at(double time_s) const;
  // Saccades with onset in [begin_s, end_s).
  std::vector<Saccade> saccades_between(double begin_s, double end_s) const;
  double time_step_s() const { return step_s_; }

 private:
  VitreousState step(const VitreousState& state, std::int64_t n, double step_s, const std::vector<Saccade>& nearby) const;
  void integrate(VitreousState& state, std::int64_t from_step, std::int64_t to_step) const;

  double omega0_rad_s_, zeta_, step_s_, force_decay_s_;
  double interval_s_, impulse_sd_rad_s_;
  std::uint64_t seed_;
  bool explicit_saccades_;
  std::vector<Saccade> saccades_;  // explicit ones only
  static constexpr std::int64_t kCheckpointSteps = 1024;
  mutable std::vector<VitreousState> checkpoints_;  // state at step k * kCheckpointSteps
};

class VitreousModel {
 public:
  VitreousModel(const EyeParameters& parameters, std::uint64_t seed);

  const VitreousDynamics& dynamics() const { return dynamics_; }
  // Particles rotated by the body angle about the vertical axis through the rotation centre,
  // projected onto the pupil plane.
  void append_particles(double angle_rad, std::vector<ApertureDisc>& discs) const;

  struct Particle {
    double x_mm, y_mm, depth_from_rotation_centre_mm, diameter_mm;
  };
  const std::vector<Particle>& particles() const { return particles_; }

 private:
  VitreousDynamics dynamics_;
  std::vector<Particle> particles_;
};

}  // namespace glarelab
