#pragma once
// A procedure whose trials are all decided before the session (forced choice, ratings): it hands
// them out in order and scores each response with the design's scoring rule.
#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "protocols/procedure.h"

namespace glarelab {

class FixedDesignProcedure : public Procedure {
 public:
  using Scorer = std::function<TrialOutcome(const TrialPlan&, const Response&)>;
  // Makes the plan of trial `index` of the design; the same plan every time it is asked.
  using PlanAt = std::function<TrialPlan(std::size_t index)>;
  FixedDesignProcedure(std::vector<TrialPlan> trials, Scorer scorer);
  // A design of `trial_count` trials whose plans are made one at a time, when the session reaches
  // them: a design of millions of trials holds its order, not millions of plans.
  FixedDesignProcedure(std::size_t trial_count, PlanAt plan_at, Scorer scorer);

  bool finished() const override { return next_ >= trial_count_; }
  TrialPlan next_trial() override;
  // The design's next rows: every trial is decided before the session. An answer outside the
  // allowed set does not advance the design, so the trial shown after it may be this one again;
  // the session compares the peeked plan with the one it gets.
  std::optional<TrialPlan> peek_following_trial(std::size_t later = 0) const override;
  TrialOutcome record_response(const TrialPlan& plan, const Response& response) override;
  int planned_trials() const override { return static_cast<int>(trial_count_); }

 private:
  const TrialPlan& planned_next();  // the plan of trial next_, made once

  std::size_t trial_count_ = 0;
  PlanAt plan_at_;
  Scorer scorer_;
  std::size_t next_ = 0;
  std::optional<TrialPlan> next_plan_;  // the plan of trial next_ once made
};

}  // namespace glarelab
