#include "runner/session/controller_answers.h"

#include "runner/display/display_backend.h"
#include "runner/session/response_device_input.h"
#include "runner/store/result_store.h"

namespace glarelab {
namespace {

std::string trial_text(int trial_index) { return "trial " + std::to_string(trial_index) + ": "; }

}  // namespace

std::unique_ptr<ControllerAnswers> ControllerAnswers::of_display(DisplayBackend& display, const SessionClock& clock,
                                                                 ResultStore& store, std::int64_t session_id) {
  auto* source = dynamic_cast<ControllerPressSource*>(&display);
  const auto* predicted = dynamic_cast<const PredictedFlipClock*>(&clock);
  if (source == nullptr || predicted == nullptr) return nullptr;
  return std::make_unique<ControllerAnswers>(*source, *predicted, store, session_id);
}

ControllerAnswers::ControllerAnswers(ControllerPressSource& source, const PredictedFlipClock& clock, ResultStore& store,
                                     std::int64_t session_id)
    : source_(source), clock_(clock), store_(store), session_id_(session_id) {}

std::vector<ButtonEvent> ControllerAnswers::take(std::vector<std::string>& buttons) {
  std::vector<ButtonEvent> presses;
  for (const ControllerPress& press : source_.take_controller_presses()) {
    // The position as the digit key that gives the same answer (keyboard_responses.h).
    presses.push_back({std::to_string(press.answer_position), true, clock_.session_s(press.pressed)});
    buttons.push_back(press.button);
  }
  return presses;
}

std::optional<Response> ControllerAnswers::answer(const TrialPlan& plan, double onset_s, double answers_from_s,
                                                  bool answered) {
  std::vector<std::string> buttons;
  const std::vector<PressDecision> decisions =
      decide_presses(take(buttons), plan.allowed_responses, answers_from_s, answered);
  std::optional<Response> answer;
  for (std::size_t i = 0; i < decisions.size(); ++i) {
    const PressDecision& decision = decisions[i];
    const std::string button = "controller '" + buttons[i] + "' ";
    if (decision.response) {
      store_.log_event(session_id_, decision.press.session_time_s, "controller",
                       trial_text(plan.trial_index) + button + "answered '" + *decision.response + "'");
      answer = Response{*decision.response, decision.press.session_time_s - onset_s};
    } else {
      store_.log_event(session_id_, decision.press.session_time_s, "ignored_controller",
                       trial_text(plan.trial_index) + button + decision.ignored_because);
    }
  }
  return answer;
}

bool ControllerAnswers::continues_screen(const TrialPlan& plan, const std::string& screen_kind, double shown_from_s,
                                         bool long_enough) {
  std::vector<std::string> buttons;
  const std::vector<ButtonEvent> presses = take(buttons);
  bool continued = false;
  for (std::size_t i = 0; i < presses.size(); ++i) {
    const std::string button =
        trial_text(plan.trial_index) + screen_kind + " screen: controller '" + buttons[i] + "' ";
    const double at_s = presses[i].session_time_s;
    if (at_s < shown_from_s)
      store_.log_event(session_id_, at_s, "ignored_controller", button + "pressed before the screen was shown");
    else if (!long_enough)
      store_.log_event(session_id_, at_s, "ignored_controller", button + "before the screen's minimum duration");
    else if (continued)
      store_.log_event(session_id_, at_s, "ignored_controller", button + "came after another continued");
    else {
      continued = true;
      store_.log_event(session_id_, at_s, "controller", button + "continued");
    }
  }
  return continued;
}

}  // namespace glarelab
