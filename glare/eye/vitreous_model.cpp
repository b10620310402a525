#include "glare/eye/vitreous_model.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "glare/eye/eye_random_channels.h"
#include "core/random.h"

namespace glarelab {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Forces older than this many decay times are below e^-40 of their peak and are left out.
constexpr double kForceHorizonDecays = 40.0;
// What the forgetting window leaves of the state it starts from (glare/eye/vitreous_model.h).
constexpr double kForgottenFraction = 0x1p-60;

// 2 x 2 matrices for the powers of the Euler step matrix.
struct Matrix2 {
  double a, b, c, d;
};
Matrix2 operator*(const Matrix2& x, const Matrix2& y) {
  return {x.a * y.a + x.b * y.c, x.a * y.b + x.b * y.d, x.c * y.a + x.d * y.c, x.c * y.b + x.d * y.d};
}
double infinity_norm(const Matrix2& m) { return std::max(std::abs(m.a) + std::abs(m.b), std::abs(m.c) + std::abs(m.d)); }
}  // namespace

VitreousDynamics::VitreousDynamics(const EyeParameters& p, std::uint64_t seed)
    : omega0_rad_s_(2.0 * kPi * p.vitreous_natural_frequency_hz),
      zeta_(p.vitreous_damping_ratio),
      step_s_(p.vitreous_time_step_s),
      force_decay_s_(p.saccade_force_decay_s),
      interval_s_(p.saccade_mean_interval_s),
      impulse_sd_rad_s_(p.saccade_impulse_sd_rad_s),
      seed_(seed),
      explicit_saccades_(false),
      checkpoints_{{0, VitreousState{}}} {
  // The forgetting window: the smallest whole number of checkpoints M / kCheckpointSteps with
  // ||A^M||_inf <= 2^-60, A the forward Euler step matrix (glare/eye/vitreous_model.h). A^1024 by ten squarings.
  static_assert(kCheckpointSteps == 1024, "A^kCheckpointSteps is formed by ten squarings");
  const double h = step_s_, w = omega0_rad_s_;
  Matrix2 checkpoint_matrix{1.0, h, -h * w * w, 1.0 - 2.0 * zeta_ * w * h};
  for (int k = 0; k < 10; ++k) checkpoint_matrix = checkpoint_matrix * checkpoint_matrix;
  Matrix2 power = checkpoint_matrix;
  for (std::int64_t k = 1; k <= kMaxForgettingCheckpoints; ++k, power = power * checkpoint_matrix)
    if (infinity_norm(power) <= kForgottenFraction) {
      forgetting_checkpoints_ = k;
      break;
    }
}

VitreousDynamics::VitreousDynamics(const EyeParameters& p, std::vector<Saccade> saccades)
    : VitreousDynamics(p, 0) {
  explicit_saccades_ = true;
  saccades_ = std::move(saccades);
  std::sort(saccades_.begin(), saccades_.end(),
            [](const Saccade& a, const Saccade& b) { return a.onset_s < b.onset_s; });
}

std::vector<Saccade> VitreousDynamics::saccades_between(double begin_s, double end_s) const {
  std::vector<Saccade> result;
  if (explicit_saccades_) {
    for (const Saccade& s : saccades_)
      if (s.onset_s >= begin_s && s.onset_s < end_s) result.push_back(s);
    return result;
  }
  const CounterRandom random(seed_, RandomStream::eye_model);
  const auto first = static_cast<std::int64_t>(std::floor(std::max(0.0, begin_s) / interval_s_));
  const auto last = static_cast<std::int64_t>(std::floor(std::max(0.0, end_s) / interval_s_));
  for (std::int64_t bin = first; bin <= last; ++bin) {
    const auto index = static_cast<std::uint64_t>(bin);
    const double onset = (static_cast<double>(bin) + random.uniform(index, eye_sub_index(EyeChannel::saccades, 0))) *
                         interval_s_;
    if (onset < begin_s || onset >= end_s) continue;
    result.push_back(Saccade{onset, impulse_sd_rad_s_ * random.normal(index, eye_sub_index(EyeChannel::saccades, 1))});
  }
  return result;
}

VitreousState VitreousDynamics::step(const VitreousState& state, std::int64_t n, double step_s,
                                     const std::vector<Saccade>& nearby) const {
  const double t0 = static_cast<double>(n) * step_s_;
  const double t1 = t0 + step_s;
  // Exact integral of the damped saccade forces over [t0, t1].
  double impulse = 0.0;
  for (const Saccade& s : nearby) {
    if (s.onset_s >= t1) break;
    const double a = std::max(0.0, t0 - s.onset_s), b = t1 - s.onset_s;
    if (a > kForceHorizonDecays * force_decay_s_) continue;
    impulse += s.impulse_rad_s * (std::exp(-a / force_decay_s_) - std::exp(-b / force_decay_s_));
  }
  // Forward Euler.
  const double acceleration =
      -omega0_rad_s_ * omega0_rad_s_ * state.angle_rad - 2.0 * zeta_ * omega0_rad_s_ * state.angular_velocity_rad_s;
  return VitreousState{state.angle_rad + step_s * state.angular_velocity_rad_s,
                       state.angular_velocity_rad_s + step_s * acceleration + impulse};
}

void VitreousDynamics::integrate(VitreousState& state, std::int64_t from_step, std::int64_t to_step) const {
  // Process in chunks of one checkpoint interval, with the saccades that can act in each chunk; the
  // chunks are aligned to checkpoints so every path performs identical operations.
  std::int64_t n = from_step;
  while (n < to_step) {
    const std::int64_t chunk_end = std::min(to_step, (n / kCheckpointSteps + 1) * kCheckpointSteps);
    const double begin_s = static_cast<double>(n / kCheckpointSteps * kCheckpointSteps) * step_s_ -
                           kForceHorizonDecays * force_decay_s_ - step_s_;
    const double end_s = static_cast<double>((n / kCheckpointSteps + 1) * kCheckpointSteps + 1) * step_s_;
    const std::vector<Saccade> nearby = saccades_between(begin_s, end_s);
    for (; n < chunk_end; ++n) state = step(state, n, step_s_, nearby);
  }
}

double VitreousDynamics::forgetting_window_s() const {
  return static_cast<double>(forgetting_checkpoints_ * kCheckpointSteps) * step_s_;
}

double VitreousDynamics::epoch_s() const { return kEpochWindows * forgetting_window_s(); }

VitreousState VitreousDynamics::checkpoint_state(std::int64_t checkpoint) const {
  if (const auto found = checkpoints_.find(checkpoint); found != checkpoints_.end()) return found->second;
  // The checkpoint the integration to this one starts from: its epoch's first (0 without a window).
  const std::int64_t epoch_checkpoints = kEpochWindows * forgetting_checkpoints_;
  const std::int64_t epoch_start = epoch_checkpoints > 0 ? checkpoint - checkpoint % epoch_checkpoints : 0;
  if (!checkpoints_.contains(epoch_start)) {
    // From rest one forgetting window before the epoch (epoch_start > 0 here: checkpoint 0 is cached).
    VitreousState state;
    integrate(state, (epoch_start - forgetting_checkpoints_) * kCheckpointSteps, epoch_start * kCheckpointSteps);
    checkpoints_.emplace(epoch_start, state);
  }
  // Continue from the latest cached checkpoint of the epoch before this one.
  auto from = std::prev(checkpoints_.upper_bound(checkpoint));
  VitreousState state = from->second;
  for (std::int64_t k = from->first; k < checkpoint; ++k) {
    integrate(state, k * kCheckpointSteps, (k + 1) * kCheckpointSteps);
    checkpoints_.emplace(k + 1, state);
  }
  return state;
}

VitreousState VitreousDynamics::finish(VitreousState state, std::int64_t full_steps, double time_s) const {
  const double remainder_s = time_s - static_cast<double>(full_steps) * step_s_;
  if (remainder_s > 0.0) {
    const double begin_s = static_cast<double>(full_steps) * step_s_ - kForceHorizonDecays * force_decay_s_ - step_s_;
    state = step(state, full_steps, remainder_s, saccades_between(begin_s, time_s + step_s_));
  }
  return state;
}

VitreousState VitreousDynamics::state_at(double time_s) const {
  if (!(time_s > 0.0)) return VitreousState{};
  const auto full_steps = static_cast<std::int64_t>(std::floor(time_s / step_s_));
  const std::int64_t checkpoint = full_steps / kCheckpointSteps;
  VitreousState state;
  std::int64_t from_step = 0;
  // integrate() groups steps by checkpoint interval, so continuing from an earlier step of the same
  // interval performs exactly the operations continuing from the interval's checkpoint would.
  if (last_step_ >= 0 && last_step_ / kCheckpointSteps == checkpoint && last_step_ <= full_steps) {
    state = last_state_;
    from_step = last_step_;
  } else {
    state = checkpoint_state(checkpoint);
    from_step = checkpoint * kCheckpointSteps;
  }
  integrate(state, from_step, full_steps);
  last_step_ = full_steps;
  last_state_ = state;
  return finish(state, full_steps, time_s);
}

VitreousState VitreousDynamics::state_integrated_from_zero(double time_s) const {
  if (!(time_s > 0.0)) return VitreousState{};
  const auto full_steps = static_cast<std::int64_t>(std::floor(time_s / step_s_));
  VitreousState state;
  integrate(state, 0, full_steps);
  return finish(state, full_steps, time_s);
}

VitreousModel::VitreousModel(const EyeParameters& p, std::uint64_t seed) : dynamics_(p, seed) {
  // Uniform in a cylinder around the axis that covers the largest pupil at every body angle
  // (Ritschel 3.4: uniform random distribution throughout the vitreous).
  const CounterRandom random(seed, RandomStream::eye_model);
  const auto sub = [](std::uint32_t k) { return eye_sub_index(EyeChannel::vitreous_particles, k); };
  const double radius = p.vitreous_sampling_radius_mm;
  for (int k = 0; k < p.vitreous_particle_count; ++k) {
    const auto index = static_cast<std::uint64_t>(k);
    const double r = radius * std::sqrt(random.uniform(index, sub(0)));
    const double angle = 2.0 * kPi * random.uniform(index, sub(1));
    const double depth = p.vitreous_front_depth_mm +
                         (p.vitreous_back_depth_mm - p.vitreous_front_depth_mm) * random.uniform(index, sub(2));
    particles_.push_back(Particle{r * std::cos(angle), r * std::sin(angle), depth - p.eye_rotation_centre_depth_mm,
                                  p.vitreous_particle_diameter_mm});
  }
}

void VitreousModel::append_particles(double angle_rad, std::vector<ApertureDisc>& discs) const {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  for (const Particle& particle : particles_) {
    // Rotation about the vertical (y) axis through the centre of rotation; depth is along the axis.
    const double x = particle.x_mm * c + particle.depth_from_rotation_centre_mm * s;
    discs.push_back(ApertureDisc{x, particle.y_mm, 0.5 * particle.diameter_mm, 0.0});
  }
}

}  // namespace glarelab
