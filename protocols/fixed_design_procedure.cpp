#include "protocols/fixed_design_procedure.h"

#include <algorithm>
#include <stdexcept>

namespace glarelab {

FixedDesignProcedure::FixedDesignProcedure(std::vector<TrialPlan> trials, Scorer scorer)
    : trials_(std::move(trials)), scorer_(std::move(scorer)) {}

TrialPlan FixedDesignProcedure::next_trial() {
  if (finished()) throw std::logic_error("procedure: no trials left in the design");
  return trials_[next_];
}

std::optional<TrialPlan> FixedDesignProcedure::peek_following_trial() const {
  if (next_ + 1 >= trials_.size()) return std::nullopt;
  return trials_[next_ + 1];
}

TrialOutcome FixedDesignProcedure::record_response(const TrialPlan& plan, const Response& response) {
  if (finished() || plan.trial_index != trials_[next_].trial_index) {
    throw std::logic_error("procedure: response to trial " + std::to_string(plan.trial_index) +
                           " is not for the trial planned next");
  }
  const TrialOutcome outcome = scorer_(plan, response);
  const auto& allowed = plan.allowed_responses;
  // Only an answer or a timeout (no answer within the response window, recorded unscored) moves
  // the design on; "abort" leaves the trial to be shown again.
  const bool answered = allowed.empty() ? response.value != "abort"
                                        : std::find(allowed.begin(), allowed.end(), response.value) != allowed.end() ||
                                              response.value == kTimeoutResponse;
  if (answered) ++next_;
  return outcome;
}

}  // namespace glarelab
