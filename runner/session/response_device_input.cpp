#include "runner/session/response_device_input.h"

#include <cstdio>

#include "core/clock.h"
#include "runner/display/display_backend.h"
#include "runner/session/interrupt.h"
#include "runner/session/keyboard_responses.h"
#include "runner/session/response_device_session.h"
#include "runner/store/result_store.h"

namespace glarelab {
namespace {

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", seconds);
  return text;
}

std::string trial_text(int trial_index) { return "trial " + std::to_string(trial_index) + ": "; }

}  // namespace

std::vector<PressDecision> decide_presses(const std::vector<ButtonEvent>& presses,
                                          const std::vector<std::string>& allowed_responses, double onset_s,
                                          bool answered) {
  std::vector<PressDecision> decisions;
  for (const ButtonEvent& press : presses) {
    PressDecision decision{press, std::nullopt, ""};
    const std::optional<std::string> response = response_for_key(press.response, allowed_responses);
    if (press.session_time_s < onset_s)
      decision.ignored_because = "pressed before onset";
    else if (!response)
      decision.ignored_because = "is not a response";
    else if (answered)
      decision.ignored_because = "came after the answer";
    else {
      decision.response = response;
      answered = true;
    }
    decisions.push_back(std::move(decision));
  }
  return decisions;
}

ResponseDeviceInput::ResponseDeviceInput(ResponseDeviceSession& device, ResultStore& store, std::int64_t session_id)
    : device_(device), store_(store), session_id_(session_id) {}

void ResponseDeviceInput::log_press(const TrialPlan& plan, const PressDecision& decision) {
  const std::string button = "button '" + decision.press.response + "' ";
  if (decision.response)
    store_.log_event(session_id_, decision.press.session_time_s, "button",
                     trial_text(plan.trial_index) + button + "answered '" + *decision.response + "'");
  else
    store_.log_event(session_id_, decision.press.session_time_s, "ignored_button",
                     trial_text(plan.trial_index) + button + decision.ignored_because);
}

std::optional<Response> ResponseDeviceInput::answer(const TrialPlan& plan, double onset_s, double answers_from_s,
                                                    bool* unplugged) {
  // Gone is read before the presses: the reader queues everything it read before it stops.
  const bool gone = device_.unplugged();
  std::optional<Response> answer;
  for (const PressDecision& decision :
       decide_presses(device_.take_presses(), plan.allowed_responses, answers_from_s, false)) {
    log_press(plan, decision);
    if (decision.response) answer = Response{*decision.response, decision.press.session_time_s - onset_s};
  }
  *unplugged = gone && !answer;
  return answer;
}

bool ResponseDeviceInput::continues_screen(const TrialPlan& plan, const std::string& screen_kind, bool long_enough,
                                           bool* unplugged) {
  const bool gone = device_.unplugged();
  bool continued = false;
  for (const ButtonEvent& press : device_.take_presses()) {
    const std::string button = trial_text(plan.trial_index) + screen_kind + " screen: button '" + press.response + "' ";
    if (long_enough && !continued) {
      continued = true;
      store_.log_event(session_id_, press.session_time_s, "button", button + "continued");
    } else {
      store_.log_event(session_id_, press.session_time_s, "ignored_button",
                       button + (continued ? "came after another continued" : "before the screen's minimum duration"));
    }
  }
  *unplugged = gone && !continued;
  return continued;
}

std::vector<TimedInput> ResponseDeviceInput::adjustment_presses(const TrialPlan& plan, double onset_s,
                                                                bool* unplugged) {
  const bool gone = device_.unplugged();
  std::vector<TimedInput> inputs;
  for (const ButtonEvent& press : device_.take_presses()) {
    if (press.session_time_s < onset_s) {
      log_press(plan, {press, std::nullopt, "pressed before onset"});
      continue;
    }
    inputs.push_back({TimedInput::Source::button, press.response, false, press.session_time_s});
  }
  *unplugged = gone;
  return inputs;
}

void ResponseDeviceInput::log_not_adjusting(const TrialPlan& plan, const TimedInput& input) {
  const bool button = input.source == TimedInput::Source::button;
  store_.log_event(session_id_, input.session_time_s, button ? "ignored_button" : "ignored_key",
                   trial_text(plan.trial_index) + (button ? "button '" : "key '") + input.name + "' does not adjust");
}

ResponseDeviceInput::PauseResult ResponseDeviceInput::pause(int trial_index, DisplayBackend& display,
                                                            const SessionClock& clock,
                                                            const std::function<void()>& show_frame,
                                                            const std::function<long()>& message_pixels) {
  const double start_s = clock.now_s();
  device_.begin_reconnecting(start_s);
  show_frame();
  store_.log_event(session_id_, start_s, "device_unplugged",
                   trial_text(trial_index) + device_.description() + " unplugged; session paused with '" +
                       kDeviceUnpluggedMessage + "' on screen (" + std::to_string(message_pixels()) +
                       " pixels of text lit); reopening it every 0.1 s, doubling to 2 s");
  const auto end = [&](const std::string& reason) {
    const double paused_s = clock.now_s() - start_s;
    device_.note_pause(paused_s);
    store_.log_event(session_id_, clock.now_s(), "device_pause_aborted",
                     trial_text(trial_index) + reason + " after " + seconds_text(paused_s) + " s paused");
    return PauseResult{false, reason + " while the response device was unplugged"};
  };
  while (true) {
    if (interrupt_requested()) return end("interrupted (Ctrl-C or SIGTERM)");
    if (display.close_requested()) return end(display.close_reason());
    for (const std::string& key : display.poll_keys()) {
      if (key == "escape") return end("Escape pressed");
      store_.log_event(session_id_, clock.now_s(), "ignored_key",
                       trial_text(trial_index) + "key '" + key + "' pressed during the device pause");
    }
    if (device_.try_reconnect(clock.now_s())) {
      const double paused_s = clock.now_s() - start_s;
      device_.note_pause(paused_s);
      store_.log_event(session_id_, clock.now_s(), "device_reconnected",
                       trial_text(trial_index) + device_.description() + " reconnected after " +
                           seconds_text(paused_s) + " s paused (" + std::to_string(device_.reconnect_attempts()) +
                           " attempt(s)); the trial re-runs from its onset");
      return {true, ""};
    }
    show_frame();
  }
}

}  // namespace glarelab
