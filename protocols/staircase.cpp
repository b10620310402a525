// Up/down staircases following PsychoPy's StairHandler step for step (see staircase.h).
#include "protocols/staircase.h"

#include <algorithm>
#include <cmath>

#include "core/random.h"

namespace glarelab {

StepType parse_step_type(const std::string& name) {
  if (name == "db") return StepType::db;
  if (name == "log") return StepType::log;
  if (name == "lin") return StepType::lin;
  throw std::invalid_argument("unknown step type '" + name + "' (choose 'db', 'log' or 'lin')");
}

std::string to_string(StepType type) {
  switch (type) {
    case StepType::db: return "db";
    case StepType::log: return "log";
    case StepType::lin: return "lin";
  }
  return "db";
}

void validate_staircase_spec(const StaircaseSpec& spec) {
  const std::string where = "staircase '" + spec.name + "': ";
  if (spec.step_sizes.empty()) throw std::invalid_argument(where + "step_sizes must not be empty");
  for (double s : spec.step_sizes)
    if (!(s > 0.0) || !std::isfinite(s)) throw std::invalid_argument(where + "step sizes must be finite and > 0");
  if (spec.n_reversals < static_cast<int>(spec.step_sizes.size())) {
    throw std::invalid_argument(where + "n_reversals (" + std::to_string(spec.n_reversals) + ") is smaller than the " +
                                std::to_string(spec.step_sizes.size()) +
                                " step sizes: the later step sizes would never be used");
  }
  if (spec.n_up < 1 || spec.n_down < 1) throw std::invalid_argument(where + "n_up and n_down must be >= 1");
  if (spec.n_trials < 0) throw std::invalid_argument(where + "n_trials must be >= 0");
  if (spec.step_type != StepType::lin && !(spec.start_value > 0.0))
    throw std::invalid_argument(where + "db and log steps need a start value > 0");
  if (spec.min_value && spec.max_value && *spec.min_value > *spec.max_value)
    throw std::invalid_argument(where + "min_value is above max_value");
}

Staircase::Staircase(StaircaseSpec spec)
    : spec_(std::move(spec)), next_intensity_(spec_.start_value), step_size_(0.0) {
  validate_staircase_spec(spec_);
  step_size_ = spec_.step_sizes.front();
}

// _intensityInc: step, then clamp to max_value only.
void Staircase::step_up() {
  switch (spec_.step_type) {
    case StepType::db: next_intensity_ *= std::pow(10.0, step_size_ / 20.0); break;
    case StepType::log: next_intensity_ *= std::pow(10.0, step_size_); break;
    case StepType::lin: next_intensity_ += step_size_; break;
  }
  if (spec_.max_value && next_intensity_ > *spec_.max_value) next_intensity_ = *spec_.max_value;
  run_counter_ = 0;
}

// _intensityDec: step, then clamp to min_value only.
void Staircase::step_down() {
  switch (spec_.step_type) {
    case StepType::db: next_intensity_ /= std::pow(10.0, step_size_ / 20.0); break;
    case StepType::log: next_intensity_ /= std::pow(10.0, step_size_); break;
    case StepType::lin: next_intensity_ -= step_size_; break;
  }
  run_counter_ = 0;
  if (spec_.min_value && next_intensity_ < *spec_.min_value) next_intensity_ = *spec_.min_value;
}

bool Staircase::add_response(bool correct) {
  if (finished_) throw std::logic_error("staircase '" + spec_.name + "' is finished");
  intensities_.push_back(next_intensity_);
  responses_.push_back(correct);
  const int trial = trial_count() - 1;

  // addResponse: extend the run when this response repeats the previous one, else restart it.
  const bool on_run = responses_.size() > 1 && responses_[responses_.size() - 2] == correct;
  if (correct)
    run_counter_ = on_run ? run_counter_ + 1 : 1;
  else
    run_counter_ = on_run ? run_counter_ - 1 : -1;

  // calculateNextIntensity: direction and reversal.
  bool reversal = false;
  const bool initial_phase = reversal_intensities_.empty() && spec_.apply_initial_rule;
  if (initial_phase) {
    if (correct) {
      reversal = direction_ == Direction::up;
      direction_ = Direction::down;
    } else {
      reversal = direction_ == Direction::down;
      direction_ = Direction::up;
    }
  } else if (run_counter_ >= spec_.n_down) {
    reversal = direction_ == Direction::up;
    direction_ = Direction::down;
  } else if (run_counter_ <= -spec_.n_up) {
    reversal = direction_ == Direction::down;
    direction_ = Direction::up;
  }

  if (reversal) {
    reversal_trials_.push_back(trial);
    if (initial_phase) initial_rule_step_ = true;
    reversal_intensities_.push_back(intensities_.back());
  }
  if (static_cast<int>(reversal_intensities_.size()) >= spec_.n_reversals && trial_count() >= spec_.n_trials)
    finished_ = true;

  // The step size advances at a reversal, before the step.
  if (reversal && spec_.step_sizes.size() > 1) {
    const std::size_t index = std::min(reversal_intensities_.size(), spec_.step_sizes.size() - 1);
    step_size_ = spec_.step_sizes[index];
  }

  if ((reversal_intensities_.empty() || initial_rule_step_) && spec_.apply_initial_rule) {
    initial_rule_step_ = false;
    if (correct)
      step_down();
    else
      step_up();
  } else if (run_counter_ >= spec_.n_down) {
    step_down();
  } else if (run_counter_ <= -spec_.n_up) {
    step_up();
  }
  return reversal;
}

double Staircase::mean_of_last_reversals(int k) const {
  if (reversal_intensities_.empty()) throw std::logic_error("staircase '" + spec_.name + "' has no reversals yet");
  const std::size_t n = std::min(reversal_intensities_.size(), static_cast<std::size_t>(std::max(k, 1)));
  double sum = 0.0;
  for (std::size_t i = reversal_intensities_.size() - n; i < reversal_intensities_.size(); ++i)
    sum += reversal_intensities_[i];
  return sum / static_cast<double>(n);
}

InterleavedStaircases::InterleavedStaircases(std::vector<StaircaseSpec> specs, std::uint64_t seed) : seed_(seed) {
  if (specs.empty()) throw std::invalid_argument("interleaved staircases: at least one staircase is required");
  for (auto& spec : specs) staircases_.emplace_back(std::move(spec));
}

bool InterleavedStaircases::finished() const {
  return std::all_of(staircases_.begin(), staircases_.end(), [](const Staircase& s) { return s.finished(); });
}

std::optional<std::size_t> InterleavedStaircases::next() {
  while (!finished()) {
    if (pass_remaining_.empty()) {
      // A new pass: every staircase, in a freshly shuffled order (MultiStairHandler._startNewPass).
      for (std::size_t i = 0; i < staircases_.size(); ++i) pass_remaining_.push_back(i);
      const CounterRandom random(seed_, RandomStream::staircase);
      shuffle_in_place(pass_remaining_, random, pass_ * staircases_.size());
      ++pass_;
    }
    const std::size_t candidate = pass_remaining_.front();
    pass_remaining_.erase(pass_remaining_.begin());
    if (!staircases_[candidate].finished()) return candidate;
  }
  return std::nullopt;
}

}  // namespace glarelab
