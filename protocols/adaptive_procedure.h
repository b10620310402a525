#pragma once
// Staircases (PsychoPy StairHandler semantics, protocols/staircase.h) and QUEST (Watson & Pelli
// 1983, protocols/quest.h) as a Procedure. Each trial is a forced choice between the condition
// row's "reference" scene and its "comparison" scene, side by side, the comparison scaled so that
// its peak luminance is the trial's intensity (cd/m2; QUEST works on log10 cd/m2). The response is
// correct when it names the brighter source; with equal sources "neither" (3-way, Spencer 1995)
// is correct, and in 2-AFC the comparison's side counts as correct so the track can move on.
// Several tracks interleave like PsychoPy's MultiStairHandler: passes over the unfinished tracks,
// each pass in an order shuffled with (seed, RandomStream::staircase).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "protocols/procedure.h"
#include "protocols/quest.h"
#include "protocols/staircase.h"

namespace glarelab {

class AdaptiveProcedure : public Procedure {
 public:
  AdaptiveProcedure(const Experiment& experiment, const std::map<std::string, double>& source_peak_cd_m2);

  bool finished() const override;
  TrialPlan next_trial() override;
  TrialOutcome record_response(const TrialPlan& plan, const Response& response) override;
  int planned_trials() const override;

  std::size_t track_count() const { return tracks_.size(); }
  const Staircase* staircase(std::size_t track) const;  // null for QUEST tracks
  const Quest* quest(std::size_t track) const;          // null for staircase tracks

 private:
  struct Track {
    std::string name;
    std::size_t row = 0;  // index into experiment_.conditions
    std::optional<Staircase> staircase;
    std::optional<Quest> quest;
    bool finished() const { return staircase ? staircase->finished() : quest->finished(); }
    // The luminance (cd/m2) the comparison shows on the track's next trial.
    double next_luminance_cd_m2() const;
  };
  std::size_t choose_track();

  Experiment experiment_;  // a copy: the procedure may outlive the caller's experiment
  std::map<std::string, double> peak_cd_m2_;
  std::vector<Track> tracks_;
  std::uint64_t pass_ = 0;
  std::vector<std::size_t> pass_remaining_;
  std::optional<std::size_t> current_;  // the track of the trial planned and not yet answered
  int trials_done_ = 0;
};

}  // namespace glarelab
