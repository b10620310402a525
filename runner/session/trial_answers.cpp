// Collecting a trial's answer: keys, response-device and controller presses while answers count (the first
// allowed one answers, the rest are logged), keys outside that period, Escape, Ctrl-C and a closed
// window.
#include <optional>
#include <string>
#include <vector>

#include "runner/session/interrupt.h"
#include "runner/session/keyboard_responses.h"
#include "runner/session/session_loop.h"

namespace glarelab {

void SessionLoop::check_interrupt() {
  if (interrupt_requested()) {
    aborted_ = true;
    abort_reason_ = "interrupted (Ctrl-C or SIGTERM)";
  } else if (!aborted_ && display_.close_requested()) {
    // Whoever answers: a simulated or scripted observer's session ends too when the window is
    // closed or a headset's runtime ends its session (runner/display/openxr_display.h).
    aborted_ = true;
    abort_reason_ = display_.close_reason();
  }
}

void SessionLoop::ignore_keys(const TrialPlan& plan, const std::string& why) {
  check_interrupt();
  if (aborted_) return;
  if (display_.close_requested()) {
    aborted_ = true;
    abort_reason_ = display_.close_reason();
    return;
  }
  for (const std::string& key : display_.poll_keys()) {
    if (key == "escape") {
      aborted_ = true;
      abort_reason_ = "Escape pressed";
      return;
    }
    store_.log_event(session_id_, clock_.now_s(), "ignored_key",
                     "trial " + std::to_string(plan.trial_index) + ": key '" + key + "' " + why);
  }
}

std::optional<Response> SessionLoop::poll_keyboard(const TrialPlan& plan, double onset_s, double answers_from_s) {
  check_interrupt();
  if (aborted_) return std::nullopt;
  if (display_.close_requested()) {
    aborted_ = true;
    abort_reason_ = display_.close_reason();
    return std::nullopt;
  }
  // Every key of the batch is looked at: the first allowed one answers, an Escape anywhere in the
  // batch still ends the session, and the rest are logged, never silently dropped.
  std::optional<Response> answer;
  // Device presses first: they were stamped when read, so before the keys of this poll.
  if (device_ != nullptr) {
    bool unplugged = false;
    answer = device_->answer(plan, onset_s, answers_from_s, &unplugged);
    if (unplugged) pause_for_response_device(plan.trial_index);
    if (aborted_) return std::nullopt;
  }
  // A headset's controllers next: stamped by the runtime when it saw them, before this poll.
  if (controllers_ != nullptr) {
    const std::optional<Response> pressed = controllers_->answer(plan, onset_s, answers_from_s, answer.has_value());
    if (!answer) answer = pressed;
  }
  for (const std::string& key : display_.poll_keys()) {
    const double key_time_s = clock_.now_s();
    if (key == "escape") {
      aborted_ = true;
      abort_reason_ = "Escape pressed";
      return std::nullopt;
    }
    const auto response = response_for_key(key, plan.allowed_responses);
    if (response && !answer) {
      answer = Response{*response, key_time_s - onset_s};
      continue;
    }
    // Outside the allowed set, or after the answer: logged, never recorded as an answer.
    store_.log_event(session_id_, key_time_s, "ignored_key",
                     "trial " + std::to_string(plan.trial_index) + ": key '" + key + "' " +
                         (response ? "came after the answer" : "is not a response"));
  }
  return answer;
}

}  // namespace glarelab
