#include "glare/vitreous_model.h"

#include <algorithm>
#include <cmath>

#include "glare/eye_random_channels.h"
#include "core/random.h"

namespace glarelab {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Forces older than this many decay times are below e^-40 of their peak and are left out.
constexpr double kForceHorizonDecays = 40.0;
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
      checkpoints_{VitreousState{}} {}

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

VitreousState VitreousDynamics::state_at(double time_s) const {
  if (!(time_s > 0.0)) return VitreousState{};
  const auto full_steps = static_cast<std::int64_t>(std::floor(time_s / step_s_));
  const auto checkpoint = static_cast<std::size_t>(full_steps / kCheckpointSteps);
  while (checkpoints_.size() <= checkpoint) {
    VitreousState state = checkpoints_.back();
    const auto from = static_cast<std::int64_t>(checkpoints_.size() - 1) * kCheckpointSteps;
    integrate(state, from, from + kCheckpointSteps);
    checkpoints_.push_back(state);
  }
  VitreousState state = checkpoints_[checkpoint];
  integrate(state, static_cast<std::int64_t>(checkpoint) * kCheckpointSteps, full_steps);
  // The remaining fraction of a step, so the angle is continuous in time.
  const double remainder_s = time_s - static_cast<double>(full_steps) * step_s_;
  if (remainder_s > 0.0) {
    const double begin_s = static_cast<double>(full_steps) * step_s_ - kForceHorizonDecays * force_decay_s_ - step_s_;
    state = step(state, full_steps, remainder_s, saccades_between(begin_s, time_s + step_s_));
  }
  return state;
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
