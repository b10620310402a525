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
// its start, so the result is bit-identical whether or not earlier times were asked for. Not thread-safe.
//
// Cost independent of t (the body forgets its past). One Euler step maps the state x = (theta, omega)
// to A x + (0, impulse) with A = [[1, h], [-h w0^2, 1 - 2 zeta w0 h]], whose eigenvalues are 1 - h s_i
// for the roots s_i of s^2 - 2 zeta w0 s + w0^2 (|.| < 1: the step bound of glare/eye/eye_parameters.cpp). By
// linearity, two integrations with the same forces that start M steps apart in different states
// differ afterwards by A^M (x_a - x_b). The constructor finds the smallest M (a whole number of
// checkpoints) with ||A^M||_inf <= 2^-60, the forgetting window (35 s for the defaults: the slow
// root s_1 = w0 (zeta - sqrt(zeta^2 - 1)) = 1.2 / s). Time is cut into epochs of 4 windows; the
// state at the start of epoch e > 0 is integrated from rest one window before it, and every time
// inside the epoch continues from there by checkpoints. So:
//  - t in epoch 0 (the first 140 s for the defaults): exactly the integration from t = 0, bit for bit;
//  - later t: in exact arithmetic that integration plus A^M x(epoch start - M), at most 2^-60 of the
//    state then (|theta| < 0.5 rad: < 5e-19 rad, below one unit in the last place of any angle above
//    0.004 rad); in floating point each also carries its own rounding, of the size the integration
//    from 0 has against exact arithmetic (measured: the two agree to the last bit at 150-3000 s,
//    tests/eye_time_bound_test.cpp);
//  - any t costs at most 5 windows of steps (a fresh model at 24 h: ~180k steps),
//    and times in order cost about 1.25 steps per step (one window of 4 integrated twice).
// If the damping is so weak that no window up to kMaxForgettingCheckpoints checkpoints reaches
// 2^-60, the model integrates every time from t = 0 (times are bounded by kMaxEyeModelTime_s).
#include <cstdint>
#include <map>
#include <vector>

#include "glare/eye/aperture_geometry.h"
#include "glare/eye/eye_parameters.h"

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
  // The plain forward Euler integration from rest at t = 0, whatever t: cost in proportion to t.
  // The reference state_at() is checked against (tests/eye_vitreous_test.cpp).
  VitreousState state_integrated_from_zero(double time_s) const;
  // Length of the forgetting window and of an epoch (see above); 0 when the window is off.
  double forgetting_window_s() const;
  double epoch_s() const;
  // Saccades with onset in [begin_s, end_s).
  std::vector<Saccade> saccades_between(double begin_s, double end_s) const;
  double time_step_s() const { return step_s_; }

 private:
  VitreousState step(const VitreousState& state, std::int64_t n, double step_s, const std::vector<Saccade>& nearby) const;
  void integrate(VitreousState& state, std::int64_t from_step, std::int64_t to_step) const;
  VitreousState checkpoint_state(std::int64_t checkpoint) const;
  // The last fraction of a step after full_steps, so the angle is continuous in time.
  VitreousState finish(VitreousState state, std::int64_t full_steps, double time_s) const;

  double omega0_rad_s_, zeta_, step_s_, force_decay_s_;
  double interval_s_, impulse_sd_rad_s_;
  std::uint64_t seed_;
  bool explicit_saccades_;
  std::vector<Saccade> saccades_;  // explicit ones only
  static constexpr std::int64_t kCheckpointSteps = 1024;
  static constexpr std::int64_t kMaxForgettingCheckpoints = 4096;
  static constexpr std::int64_t kEpochWindows = 4;
  std::int64_t forgetting_checkpoints_ = 0;  // M / kCheckpointSteps; 0: no window, integrate from 0
  mutable std::map<std::int64_t, VitreousState> checkpoints_;  // state at step k * kCheckpointSteps
  // The last full-step state asked for: a later time in the same checkpoint interval continues from
  // it (the same operations as from the checkpoint), so times in order cost O(steps between them).
  mutable std::int64_t last_step_ = -1;
  mutable VitreousState last_state_;
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
