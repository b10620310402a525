// The one place a tracker source is chosen from a --tracker value.
#include <cstdlib>

#include "runner/tracker/pupil_labs_client.h"
#include "runner/tracker/replay_tracker.h"
#include "runner/tracker/simulated_tracker.h"
#include "runner/tracker/tracker_source.h"

namespace glarelab {

std::unique_ptr<TrackerSource> make_tracker_source(const std::string& spec, std::uint64_t seed) {
  if (spec == "none") return nullptr;
  if (spec == "simulated") return std::make_unique<SimulatedTracker>(seed);
  if (spec.starts_with("pupil-labs://")) return std::make_unique<PupilLabsClient>(parse_pupil_labs_address(spec));
  if (spec.starts_with("replay:")) {
    const std::string target = spec.substr(7);
    const auto hash = target.rfind('#');
    if (hash != std::string::npos) {
      const std::string file = target.substr(0, hash);
      const std::string id_text = target.substr(hash + 1);
      char* end = nullptr;
      const long long session_id = std::strtoll(id_text.c_str(), &end, 10);
      if (id_text.empty() || *end != '\0' || session_id <= 0)
        throw TrackerError("--tracker " + spec + ": '" + id_text + "' is not a session id (replay:FILE.db#SESSION)");
      return std::make_unique<ReplayTracker>(read_tracker_database(file, session_id),
                                             file + " session " + id_text);
    }
    return std::make_unique<ReplayTracker>(read_tracker_csv(target), target);
  }
  throw TrackerError("--tracker " + spec +
                     ": unknown tracker (choose none, simulated, replay:FILE.csv, replay:FILE.db#SESSION or "
                     "pupil-labs://HOST:PORT)");
}

}  // namespace glarelab
