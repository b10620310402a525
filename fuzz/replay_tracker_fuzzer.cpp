// Fuzz target: the recorded tracker CSV of `--tracker replay:FILE.csv`
// (runner/tracker/replay_tracker.h). Expected outcome for bad input: TrackerError naming the file
// (and line). A track that loads is replayed to the end; poll(t) must hand out every sample and
// blink exactly once.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

#include "fuzz/fuzz_support.h"
#include "runner/tracker/replay_tracker.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glarelab;
  const std::string path =
      fuzz::ScratchFolder::instance().write("track.csv", std::string_view(reinterpret_cast<const char*>(data), size));
  RecordedTrack track;
  try {
    track = read_tracker_csv(path);
  } catch (const TrackerError&) {
    return 0;
  }
  const std::size_t samples = track.samples.size();
  const std::size_t blinks = track.blinks.size();
  ReplayTracker tracker(std::move(track), path);
  std::size_t samples_seen = 0, blinks_seen = 0;
  for (const double t : {-1.0, 0.0, 0.5, 1.0, 10.0, std::numeric_limits<double>::infinity()}) {
    const TrackerBatch batch = tracker.poll(t);
    samples_seen += batch.samples.size();
    blinks_seen += batch.blinks.size();
  }
  // NaN times never compare <= t; everything else must have come out by t = +inf.
  if (samples_seen > samples || blinks_seen > blinks) {
    std::fprintf(stderr, "replay handed out %zu of %zu samples, %zu of %zu blinks\n", samples_seen, samples,
                 blinks_seen, blinks);
    std::abort();
  }
  return 0;
}
