#pragma once
// Observers answer trials. Non-interactive ones (simulated, scripted) answer at once from the
// trial plan; the keyboard observer is interactive and lives in the runner's event loop.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/errors.h"
#include "protocols/experiment.h"
#include "protocols/trial_plan.h"

namespace glarelab {

class Observer {
 public:
  virtual ~Observer() = default;
  // "simulated", "script:/abs/path" ...: recorded in sessions.observer.
  virtual std::string description() const = 0;
  // Answer for this trial. Deterministic in (seed, trial_index) for simulated observers and in
  // trial_index for scripts, so a resumed session answers exactly as an uninterrupted one.
  virtual Response respond(const TrialPlan& plan) = 0;
};

// Seeded psychometric observer: picks the position with the brighter source with probability
// 0.5 + (0.5 - lapse) * (1 - exp(-(d / threshold_log10)^slope)), d = |log10(L_left / L_right)|
// (2-AFC Weibull; see simulated_observer.cpp).
std::unique_ptr<Observer> make_simulated_observer(const SimulatedObserverSpec& spec, std::uint64_t seed);

// One response per line, consumed in trial order: an allowed response name ("left"), "1"/"0" for
// correct/incorrect, or a number. Blank lines and lines starting with '#' are skipped. With
// `timeout_allowed` (the experiment has a response window) "timeout" stands for no answer in time.
// Throws ConfigError (file:line) for a missing file; running out of lines is an error at the
// trial that needs one, naming the file and the number of responses it held.
std::unique_ptr<Observer> make_script_observer(const std::string& path, bool timeout_allowed = false);

}  // namespace glarelab
