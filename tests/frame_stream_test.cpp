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

// 30 frames at 20 ms each on the worker, a 60 Hz display: with the margin of 2 a frame takes 40 ms
// against 16.67 ms a flip. The last frame (j = 29) is ready (30 - made) x 40 ms from now and is due
// 30 periods less half a period from now, 491.67 ms: (30 - made) <= 12.29, so made >= 18.
TEST(FrameStream, AnOnsetWaitsUntilTheFramesStillToMakeCanFollowTheFlips) {
  EXPECT_FALSE(FrameStream::onset_fits(17, 30, 0.020, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(18, 30, 0.020, kPeriodS));
  // 100 ms a frame (200 ms with the margin): the last frame asks for 30 - made <= 2.46 (made >=
  // 28); the first one still to make, for 200 <= (made + 1) x 16.67 - 8.33 (made >= 12).
  EXPECT_FALSE(FrameStream::onset_fits(27, 30, 0.100, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(28, 30, 0.100, kPeriodS));
  // A worker well ahead of the display: the first three frames, no fewer.
  EXPECT_FALSE(FrameStream::onset_fits(2, 30, 0.005, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(3, 30, 0.005, kPeriodS));  // 27 x 10 = 270 <= 491.67 ms
  // 10 ms a frame, 20 with the margin: 30 - made <= 24.58, so made >= 6.
  EXPECT_FALSE(FrameStream::onset_fits(5, 30, 0.010, kPeriodS));
  EXPECT_TRUE(FrameStream::onset_fits(6, 30, 0.010, kPeriodS));
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
  for (int k = 1; k < 17; ++k) stream.publish(0, k, &frames[static_cast<std::size_t>(k)], 0.020);
  std::thread worker([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    stream.publish(0, 17, &frames[17], 0.020);  // 18 of 30 at 20 ms a frame: the onset may come
    stream.finish();                            // stopped before frame 18
  });
  stream.wait_until_onset_fits(kPeriodS);
  EXPECT_EQ(stream.ready(), 18);  // 17 did not fit
  worker.join();
  const GlaredRegion* frame = nullptr;
  ASSERT_TRUE(stream.wait_for(0, 17, frame));
  EXPECT_EQ(frame, &frames[17]);
  EXPECT_FALSE(stream.wait_for(0, 18, frame));
  EXPECT_EQ(frame, nullptr);
  EXPECT_FALSE(stream.complete());
}

}  // namespace
}  // namespace glarelab
