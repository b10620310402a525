#include "protocols/psychometric_observer.h"

#include <cmath>
#include <stdexcept>

namespace glarelab {

double PsychometricFunction::p_correct(double intensity) const {
  const double weibull = intensity > 0.0 ? 1.0 - std::exp(-std::pow(intensity / threshold, slope)) : 0.0;
  return guess + (1.0 - guess - lapse) * weibull;
}

double PsychometricFunction::intensity_at(double p) const {
  if (!(p > guess && p < 1.0 - lapse))
    throw std::invalid_argument("psychometric function: p must lie between guess and 1 - lapse");
  // Invert p = g + (1 - g - l)(1 - exp(-(I/a)^b)): (I/a)^b = -ln(1 - (p - g)/(1 - g - l)).
  const double w = (p - guess) / (1.0 - guess - lapse);
  return threshold * std::pow(-std::log(1.0 - w), 1.0 / slope);
}

}  // namespace glarelab
