#pragma once
// How the process allocates frame-sized memory (call once, first thing in main).
//
// A frame is a few MB of floats, made and freed several times per refresh. By default glibc hands
// such a block back to the kernel as soon as a few are free, so each new frame faults its pages
// in again, zero-filled, 4 KB at a time: the demo session took 320 thousand page faults, a sixth of
// its CPU time. Kept instead: blocks up to 32 MB (glibc's largest mmap threshold) come from the
// heap, and free memory stays with the process until 1 GB of it is free (the demo: 110 thousand
// faults, a quarter less CPU time; docs/PERFORMANCE.md). The peak memory is unchanged. And one
// arena serves every thread, so a frame freed by one thread is reused by the next that asks.
namespace glarelab {

void keep_freed_frames_in_the_process();

}  // namespace glarelab
