// The vitreous: a rigid body with damped rotation driven by saccades, integrated by forward Euler
// (Ritschel 3.4); overdamped as Zimmerman 1980 measured. Checked against the closed-form solution.
#include <gtest/gtest.h>

#include <cmath>

#include "glare/eye/vitreous_model.h"

namespace glarelab {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Closed-form response of theta'' + 2 zeta w0 theta' + w0^2 theta = J / T exp(-t / T) (t >= 0) for an
// overdamped oscillator, roots -s1, -s2: the convolution of the impulse response
// h(t) = (e^{-s1 t} - e^{-s2 t}) / (s2 - s1) with the force.
double analytic_response(double t, double impulse, double decay_s, double s1, double s2) {
  if (t <= 0.0) return 0.0;
  const double a = 1.0 / decay_s;
  const double first = (std::exp(-s1 * t) - std::exp(-a * t)) / (a - s1);
  const double second = (std::exp(-s2 * t) - std::exp(-a * t)) / (a - s2);
  return impulse * a / (s2 - s1) * (first - second);
}

struct Roots {
  double s1, s2;
};
Roots roots(const EyeParameters& p) {
  const double w0 = 2 * kPi * p.vitreous_natural_frequency_hz, z = p.vitreous_damping_ratio;
  return {w0 * (z - std::sqrt(z * z - 1)), w0 * (z + std::sqrt(z * z - 1))};
}

TEST(EyeVitreous, SingleSaccadeDecaysAsTheOverdampedSolution) {
  EyeParameters p;
  const VitreousDynamics dynamics(p, std::vector<Saccade>{{0.5, 0.1}});
  const Roots r = roots(p);
  double peak = 0.0;
  for (int k = 0; k <= 600; ++k) peak = std::max(peak, analytic_response(k * 0.01 - 0.5, 0.1, p.saccade_force_decay_s, r.s1, r.s2));
  for (int k = 0; k <= 600; ++k) {
    const double t = k * 0.01;
    const double theta = dynamics.state_at(t).angle_rad;
    EXPECT_NEAR(theta, analytic_response(t - 0.5, 0.1, p.saccade_force_decay_s, r.s1, r.s2), 0.01 * peak) << t;
    EXPECT_GE(theta, -1e-12) << "overdamped (Zimmerman 1980): no overshoot";
  }
  // Relaxation: after the peak the angle decays with the slow rate s1 = w0 (zeta - sqrt(zeta^2 - 1)).
  const double late1 = dynamics.state_at(3.5).angle_rad, late2 = dynamics.state_at(4.5).angle_rad;
  EXPECT_NEAR(std::log(late1 / late2), r.s1, 0.02 * r.s1);
  EXPECT_LT(dynamics.state_at(6.0).angle_rad, 0.02 * peak);
  std::printf("vitreous: peak %.4f rad for a 0.1 rad/s saccade, slow decay rate %.3f 1/s (time constant %.3f s)\n", peak,
              std::log(late1 / late2), 1.0 / std::log(late1 / late2));
}

TEST(EyeVitreous, RandomSaccadesStayBoundedAndMatchSuperposition) {
  EyeParameters p;
  const VitreousDynamics dynamics(p, 21);
  const Roots r = roots(p);
  const auto saccades = dynamics.saccades_between(0.0, 60.0);
  EXPECT_NEAR(static_cast<double>(saccades.size()), 60.0 / p.saccade_mean_interval_s, 1.0);
  double largest = 0.0, bound = 0.0, worst_error = 0.0;
  for (const Saccade& s : saccades) bound = std::max(bound, std::abs(s.impulse_rad_s));
  for (int k = 0; k <= 1200; ++k) {
    const double t = k * 0.05;
    double expected = 0.0;
    for (const Saccade& s : saccades) expected += analytic_response(t - s.onset_s, s.impulse_rad_s, p.saccade_force_decay_s, r.s1, r.s2);
    const double theta = dynamics.state_at(t).angle_rad;
    EXPECT_NEAR(theta, expected, 0.002 * bound) << t;
    worst_error = std::max(worst_error, std::abs(theta - expected));
    largest = std::max(largest, std::abs(theta));
  }
  // Bounded: never more than the sum of all single-saccade peaks could give, and far below it.
  EXPECT_LT(largest, 0.5);
  EXPECT_GT(largest, 0.0);
  std::printf("vitreous: max |angle| over 60 s = %.4f rad (%.2f deg), forward Euler against closed form: %.2e rad\n",
              largest, largest * 180 / kPi, worst_error);
}

TEST(EyeVitreous, StateAtIsIdenticalWithOrWithoutEarlierCalls) {
  EyeParameters p;
  const VitreousDynamics fresh(p, 3), warmed(p, 3);
  for (int k = 0; k < 500; ++k) (void)warmed.state_at(k * 0.0371);
  for (const double t : {0.0005, 1.024, 7.3, 18.4567}) {
    const VitreousState a = fresh.state_at(t), b = warmed.state_at(t);
    EXPECT_EQ(a.angle_rad, b.angle_rad) << t;
    EXPECT_EQ(a.angular_velocity_rad_s, b.angular_velocity_rad_s) << t;
  }
}

TEST(EyeVitreous, ParticlesRotateRigidly) {
  EyeParameters p;
  const VitreousModel model(p, 8);
  ASSERT_EQ(model.particles().size(), static_cast<std::size_t>(p.vitreous_particle_count));
  std::vector<ApertureDisc> rest, turned;
  model.append_particles(0.0, rest);
  model.append_particles(0.01, turned);
  for (std::size_t k = 0; k < rest.size(); ++k) {
    const auto& particle = model.particles()[k];
    EXPECT_EQ(rest[k].centre_y_mm, turned[k].centre_y_mm);  // rotation about the vertical axis
    EXPECT_NEAR(turned[k].centre_x_mm,
                particle.x_mm * std::cos(0.01) + particle.depth_from_rotation_centre_mm * std::sin(0.01), 1e-12);
  }
}

}  // namespace
}  // namespace glarelab
