#pragma once
// Staircases (PsychoPy StairHandler semantics, protocols/staircase.h), QUEST (Watson & Pelli
// 1983, protocols/quest.h) and QUEST+ / Psi (Watson 2017, protocols/quest_plus.h) as a Procedure. Each trial is a forced choice between the condition
// row's "reference" scene and its "comparison" scene, side by side, the comparison scaled so that
// its peak luminance is the trial's intensity (cd/m2; QUEST works on log10 cd/m2). The response is
// correct when it names the brighter source; with equal sources "neither" (3-way, Spencer 1995)
// is correct, and in 2-AFC the comparison's side counts as correct so the track can move on.
// Several tracks interleave like PsychoPy's MultiStairHandler: passes over the unfinished tracks,
// each pass in an order shuffled with (seed, RandomStream::staircase).
// With [[blocks]] (staircase and QUEST) the blocks run one after the other in the participant's
// block order (protocols/block_design.h), each interleaving the tracks of its own rows until they
// all finish, its passes shuffled with the block's seed (block_trial_seed) or kept in track order
// (trial_order = "as_listed").
// With response_rule = "pse" (Spencer et al. 1995, section 4) a staircase track finds the point of
// subjective equality: "comparison brighter" steps the comparison down, "reference brighter" up,
// and "neither" reverses the track's last step (the first "neither" of a track steps toward the
// middle of [min_value, max_value]); trials are unscored. With glare_on = "reference" the row's
// glare is applied to the reference's side only (the sides are drawn per trial, so the glare
// image and the disc swap sides at random).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "protocols/blocked_design.h"
#include "protocols/procedure.h"
#include "protocols/quest.h"
#include "protocols/quest_plus.h"
#include "protocols/staircase.h"

namespace glarelab {

// A QUEST+ track's full stimulus grid: the intensity grid and, for each stimulus column, the
// distinct values of that column over the track's rows (in row order), and the condition row of
// every point of those further dimensions (C order). std::invalid_argument when a row is missing,
// a value is not a number, or a combination is missing or repeated.
struct QuestPlusTrackGrid {
  QuestPlusSpec spec;
  std::vector<std::size_t> rows;  // one per point of stimulus dimensions 1.. (one entry without them)
};
QuestPlusTrackGrid quest_plus_track_grid(const Experiment& experiment, const AdaptiveTrackSpec& track);

// The luminance (cd/m2) of a QUEST+ intensity in its unit ("db_cd_m2": 10^(x / 20);
// "log10_cd_m2": 10^x).
double quest_plus_luminance_cd_m2(const std::string& intensity_unit, double intensity);

class AdaptiveProcedure : public Procedure {
 public:
  AdaptiveProcedure(const Experiment& experiment, const std::map<std::string, double>& source_peak_cd_m2);

  bool finished() const override;
  TrialPlan next_trial() override;
  TrialOutcome record_response(const TrialPlan& plan, const Response& response) override;
  int planned_trials() const override;

  // A preview (glarelab render) of condition row `row`, which a QUEST+ or Psi track may never
  // choose (it picks the row with the intensity): unless a track of that row alone shows it on its
  // first trial, from now on the next trial of a track holding the row shows it at the intensity
  // the track chose, saying so in preview_note(). False when no track shows the row.
  bool show_row_on_its_tracks_next_trial(std::size_t row);
  // What that request changed of the trial planned last, in words; empty when nothing.
  const std::string& preview_note() const { return preview_note_; }

  std::size_t track_count() const { return tracks_.size(); }
  const Staircase* staircase(std::size_t track) const;  // null for QUEST tracks
  const Quest* quest(std::size_t track) const;          // null for staircase tracks
  const QuestPlus* quest_plus(std::size_t track) const;  // null unless QUEST+ / Psi

 private:
  struct Track {
    std::string name;
    std::size_t row = 0;  // index into experiment_.conditions
    std::optional<Staircase> staircase;
    std::optional<Quest> quest;
    std::optional<QuestPlus> quest_plus;
    std::string intensity_unit;              // QUEST+: unit of its intensity grid
    std::vector<std::size_t> quest_plus_rows;  // QUEST+: the row of each point of dimensions 1..
    std::optional<bool> last_pse_step_down;  // PSE rule: the direction of the track's last step
    bool finished() const {
      return staircase ? staircase->finished() : quest ? quest->finished() : quest_plus->finished();
    }
    // The condition row the next trial shows.
    std::size_t next_row() const;
    // The luminance (cd/m2) the comparison shows on the track's next trial.
    double next_luminance_cd_m2() const;
  };
  // The tracks that run together: every track (no blocks) or one block's.
  struct TrackGroup {
    std::vector<std::size_t> tracks;
    std::uint64_t seed = 0;  // of the shuffle of each pass (RandomStream::staircase)
    bool shuffled = true;
    BlockPlacement placement;  // empty without blocks
    std::uint64_t pass = 0;
    std::vector<std::size_t> pass_remaining;
    int trials_done = 0;
  };
  std::size_t choose_track();
  bool group_finished(const TrackGroup& group) const;

  Experiment experiment_;  // a copy: the procedure may outlive the caller's experiment
  std::map<std::string, double> peak_cd_m2_;
  std::vector<Track> tracks_;
  std::vector<TrackGroup> groups_;  // in the order they run
  std::size_t group_ = 0;           // the group running now
  std::optional<std::size_t> current_;  // the track of the trial planned and not yet answered
  std::optional<std::size_t> preview_row_;  // show_row_on_its_tracks_next_trial
  std::string preview_note_;
  int trials_done_ = 0;
};

}  // namespace glarelab
