// A Pupil Capture that answers badly (pupil_capture_emulator.h on loopback): clock replies that
// are not a time, slow clock replies, a data stream that goes silent while Pupil Remote still
// answers, and a blink onset whose offset never comes. Each must leave the session running with
// every sample on the session's time line and the fault in the log.
#include <gtest/gtest.h>

#include <algorithm>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "cli_process.h"
#include "core/clock.h"
#include "pupil_capture_emulator.h"
#include "raw_db.h"
#include "runner/tracker/pupil_filter.h"
#include "runner/tracker/pupil_labs_client.h"
#include "runner/tracker/tracker_session.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

using test::PupilCaptureEmulator;
using TimeReply = PupilCaptureEmulator::TimeReply;

PupilLabsSettings emulator_settings(const PupilCaptureEmulator& emulator) {
  PupilLabsSettings settings;
  settings.port = emulator.remote_port();
  return settings;
}

int count_notices(const TrackerBatch& batch, const std::string& kind) {
  int count = 0;
  for (const TrackerNotice& notice : batch.notices) count += notice.kind == kind;
  return count;
}

// The connection's 12 "t" replies with a nan and an inf among them, then a re-estimate whose 12
// replies are all nan: the first estimate rests on its 10 times, the second keeps the offset.
TEST(TrackerFaults, ClockRepliesThatAreNotATimeAreSkippedAndLogged) {
  PupilCaptureEmulator emulator(120.0, 3000.0);
  std::vector<TimeReply> replies(12);
  replies[3].text = "nan";
  replies[8].text = "inf";
  replies.insert(replies.end(), 12, TimeReply{"nan", 0.0});
  emulator.script_time_replies(replies);
  MonotonicClock clock;
  const double origin_steady_s = PupilCaptureEmulator::steady_now_s() - clock.now_s();
  PupilLabsSettings settings = emulator_settings(emulator);
  settings.offset_interval_s = 0.4;
  PupilLabsClient client(settings);
  client.start(clock);
  const double first_offset_s = client.clock_offset().offset_s;
  EXPECT_NEAR(first_offset_s, 3000.0 + origin_steady_s, 0.002) << "the estimate from the replies that were times";
  emulator.start_publishing([](double) { return 4.0; }, {});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  emulator.stop_publishing();
  client.stop();
  const TrackerBatch batch = client.poll(clock.now_s());
  EXPECT_EQ(client.status().clock_faults, 14);
  EXPECT_EQ(count_notices(batch, "tracker_clock_fault"), 3)
      << "the two skipped replies at the start, the 12 of the failed re-estimate, and that it kept the offset";
  EXPECT_GE(count_notices(batch, "tracker_clock"), 1) << "later re-estimates succeed again";
  EXPECT_EQ(client.status().connection_losses, 0) << "a clock fault is not a lost connection";
  ASSERT_GT(batch.samples.size(), 200u);
  for (const TrackerSample& sample : batch.samples) {
    ASSERT_TRUE(std::isfinite(sample.session_time_s));
    const double truth_s = sample.device_time_s - 3000.0 - origin_steady_s;
    ASSERT_NEAR(sample.session_time_s, truth_s, 0.002);
  }
}

TEST(TrackerFaults, ATrackerWhoseClockIsNotATimeIsRefusedAtTheStart) {
  PupilCaptureEmulator emulator(120.0, 3000.0);
  emulator.script_time_replies(std::vector<TimeReply>(12, TimeReply{"nan", 0.0}));
  MonotonicClock clock;
  PupilLabsClient client(emulator_settings(emulator));
  try {
    client.start(clock);
    FAIL() << "start should refuse a clock that answers nan";
  } catch (const TrackerError& error) {
    EXPECT_NE(std::string(error.what()).find("'t' answered 'nan', not a time, in 12 of 12 requests"), std::string::npos)
        << error.what();
  }
}

// Each re-estimate takes 12 x 0.3 s. The receiver must keep the data flowing meanwhile: the
// freshest sample at every poll stays recent, and every published datum is received.
TEST(TrackerFaults, SlowClockRepliesDoNotHoldUpTheDataStream) {
  PupilCaptureEmulator emulator(120.0, 50.0);
  emulator.script_time_replies(std::vector<TimeReply>(12), 0.3);  // the connection's replies are quick
  MonotonicClock clock;
  PupilLabsSettings settings = emulator_settings(emulator);
  settings.offset_interval_s = 0.5;
  PupilLabsClient client(settings);
  client.start(clock);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  emulator.start_publishing([](double) { return 4.0; }, {});
  double worst_lag_s = 0.0;
  std::size_t received = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  while (std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const TrackerBatch batch = client.poll(clock.now_s());
    received += batch.samples.size();
    if (batch.samples.empty()) {
      worst_lag_s = std::max(worst_lag_s, 0.05);
      continue;
    }
    // Both clocks are this host's: how far the newest sample lags the poll, with the offset's error.
    worst_lag_s = std::max(worst_lag_s, clock.now_s() - batch.samples.back().session_time_s);
  }
  emulator.stop_publishing();
  client.stop();
  received += client.poll(clock.now_s()).samples.size();
  std::printf("[ figures  ] %d 't' requests, %zu of %zu published data received, worst lag %.3f s\n",
              emulator.time_requests(), received, emulator.published().size(), worst_lag_s);
  EXPECT_GE(emulator.time_requests(), 24) << "at least one slow re-estimate ran during the stream";
  // A stalled receiver (the clock estimate on its thread) would lag by the 3.6 s of an estimate.
  EXPECT_LT(worst_lag_s, 1.0);
  EXPECT_GE(static_cast<double>(received), 0.99 * static_cast<double>(emulator.published().size()));
}

// The stream stops for 3 s while Pupil Remote keeps answering: the client reconnects (a Remote
// answers) but no data comes; the longest gap is the stream's 3 s, not the 1 s loss timeout.
TEST(TrackerFaults, TheLongestGapIsTheDataStreamsAcrossReconnections) {
  PupilCaptureEmulator emulator(120.0, 50.0);
  MonotonicClock clock;
  PupilLabsClient client(emulator_settings(emulator));
  client.start(clock);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  emulator.start_publishing([](double) { return 4.0; }, {});
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  emulator.stop_publishing();
  const auto silent_from = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  emulator.start_publishing([](double) { return 4.0; }, {});
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  emulator.stop_publishing();
  client.stop();
  const double silence_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - silent_from).count() - 0.6;  // at least
  const TrackerStatus status = client.status();
  EXPECT_GE(status.connection_losses, 1);
  EXPECT_GE(status.longest_gap_s, 2.9) << "silent for " << silence_s << " s";
  EXPECT_GT(status.samples, 150) << "data flowed again after the silence";
}

// PupilFilter alone: an onset at 1 s without an offset, confident samples throughout. Before the
// timeout every sample is a blink; after it (and the 50 ms margin) samples are accepted again. A
// lid that stays shut (confidence 0) stays a blink by the confidence test.
TEST(TrackerFaults, ABlinkWithoutAnOffsetEndsAfterMaxBlinkS) {
  for (const bool lid_open : {true, false}) {
    PupilFilter filter;
    filter.add_blink({1.0, true, 1.0});
    int blinks_after_timeout = 0, accepted_after_timeout = 0, blinks_before = 0;
    for (int k = 0; k < 360; ++k) {
      TrackerSample sample;
      sample.eye = k % 2;
      sample.session_time_s = 1.0 + k / 120.0;
      sample.pupil_diameter_mm = lid_open ? 4.0 : 0.0;
      sample.confidence = lid_open ? 0.95 : 0.0;
      sample.valid = lid_open;
      const FilteredPupil out = filter.add(sample);
      if (sample.session_time_s < 1.99) blinks_before += out.blink;
      if (sample.session_time_s > 2.1) {
        blinks_after_timeout += out.blink;
        accepted_after_timeout += out.accepted;
      }
    }
    EXPECT_EQ(filter.timed_out_blinks(), 1u);
    EXPECT_EQ(blinks_before, 119) << "every sample in the first second is in the blink";
    if (lid_open) {
      EXPECT_EQ(blinks_after_timeout, 0);
      EXPECT_GT(accepted_after_timeout, 200);
    } else {
      EXPECT_EQ(accepted_after_timeout, 0);
      EXPECT_GT(blinks_after_timeout, 200) << "unconfident samples remain a blink";
    }
  }
}

// The same through the session's tracker: the blink seen by the lids ends, and the log says why.
TEST(TrackerFaults, ALostBlinkOffsetIsEndedAndLoggedInTheSession) {
  PupilCaptureEmulator emulator(120.0, 50.0);
  TrackerOptions options;
  options.spec = "pupil-labs://127.0.0.1:" + std::to_string(emulator.remote_port());
  TrackerSession tracker(options, 1);
  MonotonicClock clock;
  ASSERT_FALSE(tracker.start(clock).has_value());
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  emulator.start_publishing([](double) { return 4.0; }, {});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  emulator.publish_blink(true);
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(2500);
  while (std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(16));
    tracker.on_frame(clock.now_s());
  }
  emulator.stop_publishing();
  tracker.finish(clock.now_s());
  ASSERT_FALSE(tracker.detected_blinks().empty());
  const TrackerBlinkInterval blink = tracker.detected_blinks().back();
  ASSERT_TRUE(std::isfinite(blink.offset_s)) << "the blink must end";
  // It ends at the first sample after max_blink_s (1 s). The emulator publishes from a thread of
  // this process, which a loaded host holds up now and then (64 ms at load 18): the first sample
  // after the timeout then comes that much later, as the stream's longest gap says.
  const auto published = emulator.published();
  double longest_gap_s = 0.0;
  for (std::size_t k = 1; k < published.size(); ++k)
    longest_gap_s = std::max(longest_gap_s, published[k].pupil_time_s - published[k - 1].pupil_time_s);
  EXPECT_GE(blink.offset_s - blink.onset_s, 1.0 - 0.05);
  EXPECT_LE(blink.offset_s - blink.onset_s, 1.0 + 0.05 + longest_gap_s) << "longest gap " << longest_gap_s << " s";
}

std::int64_t count_rows(const std::string& db, const std::string& sql) { return std::stoll(test::RawDb(db).value(sql)); }

// As a user would meet it: `run` against a tracker whose clock answers nan and inf among its
// times. The session completes, logs the fault, and every sample lies on the session's time line.
TEST(TrackerFaults, ARunWithATrackerAnsweringNanKeepsEverySample) {
  test::ScratchDir dir;
  const auto experiment = test::demo_variant(dir.path(), {});
  PupilCaptureEmulator emulator(120.0, 700.0);
  std::vector<TimeReply> replies(12);
  replies[2].text = "nan";
  replies[5].text = "-inf";
  emulator.script_time_replies(replies);
  emulator.start_publishing([](double) { return 4.5; }, {});
  const std::string db = (dir.path() / "run.db").string();
  const std::string tracker = "pupil-labs://127.0.0.1:" + std::to_string(emulator.remote_port());
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                       "--db", db, "--tracker", tracker, "--stop-after", "2"},
                                      dir.path());
  emulator.stop_publishing();
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM session_events WHERE kind = 'tracker_clock_fault'"), 1);
  EXPECT_GE(count_rows(db, "SELECT count(*) FROM tracker_samples"), 200);
  // Up to the tracker's stop, logged as its summary's time: a loaded host can hold the session's
  // end (the last commit, the summary) more than a few tenths of a second after the last flip,
  // and samples arrive until the stop.
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM tracker_samples WHERE session_time_s IS NULL OR session_time_s < -0.5 "
                           "OR session_time_s > (SELECT session_time_s + 0.5 FROM session_events WHERE kind = "
                           "'tracker_summary')"),
            0);
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM session_events WHERE kind = 'tracker_summary' AND session_time_s >= "
                           "(SELECT max(flip_s) FROM frames)"),
            1);
  EXPECT_NE(run.output.find("2 clock replies that were not a time"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace glarelab
