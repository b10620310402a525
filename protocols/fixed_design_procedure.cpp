#include "protocols/fixed_design_procedure.h"

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace glarelab {

FixedDesignProcedure::FixedDesignProcedure(std::vector<TrialPlan> trials, Scorer scorer)
    : trial_count_(trials.size()), scorer_(std::move(scorer)) {
  auto held = std::make_shared<const std::vector<TrialPlan>>(std::move(trials));
  plan_at_ = [held](std::size_t index) { return (*held)[index]; };
}

FixedDesignProcedure::FixedDesignProcedure(std::size_t trial_count, PlanAt plan_at, Scorer scorer)
    : trial_count_(trial_count), plan_at_(std::move(plan_at)), scorer_(std::move(scorer)) {}

const TrialPlan& FixedDesignProcedure::planned_next() {
  if (!next_plan_) next_plan_ = plan_at_(next_);
  return *next_plan_;
}

TrialPlan FixedDesignProcedure::next_trial() {
  if (finished()) throw std::logic_error("procedure: no trials left in the design");
  return planned_next();
}

std::optional<TrialPlan> FixedDesignProcedure::peek_following_trial(std::size_t later) const {
  if (later >= trial_count_ || next_ + 1 + later >= trial_count_) return std::nullopt;
  return plan_at_(next_ + 1 + later);
}

TrialOutcome FixedDesignProcedure::record_response(const TrialPlan& plan, const Response& response) {
  if (finished() || plan.trial_index != planned_next().trial_index) {
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
  if (answered) {
    ++next_;
    next_plan_.reset();
  }
  return outcome;
}

}  // namespace glarelab
