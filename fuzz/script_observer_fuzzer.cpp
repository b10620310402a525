// Fuzz target: the response script of `--observer script:FILE` (protocols/script_observer.cpp).
// The file is read, then asked for the answers of trials 0, 1, ... under three kinds of trial: a
// two-alternative forced choice with a correct answer, one with equal sources (no correct answer),
// and a procedure without named responses (adjustment). Expected outcomes: ConfigError naming the
// script's line for a response the trial does not allow, and the runtime_error "response script
// ... holds N responses" once the trials outrun the script.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "core/errors.h"
#include "fuzz/fuzz_support.h"
#include "protocols/observer.h"
#include "protocols/trial_plan.h"

namespace {

glarelab::TrialPlan plan_of_kind(int kind, int trial_index) {
  glarelab::TrialPlan plan;
  plan.trial_index = trial_index;
  if (kind == 0) {
    plan.procedure = "forced_choice";
    plan.allowed_responses = {"left", "right"};
    plan.correct_response = "right";
  } else if (kind == 1) {
    plan.procedure = "forced_choice";
    plan.allowed_responses = {"left", "right"};
  } else {
    plan.procedure = "adjustment";
  }
  return plan;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glarelab;
  // The first byte picks whether "timeout" is allowed; the rest is the script.
  const bool timeout_allowed = size > 0 && (data[0] & 1) != 0;
  const std::string path = fuzz::ScratchFolder::instance().write(
      "responses.txt", std::string_view(reinterpret_cast<const char*>(data), size).substr(size > 0 ? 1 : 0));
  const auto observer = make_script_observer(path, timeout_allowed);
  (void)observer->description();
  constexpr int kMaxTrials = 64;  // enough for every short script; long ones are no different
  for (int trial = 0; trial < kMaxTrials; ++trial) {
    try {
      const Response response = observer->respond(plan_of_kind(trial % 3, trial));
      if (response.value.empty()) {
        std::fprintf(stderr, "trial %d answered with an empty response\n", trial);
        std::abort();
      }
    } catch (const ConfigError&) {
      // A response the trial does not allow, named with the script's line: keep asking.
    } catch (const std::runtime_error& error) {
      if (std::string(error.what()).find(" responses; trial ") == std::string::npos) throw;
      break;  // the script has no more answers
    }
  }
  return 0;
}
