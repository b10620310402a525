#pragma once
// The frames a session saves (--save-frames) written beside it: the display's thread reads a frame
// back and hands it over, and a thread of the writer's own writes the OpenEXR file, uncompressed
// (core/exr_io.h: under a temporary name, then renamed). Zipped, a 1024 x 512 float frame took
// about 180 ms to compress and write on one core, and was written on the display's thread between a
// trial's first frame's drawing and its flip: on a real clock every onset of such a run came 200 to
// 700 ms late, named "host stall" (docs/PERFORMANCE.md, "what the host stall onsets were").
//
// Frames are written in the order handed over. At most kQueuedFrames wait at once: the display's
// thread waits beyond that (memory stays bounded when frames come faster than the disk takes
// them). A session waits for its trial's frames at the trial's commit (finish()), so a trial is
// committed with its saved frames on disk; a failed write is raised there on the display's thread
// (or at the next hand-over), and the session ends as aborted with the reason, as when the write
// was its own. The destructor writes what is still queued: a frame read back is not lost when the
// session ends early.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

#include "core/image.h"

namespace glarelab {

class SavedFrameWriter {
 public:
  static constexpr std::size_t kQueuedFrames = 4;
  SavedFrameWriter();
  ~SavedFrameWriter();
  SavedFrameWriter(const SavedFrameWriter&) = delete;
  SavedFrameWriter& operator=(const SavedFrameWriter&) = delete;

  // Queues `frame` for `path`; waits while kQueuedFrames are queued. Raises an earlier write's error.
  // `as_scene`: a stimulus frame, written so that it loads as a scene with no option (its glare's
  // round-off below 0 set to 0 on the writer's thread, stimuli/scene_library.h); a display's drive
  // values are written as they are.
  void write(std::string path, ImageRGBA frame, bool as_scene);
  // Waits until every frame handed over is written; raises the first write's error, if any.
  void finish();

 private:
  struct Job {
    std::string path;
    ImageRGBA frame;
    bool as_scene = false;
  };
  void run();
  void raise_error_locked(std::unique_lock<std::mutex>& lock);

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Job> queue_;
  bool writing_ = false;  // a job taken from the queue and not yet written
  bool stopping_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace glarelab
