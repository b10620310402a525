// Freed frames stay in the process (core/frame_allocation.h): making and freeing frame after frame
// faults the pages of the first ones in, not of every one. The kernel counts the faults, so this
// holds on a loaded machine.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <thread>
#include <vector>

#include "core/frame_allocation.h"
#include "core/image.h"

namespace glarelab {
namespace {

// The test program allocates frames as glarelab does.
const bool kAllocatesAsGlarelab = (keep_freed_frames_in_the_process(), true);

long minor_faults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// Under AddressSanitizer malloc is the sanitizer's: it ignores glibc's mallopt settings and holds
// freed blocks in a quarantine instead of handing them out again (to catch use after free).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitizerAllocator = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitizerAllocator = true;
#else
constexpr bool kSanitizerAllocator = false;
#endif
#else
constexpr bool kSanitizerAllocator = false;
#endif

// Three half-HD frames (960 x 1080, 16.6 MB each, under glibc's 32 MB mmap threshold) alive at
// once, then all freed, as a glare frame's source, energy and sum are; each frame's first red value
// set to 1 and its last alpha 1, so a round sums to 6.
constexpr long kPagesPerFrame = 4L * 960 * 1080 * 4 / 4096;  // 4050 pages of 4 KB
double make_and_free_frames() {
  std::vector<ImageRGBA> frames;
  for (int i = 0; i < 3; ++i) frames.emplace_back(960, 1080);
  double sum = 0.0;
  for (ImageRGBA& frame : frames) {
    frame.rgba.front() = 1.0f;
    sum += frame.rgba.front() + frame.rgba.back();
  }
  return sum;
}

TEST(FrameAllocation, FramesMadeAndFreedAgainFaultTheirPagesInOnce) {
  if (kSanitizerAllocator)
    GTEST_SKIP() << "AddressSanitizer's allocator quarantines freed blocks: the reuse measured here is glibc's";
  ASSERT_TRUE(kAllocatesAsGlarelab);
  make_and_free_frames();  // the first frames fault their pages in
  const long before = minor_faults();
  double sum = 0.0;
  for (int round = 0; round < 20; ++round) sum += make_and_free_frames();
  const long faults = minor_faults() - before;
  EXPECT_EQ(sum, 20.0 * 6.0);
  // Handed back to the kernel each round, 20 rounds would fault 20 x 3 frames of pages in
  // (243 thousand); kept, a few hundred (the test framework's own).
  EXPECT_LT(faults, kPagesPerFrame / 2) << faults << " page faults for 20 rounds of 3 half-HD frames";
}

// Frames freed by one thread are reused by threads made after it, as a session's worker threads
// (one per trial prepared ahead) reuse what the display's thread freed: one arena for all. With an
// arena per thread the first new thread's arena faults its three frames' pages in (3 x 4050).
TEST(FrameAllocation, FramesFreedByOneThreadAreReusedByTheNextThreads) {
  if (kSanitizerAllocator)
    GTEST_SKIP() << "AddressSanitizer's allocator quarantines freed blocks: the reuse measured here is glibc's";
  ASSERT_TRUE(kAllocatesAsGlarelab);
  make_and_free_frames();  // this thread's frames fault their pages in
  const long before = minor_faults();
  double sum = 0.0;
  for (int round = 0; round < 6; ++round) std::thread([&] { sum += make_and_free_frames(); }).join();
  const long faults = minor_faults() - before;  // the process's: every thread's
  EXPECT_EQ(sum, 6.0 * 6.0);
  EXPECT_LT(faults, 2 * kPagesPerFrame) << faults << " page faults for 6 threads' 3 frames each";
}

}  // namespace
}  // namespace glarelab
