#include "stimuli/perception/temporal_adaptation.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "glare/eye/pupil_model.h"

namespace glarelab {
namespace {

void require_positive(double value, const char* field) {
  if (!std::isfinite(value) || value <= 0.0)
    throw std::invalid_argument(std::string("perception adaptation: ") + field + " must be finite and > 0 (got " +
                                std::to_string(value) + ")");
}

void require_non_negative(double value, const char* what) {
  if (!std::isfinite(value) || value < 0.0)
    throw std::invalid_argument(std::string("perception adaptation: ") + what + " must be finite and >= 0 (got " +
                                std::to_string(value) + ")");
}

}  // namespace

void validate_adaptation_time_constants(const AdaptationTimeConstants& constants) {
  require_positive(constants.rod_time_constant_s, "rod_time_constant_s");
  require_positive(constants.cone_time_constant_s, "cone_time_constant_s");
  require_positive(constants.rod_half_sensitivity_cd_m2, "rod_half_sensitivity_cd_m2");
}

TemporalAdaptation::TemporalAdaptation(double initial_adapted_cd_m2, const AdaptationTimeConstants& constants)
    : constants_(constants), adapted_cd_m2_(initial_adapted_cd_m2) {
  validate_adaptation_time_constants(constants);
  require_non_negative(initial_adapted_cd_m2, "the initial adapted luminance (cd/m2)");
}

double TemporalAdaptation::advance(double frame_luminance_cd_m2, double frame_time_s) {
  require_non_negative(frame_luminance_cd_m2, "a frame's adaptation luminance (cd/m2)");
  require_non_negative(frame_time_s, "a frame time (s)");
  const double tau_s = adaptation_time_constant_s(frame_luminance_cd_m2, constants_.rod_time_constant_s,
                                                  constants_.cone_time_constant_s,
                                                  constants_.rod_half_sensitivity_cd_m2);
  adapted_cd_m2_ = adapted_luminance_after_cd_m2(adapted_cd_m2_, frame_luminance_cd_m2, frame_time_s, tau_s);
  return adapted_cd_m2_;
}

double TemporalAdaptation::rod_sensitivity() const {
  return glarelab::rod_sensitivity(adapted_cd_m2_, constants_.rod_half_sensitivity_cd_m2);
}

}  // namespace glarelab
