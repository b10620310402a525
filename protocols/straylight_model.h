#pragma once
// The compensation-comparison measurement of intraocular straylight (Franssen, Coppens & van den
// Berg 2006, the C-Quant method) as mathematics: the ring constant, the age norm, the
// psychometric model of the two halves' flicker and the maximum-likelihood estimate of log10(s)
// from a participant's answers. Derivations in docs/STRAYLIGHT.md.
//
// Straylight is in the units of the straylight parameter s = theta^2 L_eq / E_glare (deg^2 / sr).
// A ring of luminance L_ring flickering on and off makes the dark test field flicker with the
// amplitude of its veil, k s L_ring. The compensated half also gets light L_c = k s_c L_ring in
// counterphase, so its flicker amplitude is k L_ring |s - s_c|; the other half's is k L_ring s.
#include <cstdint>
#include <vector>

namespace glarelab {

// ESD above which a measurement is flagged unreliable (the C-Quant's criterion, 0.08 log units);
// applied to both spreads of the likelihood (StraylightEstimate).
inline constexpr double kStraylightUnreliableEsdLog10 = 0.08;

// k = 2 pi (pi / 180)^2 ln(outer / inner): L_eq / (s L_ring) at the centre of a uniform ring whose
// s is the same at every angle (1.327e-3 for 5-10 degrees). std::invalid_argument unless
// 0 < inner < outer.
double ring_straylight_constant(double inner_deg, double outer_deg);

// The healthy eye's age norm at 7 degrees: log10(s) = 0.87 + log10(1 + (age / 65)^4)
// (van den Berg et al. 2007, 2318 eyes; population SD about 0.10).
double straylight_age_norm_log10(double age_years);
// The healthy population's SD about the age norm (log10 units).
inline constexpr double kStraylightAgeNormSdLog10 = 0.10;

// The observer model both the estimate and the simulated observer use: each half's flicker
// amplitude is seen on a log10 scale with Gaussian noise, the difference of the two having SD
// `amplitude_noise_log10`; with probability `lapse` the answer is a guess.
struct StraylightPsychometric {
  double amplitude_noise_log10 = 0.15;
  double lapse = 0.04;
};

// P(the compensated half is answered as flickering more) for an eye with log10 s and a
// compensation log10 s_c: lapse / 2 + (1 - lapse) Phi(log10|1 - s_c / s| / amplitude_noise_log10).
// It is 1/2 at s_c = 0, near lapse / 2 at s_c = s (full compensation) and 1/2 again at s_c = 2 s.
double probability_compensated_stronger(double log_s, double log_compensation,
                                        const StraylightPsychometric& psychometric);

// One answer of the measurement: the compensation shown (log10 s_c) and whether the participant
// chose the compensated half as the one flickering more.
struct StraylightAnswer {
  double log_compensation = 0.0;
  bool compensated_stronger = false;
};

// The grid the likelihood is evaluated on: log10 s from -0.5 to 3.0 in 0.005 steps (an eye's
// straylight lies between 0.6 and 2.5 even with dense cataract).
struct StraylightLikelihood {
  std::vector<double> log_s;       // grid points
  std::vector<double> normalised;  // likelihood over the grid, summing to 1 (a flat prior's posterior)
};

struct StraylightEstimate {
  double log_s = 0.0;  // maximum of the likelihood (parabolic refinement between grid points)
  // Expected SD: half the width of the likelihood's peak at e^-1/2 of its maximum (a Gaussian
  // likelihood's SD), interpolated between grid points.
  double esd_log10 = 0.0;
  double likelihood_sd_log10 = 0.0;  // the SD of the whole normalised likelihood (its tails included)
  // esd_log10 or likelihood_sd_log10 above kStraylightUnreliableEsdLog10.
  bool unreliable = false;
  StraylightLikelihood likelihood;
};

// Maximum-likelihood estimate of log10 s. std::invalid_argument for no answers.
// `display_straylight` (deg^2 / sr): the display's own stray light on the test field while the ring
// is on, in straylight units (glow / (k L_ring)). It flickers with the ring, so the answers see
// s + display_straylight; the grid is the eye's s, and the display's part is subtracted by
// evaluating each grid point's probabilities at s + display_straylight.
StraylightEstimate estimate_straylight(const std::vector<StraylightAnswer>& answers,
                                       const StraylightPsychometric& psychometric, double display_straylight = 0.0);

// The levels of one measurement: a range-finding phase (a one-up/one-down run of
// `range_answers` answers in `range_step_log10` steps from `start_log_compensation`, descending
// while the compensated half is seen to flicker more), then the remaining answers at fixed offsets
// spread evenly over +-`fixed_half_span_log10`, in a seeded order, around 2 s of the estimate from
// the answers so far (where the two halves flicker equally), rounded to `level_step_log10`.
struct StraylightSchedule {
  int answers = 25;
  int range_answers = 7;
  double start_log_compensation = 2.1;
  double range_step_log10 = 0.2;
  double fixed_half_span_log10 = 0.3;
  double level_step_log10 = 0.02;
};

// The compensation (log10 s_c) of answer number answers.size(), a pure function of the schedule,
// the answers so far and the seed (so a resumed session replays to the same level).
// std::invalid_argument once answers.size() >= schedule.answers.
// The fixed levels centre on 2 (s + display_straylight), where the halves flicker alike.
double next_log_compensation(const StraylightSchedule& schedule, const std::vector<StraylightAnswer>& answers,
                             const StraylightPsychometric& psychometric, std::uint64_t seed,
                             double display_straylight = 0.0);

// Whether the compensation of answer `index` is on the left half (seeded coin, one per answer).
bool compensation_on_left(std::uint64_t seed, std::uint64_t index);

}  // namespace glarelab
