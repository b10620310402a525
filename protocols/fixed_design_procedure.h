#pragma once
// A procedure whose trials are all decided before the session (forced choice, ratings): it hands
// them out in order and scores each response with the design's scoring rule.
#include <functional>
#include <optional>
#include <vector>

#include "protocols/procedure.h"

namespace glarelab {

class FixedDesignProcedure : public Procedure {
 public:
  using Scorer = std::function<TrialOutcome(const TrialPlan&, const Response&)>;
  FixedDesignProcedure(std::vector<TrialPlan> trials, Scorer scorer);

  bool finished() const override { return next_ >= trials_.size(); }
  TrialPlan next_trial() override;
  // The design's next row: every trial is decided before the session. An answer outside the
  // allowed set does not advance the design, so the trial shown after it may be this one again;
  // the session compares the peeked plan with the one it gets.
  std::optional<TrialPlan> peek_following_trial() const override;
  TrialOutcome record_response(const TrialPlan& plan, const Response& response) override;
  int planned_trials() const override { return static_cast<int>(trials_.size()); }

 private:
  std::vector<TrialPlan> trials_;
  Scorer scorer_;
  std::size_t next_ = 0;
};

}  // namespace glarelab
