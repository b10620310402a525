#pragma once
// A straylight measurement in a session (docs/STRAYLIGHT.md): the images its frames are drawn
// from, and the simulated participant answering through the physics of the display and its own
// CIE 146 eye.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "protocols/experiment.h"
#include "protocols/observer.h"
#include "protocols/straylight_model.h"
#include "protocols/straylight_observer.h"
#include "runner/store/result_store.h"

namespace glarelab {

// The measurement's stimulus as three images of one size, centred on the display (their centre is
// the display's, where the participant fixates), each 1 where it is lit and 0 elsewhere: the ring
// (ring_inner_deg <= angle < ring_outer_deg) and the test field's left and right halves
// (angle < test_field_radius_deg; an odd width leaves the middle column dark between them).
// Angles are visual angles from the eye, atan(distance on the screen / viewing distance), so the
// ring's edges are where the model puts them whatever the display's geometry.
struct StraylightImages {
  ImageRGBA ring, left_half, right_half;
};
StraylightImages straylight_images(const DisplaySpec& display, const StraylightSpec& spec);

// Whether stimulus frame `frame_in_interval` shows the ring (the first half of each cycle of
// `frames_per_cycle` frames) or the compensation light (the second half): the square wave and its
// counterphase (runner/session/straylight_trial.cpp draws it).
bool straylight_ring_on(int frame_in_interval, int frames_per_cycle);

// The simulated participant's eye: the CIE 146 glare spread function of [observer] age_years and
// pigmentation, or with `[glare] straylight` the function of that straylight at 7 degrees
// (glare/analytic/ring_straylight.h), integrated over the ring; the model's noise and lapses.
StraylightObserverEye simulated_straylight_eye(const Experiment& experiment);
// log10 of that eye's straylight as the ring measures it (the ring's veil over k L_ring).
double simulated_straylight_log_s(const Experiment& experiment);

// `--observer simulated` for a straylight measurement: simulated_straylight_eye's participant,
// seeded with the experiment's seed.
std::unique_ptr<Observer> make_simulated_straylight_participant(const Experiment& experiment);

// A straylight measurement stored in a results database: its stored trials replayed through the
// procedure of its stored configuration (as `run --resume` replays them), so the estimate is the
// one the answers give, computed the same way wherever it is read.
struct StoredStraylight {
  std::int64_t session_id = 0;
  std::string participant;
  std::string eye;  // "left" or "right"
  std::string status;  // the session's: running, completed, aborted
  double age_years = 0.0;  // [observer] age_years, for the age norm
  int answers = 0;
  StraylightEstimate estimate;
};
// Empty for a session of another procedure or one without answers. StoreError when a stored trial
// is not the one its replay plans (the database does not hold what this procedure stored).
std::optional<StoredStraylight> stored_straylight(const ResultStore& store, std::int64_t session_id);
// The same from a session's row and its trials in trial order, read by any reader; `db_path` names
// the database in errors.
std::optional<StoredStraylight> replay_straylight(const SessionRecord& session, const std::vector<TrialRecord>& trials,
                                                  const std::string& db_path);

// The summary's line: log(s), its ESD and the reliability flag, with the age norm beside them
// (an empty string for a session that measured nothing).
std::string describe_straylight_session(const ResultStore& store, std::int64_t session_id);

// `[glare] straylight = "measured"` (Experiment::straylight_measured): the observer eye's straylight
// set to the estimate of `participant`'s most recent (highest id) completed, reliable straylight
// session in the database at `db_path`, so the session's stored configuration holds the value
// used. Returns what was taken, for the session's 'straylight_measured' event; "" when the key
// does not ask for it. ConfigError at the key when there is no such session, naming the database,
// the participant and the unreliable or unfinished measurements it passed over.
std::string take_measured_straylight(Experiment& experiment, const std::string& db_path, const std::string& participant);

}  // namespace glarelab
