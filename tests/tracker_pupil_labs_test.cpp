// Acceptance of the Pupil Labs client against an emulator of Pupil Capture's network API
// (pupil_capture_emulator.h): logging completeness, clock mapping, the model pupil through blinks,
// replay, lost connections, malformed messages, an absent tracker, and the runner end to end.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <thread>

#include "cli_process.h"
#include "pupil_capture_emulator.h"
#include "core/clock.h"
#include "runner/store/result_store.h"
#include "runner/tracker/pupil_filter.h"
#include "runner/tracker/pupil_labs_client.h"
#include "runner/tracker/replay_tracker.h"
#include "runner/tracker/tracker_logger.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

using test::PupilCaptureEmulator;

PupilLabsSettings emulator_settings(const PupilCaptureEmulator& emulator) {
  PupilLabsSettings settings;
  settings.host = "127.0.0.1";
  settings.port = emulator.remote_port();
  return settings;
}

std::int64_t new_session(ResultStore& store) {
  SessionRecord session;
  session.experiment = "tracker-test";
  session.participant = "P";
  session.started_utc = utc_now_iso8601();
  session.status = "running";
  session.display_backend = "offscreen";
  session.clock = "monotonic";
  session.observer = "simulated";
  return store.begin_session(session);
}

// Scripted pupil: slow 0.5 Hz oscillation between 3.5 and 5.5 mm (a physiological speed, 3 mm/s at most).
double scripted_diameter_mm(double t_s) { return 4.5 + 1.0 * std::sin(2.0 * 3.141592653589793 * 0.5 * t_s); }

TEST(TrackerPupilLabs, LogsPublishedSamplesMapsTimeAndKeepsPupilThroughBlinks) {
  test::ScratchDir dir;
  const std::string db = (dir.path() / "tracker.db").string();
  ResultStore store(db);
  const std::int64_t session_id = new_session(store);

  PupilCaptureEmulator emulator(120.0, 5000.0);
  MonotonicClock clock;
  // The session clock's origin on steady_clock, so the emulator's truth maps onto session time.
  const double origin_steady_s = PupilCaptureEmulator::steady_now_s() - clock.now_s();

  PupilLabsClient client(emulator_settings(emulator));
  client.start(clock);
  TrackerLogger logger(db, session_id);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the SUB socket's subscription settles
  const std::vector<std::pair<double, double>> blinks = {{2.0, 2.15}, {5.0, 5.2}, {8.0, 8.3}};
  emulator.start_publishing(scripted_diameter_mm, blinks);

  PupilFilter filter;
  std::vector<FilteredPupil> live_trace;
  const auto run_until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < run_until) {
    std::this_thread::sleep_for(std::chrono::microseconds(16667));  // one 60 Hz frame
    TrackerBatch batch = client.poll(clock.now_s());
    filter.add_batch(batch, &live_trace);
    logger.enqueue(std::move(batch));
  }
  emulator.stop_publishing();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  client.stop();
  TrackerBatch last = client.poll(clock.now_s());
  filter.add_batch(last, &live_trace);
  logger.enqueue(std::move(last));
  logger.finish();

  const auto published = emulator.published();
  ASSERT_GE(published.size(), 2300u) << "the emulator should publish ~2400 pupil data in 10 s";
  const RecordedTrack logged = read_tracker_database(db, session_id);
  std::map<std::pair<int, double>, const TrackerSample*> by_key;
  for (const TrackerSample& sample : logged.samples) by_key[{sample.eye, sample.device_time_s}] = &sample;
  std::size_t found = 0;
  double worst_error_s = 0.0;
  for (const auto& datum : published) {
    const auto it = by_key.find({datum.eye, datum.pupil_time_s});
    if (it == by_key.end()) continue;
    ++found;
    const double truth_session_s = datum.pupil_time_s - emulator.pupil_time_offset_s() - origin_steady_s;
    worst_error_s = std::max(worst_error_s, std::abs(it->second->session_time_s - truth_session_s));
    EXPECT_EQ(it->second->confidence, datum.confidence);
    if (datum.confidence > 0.0) {
      EXPECT_EQ(it->second->pupil_diameter_mm, datum.diameter_mm);
    }
  }
  const double logged_fraction = static_cast<double>(found) / static_cast<double>(published.size());
  std::printf("[ figures  ] published %zu, logged %zu (%.2f%%), worst session-time error %.3f ms, "
              "offset uncertainty %.3f ms\n",
              published.size(), found, 100.0 * logged_fraction, worst_error_s * 1e3,
              client.clock_offset().uncertainty_s * 1e3);
  EXPECT_GE(logged_fraction, 0.99);
  EXPECT_LE(worst_error_s, 0.002);
  EXPECT_EQ(emulator.time_set_requests(), 0) << "the client must never send T";
  EXPECT_EQ(client.status().malformed_messages, 0);
  EXPECT_EQ(logged.blinks.size(), 2 * blinks.size()) << "every blink onset and offset is logged";

  // The model pupil stays in the physiological range through every blink, and near the script:
  // it holds the last value instead of falling toward the reported 0 mm.
  ASSERT_FALSE(live_trace.empty());
  int samples_in_blinks = 0;
  for (const FilteredPupil& out : live_trace) {
    ASSERT_GE(out.model_pupil_mm, 1.5) << "at " << out.session_time_s << " s";
    ASSERT_LE(out.model_pupil_mm, 9.0) << "at " << out.session_time_s << " s";
    if (out.blink) {
      ++samples_in_blinks;
      EXPECT_GE(out.model_pupil_mm, 3.3) << "the held pupil stays near the scripted range (3.5-5.6 mm)";
    }
  }
  EXPECT_GT(samples_in_blinks, 100);

  // Replay of the recorded session gives exactly the same model pupil trace.
  ReplayTracker replay(read_tracker_database(db, session_id), db);
  PupilFilter replay_filter;
  std::vector<FilteredPupil> replay_trace;
  replay_filter.add_batch(replay.poll(1e9), &replay_trace);
  ASSERT_EQ(replay_trace.size(), live_trace.size());
  for (std::size_t i = 0; i < live_trace.size(); ++i) {
    ASSERT_EQ(replay_trace[i].session_time_s, live_trace[i].session_time_s) << i;
    ASSERT_EQ(replay_trace[i].model_pupil_mm, live_trace[i].model_pupil_mm) << i;
  }
}

TEST(TrackerPupilLabs, LostConnectionIsLoggedAndRecoveredAndMalformedMessagesSkipped) {
  PupilCaptureEmulator emulator(120.0, 100.0);
  MonotonicClock clock;
  PupilLabsSettings settings = emulator_settings(emulator);
  settings.loss_timeout_s = 0.3;
  settings.request_timeout_s = 0.2;
  PupilLabsClient client(settings);
  client.start(clock);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  emulator.start_publishing([](double) { return 4.0; }, {});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  emulator.publish_raw("pupil.0.3d", "\xc1 not msgpack");               // 0xc1 is never used in msgpack
  emulator.publish_raw("pupil.1.3d", std::string("\x81\xa2id\x01", 5));  // a map without the required fields
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  emulator.set_silent(true);
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  const std::int64_t before_recovery = client.status().samples;
  emulator.set_silent(false);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  emulator.stop_publishing();
  client.stop();
  const TrackerBatch batch = client.poll(clock.now_s());
  const TrackerStatus status = client.status();
  EXPECT_EQ(status.malformed_messages, 2);
  EXPECT_GE(status.connection_losses, 1);
  EXPECT_GE(status.reconnections, 1);
  EXPECT_GE(status.longest_gap_s, 1.0);
  EXPECT_GT(status.samples, before_recovery + 100) << "samples flow again after reconnecting";
  int lost = 0, reconnected = 0, malformed = 0;
  for (const TrackerNotice& notice : batch.notices) {
    lost += notice.kind == "tracker_lost";
    reconnected += notice.kind == "tracker_reconnected";
    malformed += notice.kind == "tracker_malformed";
  }
  EXPECT_GE(lost, 1);
  EXPECT_GE(reconnected, 1);
  EXPECT_EQ(malformed, 1) << "the first malformed message is reported, then every 100th";
}

TEST(TrackerPupilLabs, AbsentTrackerIsAClearError) {
  int port = 0;
  { port = PupilCaptureEmulator().remote_port(); }  // a port nothing listens on any more
  MonotonicClock clock;
  PupilLabsSettings settings;
  settings.port = port;
  settings.request_timeout_s = 0.2;
  PupilLabsClient client(settings);
  try {
    client.start(clock);
    FAIL() << "start should throw";
  } catch (const TrackerError& error) {
    EXPECT_NE(std::string(error.what()).find("no Pupil Remote answers at 127.0.0.1:" + std::to_string(port)),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(probe_pupil_remote("127.0.0.1", port, 0.2).has_value());
}

std::int64_t count_rows(const std::string& db, const std::string& sql) {
  sqlite3* handle = nullptr;
  sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(handle, sql.c_str(), -1, &statement, nullptr);
  std::int64_t count = -1;
  if (sqlite3_step(statement) == SQLITE_ROW) count = sqlite3_column_int64(statement, 0);
  sqlite3_finalize(statement);
  sqlite3_close_v2(handle);
  return count;
}

TEST(TrackerPupilLabs, RunnerLogsALiveTrackerAndRefusesAnAbsentOne) {
  test::ScratchDir dir;
  const auto experiment = test::demo_variant(dir.path(), {});
  PupilCaptureEmulator emulator(120.0, 700.0);
  emulator.start_publishing(scripted_diameter_mm, {{0.5, 0.65}});
  const std::string db = (dir.path() / "run.db").string();
  const std::string tracker = "pupil-labs://127.0.0.1:" + std::to_string(emulator.remote_port());
  // Two trials of 30 frames at 60 Hz, paced in real time: about 1 s.
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                       "--db", db, "--tracker", tracker, "--stop-after", "2"},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("tracker " + tracker), std::string::npos) << run.output;
  const std::int64_t samples = count_rows(db, "SELECT count(*) FROM tracker_samples WHERE session_id = 1");
  // ~1 s at 2 x 120 Hz; a paced run that did not wait would log far fewer.
  EXPECT_GE(samples, 200) << run.output;
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM sessions WHERE clock = 'monotonic'"), 1);
  // Samples lie on the session's time line: from its start to the tracker's stop, logged as its
  // summary's time after the last flip (a loaded host can hold the session's end more than a few
  // tenths of a second after that flip, and samples arrive until the stop).
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM session_events WHERE kind = 'tracker_summary' AND session_time_s >= "
                           "(SELECT max(flip_s) FROM frames)"),
            1);
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM tracker_samples WHERE session_time_s < -0.5 OR session_time_s > "
                           "(SELECT session_time_s + 0.5 FROM session_events WHERE kind = 'tracker_summary')"),
            0);
  emulator.stop_publishing();

  int absent_port = 0;
  { absent_port = PupilCaptureEmulator().remote_port(); }
  const std::string absent = "pupil-labs://127.0.0.1:" + std::to_string(absent_port);
  const auto refused = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer",
                                           "simulated", "--db", (dir.path() / "absent.db").string(), "--tracker", absent},
                                          dir.path());
  EXPECT_EQ(refused.exit_code, 3) << refused.output;
  EXPECT_NE(refused.output.find("no Pupil Remote answers"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "absent.db")) << "nothing is written before the tracker answers";

  const std::string optional_db = (dir.path() / "optional.db").string();
  const auto optional = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer",
                                            "simulated", "--db", optional_db, "--tracker", absent, "--tracker-optional",
                                            "--stop-after", "1"},
                                           dir.path());
  EXPECT_EQ(optional.exit_code, 0) << optional.output;
  EXPECT_EQ(count_rows(optional_db, "SELECT count(*) FROM session_events WHERE kind = 'tracker_absent'"), 1);
}

}  // namespace
}  // namespace glarelab
