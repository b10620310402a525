#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "core/clock.h"
#include "runner/session/slow_flip_clock.h"
#include "runner/tracker/real_time_pacer.h"

namespace glarelab {
namespace {

TEST(Clock, VirtualFlipKIsAtKOverRefreshRate) {
  VirtualClock clock(60.0);
  EXPECT_EQ(clock.name(), "virtual");
  for (int k = 0; k < 1000; ++k) {
    EXPECT_EQ(clock.now_s(), k * (1.0 / 60.0)) << "before flip " << k;
    EXPECT_EQ(clock.on_flip(), k * (1.0 / 60.0)) << "flip " << k;
  }
  EXPECT_EQ(clock.frames_presented(), 1000);
}

TEST(Clock, VirtualClockDoesNotDriftOverLongSessions) {
  VirtualClock clock(60.0);
  double last = -1.0;
  for (int k = 0; k < 100000; ++k) last = clock.on_flip();
  EXPECT_NEAR(last, 99999.0 / 60.0, 1e-9);
  // Frame 100000 (the next flip) is at 100000 / 60 s.
  EXPECT_NEAR(clock.on_flip(), 100000.0 / 60.0, 1e-9);
  // Accumulating the period instead would drift: the reference shows the test can tell.
  double accumulated = 0.0;
  for (int k = 0; k < 100000; ++k) accumulated += 1.0 / 60.0;
  EXPECT_GT(std::abs(accumulated - 100000.0 / 60.0), 1e-12);
}

TEST(Clock, VirtualClockResumesFromOffsetAndFrame) {
  VirtualClock clock(144.0, 10.0, 500);
  EXPECT_EQ(clock.on_flip(), 10.0 + 500 * (1.0 / 144.0));
  EXPECT_EQ(clock.frames_presented(), 501);
  EXPECT_THROW(VirtualClock(0.0), std::invalid_argument);
  EXPECT_THROW(VirtualClock(-60.0), std::invalid_argument);
}

TEST(Clock, MonotonicIsNonDecreasing) {
  MonotonicClock clock(5.0);
  EXPECT_EQ(clock.name(), "monotonic");
  double previous = clock.now_s();
  EXPECT_GE(previous, 5.0);
  for (int i = 0; i < 100000; ++i) {
    const double now = (i % 2 == 0) ? clock.now_s() : clock.on_flip();
    ASSERT_GE(now, previous);
    previous = now;
  }
}

// The real-time pacer waits for refresh boundaries as a swap waits for the vertical blank: after a
// frame that took 2.5 periods it waits for the next boundary still to come, not for the ones it
// missed (which would flip the next frames at once to catch up), and never returns before the
// boundary it waited for.
TEST(Clock, RealTimePacerWaitsForTheNextBoundaryAfterALateFrame) {
  const double period_s = 0.01;
  const auto start = std::chrono::steady_clock::now();
  RealTimePacer pacer(1.0 / period_s);
  const auto elapsed_s = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  pacer.wait_for_next_frame();
  EXPECT_EQ(pacer.boundary(), 1);
  EXPECT_GE(elapsed_s(), 1.0 * period_s);
  std::this_thread::sleep_for(std::chrono::duration<double>(2.5 * period_s));  // a late frame
  pacer.wait_for_next_frame();
  const std::int64_t after_late = pacer.boundary();
  EXPECT_GE(after_late, 4);  // boundaries 2 and 3 passed while the frame was drawn
  EXPECT_GE(elapsed_s(), static_cast<double>(after_late) * period_s);
  pacer.wait_for_next_frame();
  EXPECT_GE(pacer.boundary(), after_late + 1);
  EXPECT_GE(elapsed_s(), static_cast<double>(pacer.boundary()) * period_s);
}

// The flip is the boundary waited for, not the moment the process woke: each wait returns its
// boundary, one period after the last when the frames keep up (whatever the host did meanwhile),
// and never a time still to come.
TEST(Clock, RealTimePacerReturnsTheBoundaryItWaitedFor) {
  const double period_s = 0.01;
  RealTimePacer pacer(1.0 / period_s);
  const auto first = pacer.wait_for_next_frame();
  EXPECT_LE(first, std::chrono::steady_clock::now());
  const std::int64_t first_boundary = pacer.boundary();
  const auto second = pacer.wait_for_next_frame();
  EXPECT_LE(second, std::chrono::steady_clock::now());
  const double apart_s = std::chrono::duration<double>(second - first).count();
  EXPECT_NEAR(apart_s, static_cast<double>(pacer.boundary() - first_boundary) * period_s, 1e-8);
  EXPECT_GE(pacer.boundary(), first_boundary + 1);
}

// A flip known to have happened at a steady_clock time is that time on the monotonic session
// clock (with a resumed session's offset), and a slow-flip self-test delays it as it delays
// on_flip(); the virtual clock keeps its own grid.
TEST(Clock, AFlipAtAKnownSteadyTimeIsStampedAtThatTime) {
  const auto before = std::chrono::steady_clock::now();
  MonotonicClock clock(100.0);
  const auto after = std::chrono::steady_clock::now();
  const auto presented = after + std::chrono::milliseconds(250);
  const double flip_s = clock.on_flip_at(presented);
  EXPECT_GE(flip_s, 100.25);
  EXPECT_LE(flip_s, 100.25 + std::chrono::duration<double>(after - before).count() + 1e-9);
  EXPECT_NEAR(clock.on_flip_at(presented + std::chrono::microseconds(16667)) - flip_s, 0.016667, 1e-9);

  SlowFlipClock slowed(std::make_unique<MonotonicClock>(0.0), 60.0, 2);
  const double unslowed_s = slowed.on_flip_at(presented);
  EXPECT_NEAR(slowed.on_flip_at(presented) - unslowed_s, 1.0 / 60.0, 1e-9) << "every 2nd flip a period late";

  VirtualClock virtual_clock(60.0);
  EXPECT_EQ(virtual_clock.on_flip_at(presented), 0.0);
  EXPECT_EQ(virtual_clock.on_flip_at(presented), 1.0 / 60.0);
}

// What a session asks of its clock before it waits for a flip (a frame late for it, a worker below
// the display's priority): a virtual clock slowed for the timing self-test still keeps no real time,
// whatever its name in the log says.
TEST(Clock, OnlyClocksOfTheWallKeepRealTime) {
  EXPECT_TRUE(MonotonicClock(0.0).keeps_real_time());
  EXPECT_FALSE(VirtualClock(60.0).keeps_real_time());
  const SlowFlipClock slowed_virtual(std::make_unique<VirtualClock>(60.0), 60.0, 3);
  EXPECT_EQ(slowed_virtual.name(), "virtual+slow-flips");
  EXPECT_FALSE(slowed_virtual.keeps_real_time());
  EXPECT_TRUE(SlowFlipClock(std::make_unique<MonotonicClock>(0.0), 60.0, 3).keeps_real_time());
}

}  // namespace
}  // namespace glarelab
