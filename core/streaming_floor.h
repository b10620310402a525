#pragma once
// The floor of a per-pixel stage: the time to stream the bytes the stage must read and write once,
// with the threads the stage uses (core/parallel_for.h). A stage that reads an RGBA float frame and
// writes one (tone mapping, scotopic colour, acuity) can be no faster than reading 16 and writing
// 16 bytes a pixel; one that only reads it (the adaptation luminance) no faster than reading 16.
// `glarelab bench` prints each stage beside this floor measured in the same run, so the ratio says
// how far a stage is from the machine's memory bandwidth, whatever the machine.
//
// The kernel: the read buffer is summed (eight independent lanes, so the loop needs no reordering
// of additions to run at full speed) and the write buffer filled with a value made from the input,
// each thread over its own contiguous share; both buffers are touched once before timing, so no
// page is first mapped inside a run.
#include <cstddef>
#include <vector>

namespace glarelab {

class StreamingFloor {
 public:
  // Throws std::invalid_argument for threads < 1 or no bytes at all.
  StreamingFloor(std::size_t read_bytes, std::size_t write_bytes, int threads);
  // One pass over both buffers, in seconds.
  double run_s();
  // The fastest of `runs` passes, in seconds.
  double fastest_s(int runs);
  // What the last pass read, summed (keeps the reads from being optimised away; tests check it).
  double checksum() const { return checksum_; }

 private:
  std::vector<float> read_;
  std::vector<float> write_;
  int threads_;
  double checksum_ = 0.0;
};

}  // namespace glarelab
