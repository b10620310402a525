#include "core/frame_allocation.h"

#include <malloc.h>

namespace glarelab {

void keep_freed_frames_in_the_process() {
  // Setting either threshold turns glibc's own moving thresholds off, so both are set.
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);
}

}  // namespace glarelab
