#pragma once
// Adaptive up/down staircases with the semantics of PsychoPy's StairHandler
// (psychopy/data/staircase.py: addResponse, calculateNextIntensity, _intensityInc,
// _intensityDec), because labs compare their thresholds against it:
// - step types: db (x multiplied or divided by 10^(s/20)), log (by 10^s), lin (x plus or minus s);
// - with apply_initial_rule, 1-up/1-down until the first reversal; the trial that causes that
//   reversal still steps by the 1-up/1-down rule; n-up/m-down afterwards;
// - at each reversal the step size advances to the next in the list before stepping; the last
//   size is reused once the list is exhausted;
// - a signed run counter (+ correct, - incorrect) restarts after every step;
// - reversals record the staircase's own trial index and the intensity shown on that trial;
// - finished once both n_reversals reversals and n_trials trials are reached;
// - min_value clamps only decrements and max_value only increments; the clamped value is the
//   base of later steps.
// One difference: PsychoPy silently raises nReversals to the length of the step list; here a
// shorter reversal count is an error (the experimenter asked for two things that disagree).
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace glarelab {

enum class StepType { db, log, lin };

StepType parse_step_type(const std::string& name);  // "db" | "log" | "lin"; std::invalid_argument otherwise
std::string to_string(StepType type);

struct StaircaseSpec {
  std::string name = "staircase";
  double start_value = 1.0;
  std::vector<double> step_sizes = {4.0};  // in units of step_type
  StepType step_type = StepType::db;
  int n_reversals = 1;  // minimum reversals before finishing; >= step_sizes.size()
  int n_trials = 0;     // minimum trials before finishing
  int n_up = 1;         // consecutive incorrect responses before the intensity goes up
  int n_down = 3;       // consecutive correct responses before the intensity goes down
  bool apply_initial_rule = true;
  std::optional<double> min_value;
  std::optional<double> max_value;
};

// Throws std::invalid_argument naming the rule broken (empty or non-positive step sizes, fewer
// reversals than step sizes, n_up/n_down < 1, db/log with a start value <= 0, min > max).
void validate_staircase_spec(const StaircaseSpec& spec);

class Staircase {
 public:
  explicit Staircase(StaircaseSpec spec);

  const StaircaseSpec& spec() const { return spec_; }
  bool finished() const { return finished_; }
  // The intensity the next trial shows.
  double next_intensity() const { return next_intensity_; }
  // Records the response to a trial shown at next_intensity(); returns whether it was a reversal.
  // Throws std::logic_error once finished.
  bool add_response(bool correct);

  int trial_count() const { return static_cast<int>(intensities_.size()); }
  const std::vector<double>& intensities() const { return intensities_; }  // shown, per trial
  const std::vector<bool>& responses() const { return responses_; }
  const std::vector<int>& reversal_trials() const { return reversal_trials_; }  // 0-based, own trials
  const std::vector<double>& reversal_intensities() const { return reversal_intensities_; }
  double current_step_size() const { return step_size_; }

  // Threshold estimate: arithmetic mean of the intensities at the last k reversals (all of them
  // when fewer). std::logic_error without reversals.
  double mean_of_last_reversals(int k) const;

 private:
  enum class Direction { start, up, down };
  void step_up();
  void step_down();

  StaircaseSpec spec_;
  double next_intensity_;
  double step_size_;
  int run_counter_ = 0;  // PsychoPy's correctCounter
  Direction direction_ = Direction::start;
  bool initial_rule_step_ = false;  // PsychoPy's initialRule flag
  bool finished_ = false;
  std::vector<double> intensities_;
  std::vector<bool> responses_;
  std::vector<int> reversal_trials_;
  std::vector<double> reversal_intensities_;
};

// Several staircases interleaved like PsychoPy's MultiStairHandler (type 'random'): trials run in
// passes; each pass visits every unfinished staircase once, in an order shuffled at the start of
// the pass with (seed, RandomStream::staircase), so a seed reproduces the order.
class InterleavedStaircases {
 public:
  InterleavedStaircases(std::vector<StaircaseSpec> specs, std::uint64_t seed);

  // Index of the staircase that runs the next trial; empty once all are finished.
  std::optional<std::size_t> next();
  Staircase& at(std::size_t index) { return staircases_.at(index); }
  const Staircase& at(std::size_t index) const { return staircases_.at(index); }
  std::size_t size() const { return staircases_.size(); }
  bool finished() const;

 private:
  std::vector<Staircase> staircases_;
  std::uint64_t seed_;
  std::uint64_t pass_ = 0;
  std::vector<std::size_t> pass_remaining_;
};

}  // namespace glarelab
