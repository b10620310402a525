// The one place a tracker source is chosen from a --tracker value.
#include <cstdlib>
#include <fstream>
#include <string>

#include "runner/tracker/pupil_labs_client.h"
#include "runner/tracker/replay_tracker.h"
#include "runner/tracker/simulated_tracker.h"
#include "runner/tracker/tracker_source.h"

namespace glarelab {

namespace {

// SQLite files begin with this 16-byte header string (sqlite.org/fileformat.html, 1.3).
bool looks_like_sqlite(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[16] = {};
  in.read(header, sizeof header);
  return in.gcount() == 16 && std::string(header, 16) == std::string("SQLite format 3\0", 16);
}

}  // namespace

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
    // An SQLite file without #SESSION would otherwise be read as a CSV of binary noise.
    if (looks_like_sqlite(target))
      throw TrackerError("--tracker " + spec + ": " + target +
                         " is a results database: name the session to replay, replay:FILE.db#SESSION");
    return std::make_unique<ReplayTracker>(read_tracker_csv(target), target);
  }
  throw TrackerError("--tracker " + spec +
                     ": unknown tracker (choose none, simulated, replay:FILE.csv, replay:FILE.db#SESSION or "
                     "pupil-labs://HOST:PORT)");
}

}  // namespace glarelab
