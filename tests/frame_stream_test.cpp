// Glare frames handed from the worker to the display's thread one by one
// (runner/session/frame_stream.h): the onset's rule against hand-worked numbers, and the frames a
// waiting flip gets from a worker thread that makes them later.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

#include "runner/session/frame_stream.h"

namespace glarelab {
namespace {

constexpr double kPeriodS = 1.0 / 60.0;

// 30 frames at 20 ms each on the worker, a 60 Hz display: with the 1.5 margin a frame takes 30 ms
// against 16.67 ms a flip. The last frame (j = 29) is ready (30 - made) x 30 ms from now and is due
// 30 periods less half a period from now, 491.67 ms: (30 - made) <= 16.39, so made >= 14.
TEST(FrameStream, AnOnsetWaitsUntilTheFramesStillToMakeCanFollowTheFlips) {
  EXPECT_FALSE(FrameStream::onset_fits(13, 30, 0.020, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(14, 30, 0.020, kPeriodS));
  // 100 ms a frame (150 ms with the margin): the last frame asks for 30 - made <= 3.28 (made >=
  // 27); the first one still to make, for 150 <= (made + 1) x 16.67 - 8.33 (made >= 9).
  EXPECT_FALSE(FrameStream::onset_fits(26, 30, 0.100, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(27, 30, 0.100, kPeriodS));
  // A worker faster than the display: the first three frames, no fewer.
  EXPECT_FALSE(FrameStream::onset_fits(2, 30, 0.005, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(3, 30, 0.005, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(3, 30, 0.010, kPeriodS));  // 27 x 15 = 405 <= 491.67 ms
  // The pace not known yet: every frame. One frame serving the interval: that frame.
  EXPECT_FALSE(FrameStream::onset_fits(29, 30, 0.0, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(30, 30, 0.0, kPeriodS));
  EXPECT_FALSE(FrameStream::onset_fits(0, 1, 0.001, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(1, 1, 0.0, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(0, 0, 0.0, kPeriodS));
}

TEST(FrameStream, AFlipGetsTheFrameTheWorkerMakesAfterItBeganToWait) {
  std::vector<GlaredRegion> frames(4);
  FrameStream stream;
  stream.begin({3, 0, 1});  // a dynamic interval, one with no frame, a static one
  stream.publish(0, 0, &frames[0], 0.05);
  std::thread worker([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    stream.publish(0, 1, &frames[1], 0.02);
    stream.publish(0, 2, &frames[2], 0.02);
    stream.publish(2, 0, &frames[3], 0.05);
    stream.finish();
  });
  const GlaredRegion* frame = nullptr;
  ASSERT_TRUE(stream.wait_for(0, 0, frame));
  EXPECT_EQ(frame, &frames[0]);
  ASSERT_TRUE(stream.wait_for(0, 2, frame));  // made after the wait began
  EXPECT_EQ(frame, &frames[2]);
  ASSERT_TRUE(stream.wait_for(0, 7, frame));  // past the interval's frames: its last one
  EXPECT_EQ(frame, &frames[2]);
  ASSERT_TRUE(stream.wait_for(1, 0, frame));  // an interval that computes none
  EXPECT_EQ(frame, nullptr);
  ASSERT_TRUE(stream.wait_for(2, 12, frame));  // one frame serving the interval
  EXPECT_EQ(frame, &frames[3]);
  worker.join();
  EXPECT_TRUE(stream.complete());
  EXPECT_TRUE(stream.finished());
  EXPECT_EQ(stream.total(), 4);
}

// The onset's wait ends with the frames the rule asks for there, counted as made by the onset; a
// worker stopped before a frame leaves the flip that waits for it without one.
TEST(FrameStream, TheOnsetCountsWhatWasReadyAndAStoppedWorkerEndsTheWait) {
  std::vector<GlaredRegion> frames(30);
  FrameStream stream;
  stream.begin({30});
  // Frame 0 (the interval's first, which also prepares its composed frame) is left out of the pace.
  stream.publish(0, 0, &frames[0], 0.300);
  for (int k = 1; k < 13; ++k) stream.publish(0, k, &frames[static_cast<std::size_t>(k)], 0.020);
  std::thread worker([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    stream.publish(0, 13, &frames[13], 0.020);  // 14 of 30 at 20 ms a frame: the onset may come
    stream.finish();                            // stopped before frame 14
  });
  stream.wait_until_onset_fits(kPeriodS);
  EXPECT_EQ(stream.ready(), 14);  // 13 did not fit
  worker.join();
  const GlaredRegion* frame = nullptr;
  ASSERT_TRUE(stream.wait_for(0, 13, frame));
  EXPECT_EQ(frame, &frames[13]);
  EXPECT_FALSE(stream.wait_for(0, 14, frame));
  EXPECT_EQ(frame, nullptr);
  EXPECT_FALSE(stream.complete());
}

}  // namespace
}  // namespace glarelab
