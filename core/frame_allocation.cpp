#include "core/frame_allocation.h"

#include <malloc.h>

namespace glarelab {

void keep_freed_frames_in_the_process() {
  // Setting either threshold turns glibc's own moving thresholds off, so both are set.
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);
  // One arena for every thread: glibc gives each new thread an arena of its own (up to eight per
  // core), and memory freed in one is never handed out in another, so a session's worker threads
  // (one per trial prepared ahead, and their chunk workers) faulted in frames the display's thread
  // had freed. The few frame-sized blocks a frame takes make the arena's lock no contention.
  mallopt(M_ARENA_MAX, 1);
}

}  // namespace glarelab
