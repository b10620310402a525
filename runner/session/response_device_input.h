#pragma once
// The response device inside the session loop (docs/DEVICES.md): which presses answer a trial,
// which adjust, and the pause while the device is unplugged. Every press is logged with the
// session-clock stamp of its report read: `button` when it answered, `ignored_button` with the
// reason otherwise, so each recorded response time can be traced to the press that gave it.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "protocols/trial_plan.h"
#include "runner/devices/hid_device.h"

namespace glarelab {

class DisplayBackend;
class ResultStore;
class ResponseDeviceSession;
class SessionClock;

// What one press of a poll does to a trial.
struct PressDecision {
  ButtonEvent press;
  std::optional<std::string> response;  // the answer it gives (the first allowed press at or after onset)
  std::string ignored_because;          // otherwise: why it is not recorded
};

// The presses of one poll, in order. A press stamped before `onset_s` was made before the trial
// was shown; one whose name is not an allowed response (response_for_key: the name itself, or the
// digit of its position) is no answer; after the first answer (or when `answered` already) the
// rest came after the answer. Only the first answering press carries a response.
std::vector<PressDecision> decide_presses(const std::vector<ButtonEvent>& presses,
                                          const std::vector<std::string>& allowed_responses, double onset_s,
                                          bool answered);

// An input of the adjustment phase: a key or wheel click (stamped when polled) or a button press
// (stamped when its report was read).
struct TimedInput {
  enum class Source { key, wheel, button };
  Source source = Source::key;
  std::string name;
  bool shift = false;
  double session_time_s = 0.0;
};

// The text shown while the device is unplugged.
inline constexpr const char* kDeviceUnpluggedMessage = "Response device unplugged - reconnect it to continue";

class ResponseDeviceInput {
 public:
  ResponseDeviceInput(ResponseDeviceSession& device, ResultStore& store, std::int64_t session_id);

  // The answer among the presses since the last poll, or nothing; every press is logged. Response
  // times count from `onset_s`; presses before `answers_from_s` (the onset, or a sequential
  // trial's second interval) do not answer. `*unplugged` is set when the device is gone and no
  // press answered: the caller pauses.
  std::optional<Response> answer(const TrialPlan& plan, double onset_s, double answers_from_s, bool* unplugged);
  // Presses on an instruction or break screen: any button continues it once `long_enough` (a button
  // box may have no Space); earlier presses are logged as ignored. `*unplugged` as above.
  bool continues_screen(const TrialPlan& plan, const std::string& screen_kind, bool long_enough, bool* unplugged);
  // The presses of the adjustment phase, those before onset logged as ignored; `*unplugged` as above.
  std::vector<TimedInput> adjustment_presses(const TrialPlan& plan, double onset_s, bool* unplugged);
  // An input that did nothing in the adjustment phase, logged as ignored_key or ignored_button.
  void log_not_adjusting(const TrialPlan& plan, const TimedInput& input);

  struct PauseResult {
    bool resumed = false;      // reconnected: the trial is to be re-run from its onset
    std::string abort_reason;  // otherwise why the session ends (Escape, window closed, Ctrl-C)
  };
  // The pause after an unplug: `show_frame` draws the message and presents one frame (it paces
  // the loop); `message_pixels` reads back how many pixels of the message are lit (logged, so the
  // database says the message was on screen). Reconnection is tried with backoff each frame;
  // Escape, closing the window or Ctrl-C end the pause and the session. Logged as
  // device_unplugged, then device_reconnected (with the pause duration) or device_pause_aborted.
  PauseResult pause(int trial_index, DisplayBackend& display, const SessionClock& clock,
                    const std::function<void()>& show_frame, const std::function<long()>& message_pixels);

 private:
  void log_press(const TrialPlan& plan, const PressDecision& decision);

  ResponseDeviceSession& device_;
  ResultStore& store_;
  std::int64_t session_id_;
};

}  // namespace glarelab
