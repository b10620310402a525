#include "runner/session/saved_frame_writer.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <iostream>
#include <utility>

#include "core/exr_io.h"
#include "stimuli/scene_library.h"

namespace glarelab {
namespace {

constexpr int kWriterNiceness = 2;

}  // namespace

SavedFrameWriter::SavedFrameWriter() : thread_([this] { run(); }) {}

SavedFrameWriter::~SavedFrameWriter() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();  // after the queue is written (run() empties it before it stops)
  if (error_) {
    try {
      std::rethrow_exception(error_);
    } catch (const std::exception& error) {
      std::cerr << "warning: a saved frame was not written: " << error.what() << "\n";
    }
  }
}

void SavedFrameWriter::run() {
  // At the trial worker's niceness (trial_ahead.cpp), below the display's thread: a trial waits for
  // its frame's file at its commit as its onset waits for the worker's frames.
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), kWriterNiceness);  // best effort
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, nothing left
    Job job = std::move(queue_.front());
    queue_.pop_front();
    writing_ = true;
    lock.unlock();
    std::exception_ptr failure;
    try {
      if (job.as_scene) zero_round_off_negatives(job.frame);
      write_exr(job.path, job.frame, display_frame_exr_options());
    } catch (...) {
      failure = std::current_exception();
    }
    lock.lock();
    writing_ = false;
    if (failure && !error_) error_ = failure;
    changed_.notify_all();
  }
}

void SavedFrameWriter::raise_error_locked(std::unique_lock<std::mutex>& lock) {
  if (!error_) return;
  const std::exception_ptr error = std::exchange(error_, nullptr);
  lock.unlock();
  std::rethrow_exception(error);
}

void SavedFrameWriter::write(std::string path, ImageRGBA frame, bool as_scene) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return error_ || queue_.size() < kQueuedFrames; });
  raise_error_locked(lock);
  queue_.push_back({std::move(path), std::move(frame), as_scene});
  changed_.notify_all();
}

void SavedFrameWriter::finish() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return queue_.empty() && !writing_; });
  raise_error_locked(lock);
}

}  // namespace glarelab
