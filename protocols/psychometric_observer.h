#pragma once
// A model observer for adaptive procedures: answers correctly with the probability of a Weibull
// psychometric function of the stimulus intensity (Wichmann & Hill 2001, "The psychometric
// function: I", Perception & Psychophysics 63(8), eq. 1):
//   p(I) = guess + (1 - guess - lapse) * (1 - exp(-(I / threshold)^slope)),  I >= 0.
// On a log10 axis x = log10 I this is QUEST's form guess + ... * (1 - exp(-10^(slope (x - log10 threshold)))),
// so the same observer drives staircases (linear intensities) and QUEST (log10 intensities).
// Pure logic, no rendering: fast enough for hundreds of simulated runs in a test.
#include <cstdint>

#include "core/random.h"

namespace glarelab {

struct PsychometricFunction {
  double threshold = 1.0;  // intensity where p = guess + (1 - guess - lapse)(1 - 1/e)
  double slope = 3.5;      // Weibull beta
  double guess = 0.5;      // chance rate: 1 / alternatives
  double lapse = 0.02;     // rate of errors at any intensity

  double p_correct(double intensity) const;
  // The intensity at which p_correct equals p, for guess < p < 1 - lapse (std::invalid_argument else).
  double intensity_at(double p) const;
};

class PsychometricObserver {
 public:
  PsychometricObserver(PsychometricFunction function, std::uint64_t seed)
      : function_(function), random_(seed, RandomStream::observer) {}
  // Correct with probability p_correct(intensity); the draw is a pure function of (seed, trial_index).
  bool respond(double intensity, std::uint64_t trial_index) const {
    return random_.uniform(trial_index, 1) < function_.p_correct(intensity);
  }
  const PsychometricFunction& function() const { return function_; }

 private:
  PsychometricFunction function_;
  CounterRandom random_;
};

}  // namespace glarelab
