#pragma once
// A headset's controllers inside the session loop (docs/STEREO.md, "Controllers"): their presses
// answer a trial as the digit keys do (the first allowed response, the second, the third) and
// continue a screen as a response device's buttons do. Every press is logged at the time the runtime
// saw it, on the session clock: `controller` when it answered or continued, `ignored_controller` with
// the reason otherwise, so each response time can be traced to the press that gave it.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "protocols/trial_plan.h"
#include "runner/devices/hid_device.h"
#include "runner/display/controller_presses.h"
#include "runner/display/openxr_clock.h"

namespace glarelab {

class DisplayBackend;
class ResultStore;
class SessionClock;

class ControllerAnswers {
 public:
  // Null unless the display has controllers (ControllerPressSource) and the session's flips are
  // its predicted display times (PredictedFlipClock), the clock the presses are stamped on.
  static std::unique_ptr<ControllerAnswers> of_display(DisplayBackend& display, const SessionClock& clock,
                                                       ResultStore& store, std::int64_t session_id);

  ControllerAnswers(ControllerPressSource& source, const PredictedFlipClock& clock, ResultStore& store,
                    std::int64_t session_id);

  // The answer among the presses since the last call, or nothing; every press is logged. Response
  // times count from `onset_s`; presses before `answers_from_s` do not answer, nor any when
  // `answered` (another input answered in this poll).
  std::optional<Response> answer(const TrialPlan& plan, double onset_s, double answers_from_s, bool answered);
  // Presses on an instruction or break screen shown since `shown_from_s`: any button continues it
  // once `long_enough`; the others are logged as ignored.
  bool continues_screen(const TrialPlan& plan, const std::string& screen_kind, double shown_from_s, bool long_enough);

 private:
  // The presses since the last call, stamped on the session clock; each one's button beside it.
  std::vector<ButtonEvent> take(std::vector<std::string>& buttons);

  ControllerPressSource& source_;
  const PredictedFlipClock& clock_;
  ResultStore& store_;
  std::int64_t session_id_;
};

}  // namespace glarelab
