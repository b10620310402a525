// Response devices in sessions: a fake button box (tests/hid_fake_port.h) answers an offscreen
// forced-choice session run in this process, pressed by the test as trials appear; unplugging it
// pauses the session until it is plugged back; the options are checked before anything is opened.
#include <gtest/gtest.h>

#include <algorithm>
#include <sqlite3.h>

#include <atomic>
#include <csignal>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "cli_process.h"
#include "hid_fake_port.h"
#include "runner/session/interrupt.h"
#include "runner/session/response_device_input.h"
#include "runner/session/session_runner.h"
#include "runner/store/result_store.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

// One integer from the database, read on a connection of its own; -1 while it cannot be read.
long long query_int(const std::string& db, const std::string& sql) {
  if (!std::filesystem::exists(db)) return -1;
  sqlite3* connection = nullptr;
  long long value = -1;
  if (sqlite3_open_v2(db.c_str(), &connection, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(connection, 2000);
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(connection, sql.c_str(), -1, &statement, nullptr) == SQLITE_OK &&
        sqlite3_step(statement) == SQLITE_ROW)
      value = sqlite3_column_int64(statement, 0);
    sqlite3_finalize(statement);
  }
  sqlite3_close(connection);
  return value;
}

struct LoggedEvent {
  double session_time_s = 0.0;
  std::string message;
};

std::vector<LoggedEvent> events_of_kind(const ResultStore& store, const std::string& kind) {
  sqlite3_stmt* statement = nullptr;
  std::vector<LoggedEvent> events;
  if (sqlite3_prepare_v2(store.handle(), "SELECT session_time_s, message FROM session_events WHERE kind = ? ORDER BY id",
                         -1, &statement, nullptr) != SQLITE_OK)
    return events;
  sqlite3_bind_text(statement, 1, kind.c_str(), -1, SQLITE_TRANSIENT);
  while (sqlite3_step(statement) == SQLITE_ROW)
    events.push_back({sqlite3_column_double(statement, 0), reinterpret_cast<const char*>(sqlite3_column_text(statement, 1))});
  sqlite3_finalize(statement);
  return events;
}

// run_session on a thread of its own.
class SessionThread {
 public:
  explicit SessionThread(RunOptions options)
      : thread_([this, options] {
          try {
            std::ostringstream progress;
            result_ = run_session(options, progress);
          } catch (const std::exception& error) {
            error_ = error.what();
          }
          done_ = true;
        }) {}
  ~SessionThread() { join(); }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  bool done() const { return done_; }
  const RunResult& result() const { return result_; }
  const std::string& error() const { return error_; }

 private:
  RunResult result_;
  std::string error_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

// Waits (polling) until `condition` holds or the session ended; a 60 s guard turns a hang into a
// failure. Returns whether the condition held.
bool wait_for(const SessionThread& session, const std::function<bool()>& condition) {
  for (int i = 0; i < 12000; ++i) {
    if (condition()) return true;
    if (session.done()) return condition();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

// The test's side of a session answered with the fake button box.
class DeviceDriver {
 public:
  DeviceDriver(const SessionThread& session, test::FakeHidPort& port, std::string db)
      : session_(session), port_(port), db_(std::move(db)) {}

  long long trials() const { return query_int(db_, "SELECT COUNT(*) FROM trials"); }
  long long events(const std::string& where) const {
    return query_int(db_, "SELECT COUNT(*) FROM session_events WHERE " + where);
  }
  bool wait_for_trials(long long count) const {
    return wait_for(session_, [&] { return trials() >= count; });
  }
  bool wait_for_event(const std::string& kind) const {
    return wait_for(session_, [&] { return events("kind = '" + kind + "'") > 0; });
  }

  // Answers trial k (trial k - 1 is committed, so no earlier trial polls any more) with button
  // `bit`: a press made before the trial's onset is logged as ignored, so the test presses again
  // until one of its presses is logged as trial k's answer. False when the session ended first.
  bool answer(int k, int bit) const {
    // Presses during trial k itself ("trial k: button ..."), not on a screen before it.
    const std::string of_trial = "message LIKE 'trial " + std::to_string(k) + ": button %'";
    const std::string presses = "kind IN ('button', 'ignored_button') AND " + of_trial;
    for (int attempt = 0; attempt < 100; ++attempt) {
      const long long logged = events(presses);
      port_.click(bit);
      if (!wait_for(session_, [&] { return events(presses) > logged; })) return false;
      if (events("kind = 'button' AND " + of_trial) > 0) return true;
    }
    return false;
  }

 private:
  const SessionThread& session_;
  test::FakeHidPort& port_;
  std::string db_;
};

RunOptions device_session_options(const test::ScratchDir& scratch, test::FakeHidPort& port) {
  test::write_demo_conditions_without_glare(scratch.path() / "conditions.csv");
  const auto experiment =
      test::demo_variant(scratch.path(), {{"file", "file = \"" + (scratch.path() / "conditions.csv").string() + "\""},
                                          {"width_px", "width_px = 512"},
                                          {"height_px", "height_px = 256"},
                                          {"stimulus_frames", "stimulus_frames = 3"},
                                          {"repetitions", "repetitions = 1"}});
  RunOptions options;
  options.experiment_path = experiment.string();
  options.display = "offscreen";
  options.db_path = (scratch.path() / "device.db").string();
  options.response_device = {"1209:0001", "1:0=left,1:1=right,1:2=x", false, port.opener()};
  return options;
}

std::string expected_response(int k) { return k % 2 == 0 ? "left" : "right"; }

TEST(HidSession, ButtonPressesAnswerAnOffscreenForcedChoiceWithDeviceStamps) {
  const test::ScratchDir scratch;
  test::FakeHidPort port;
  const RunOptions options = device_session_options(scratch, port);
  SessionThread session(options);
  DeviceDriver driver(session, port, options.db_path);
  for (int k = 0; driver.wait_for_trials(k) && !session.done(); ++k) {
    if (k == 0) port.click(2);  // "x": a mapped button that is no response
    if (!driver.answer(k, k % 2)) break;
  }
  session.join();
  ASSERT_EQ(session.error(), "");
  ASSERT_EQ(session.result().status, "completed");

  const ResultStore store(options.db_path);
  const SessionRecord record = store.load_sessions().at(0);
  EXPECT_EQ(record.display_backend, "offscreen");
  EXPECT_EQ(record.clock, "monotonic");  // a live device: real time, paced
  EXPECT_EQ(record.observer, "response device fake button box (1:0=left,1:1=right,1:2=x)");
  const auto trials = store.load_trials(record.id);
  ASSERT_EQ(static_cast<int>(trials.size()), session.result().trials_in_design);
  ASSERT_GE(trials.size(), 5u);
  const auto answers = events_of_kind(store, "button");
  ASSERT_EQ(answers.size(), trials.size());
  for (std::size_t k = 0; k < trials.size(); ++k) {
    const int index = static_cast<int>(k);
    EXPECT_EQ(trials[k].trial_index, index);
    EXPECT_EQ(trials[k].response, expected_response(index));
    EXPECT_EQ(answers[k].message, "trial " + std::to_string(k) + ": button '" + expected_response(index) +
                                      "' answered '" + expected_response(index) + "'");
    // The response time is the press's read stamp minus the onset flip, not a poll time.
    ASSERT_TRUE(trials[k].response_time_s.has_value());
    EXPECT_EQ(*trials[k].response_time_s, answers[k].session_time_s - trials[k].onset_s);
    EXPECT_GE(*trials[k].response_time_s, 0.0);
    // Its three stimulus frames (any response-screen flips after them, numbered -1, -2, ..., depend
    // on when the press arrives on the real clock).
    int stimulus_frames = 0;
    for (const FrameRecord& frame : store.load_frames(trials[k].id)) stimulus_frames += frame.frame_index >= 0 ? 1 : 0;
    EXPECT_EQ(stimulus_frames, 3);
  }
  bool x_ignored = false;
  for (const LoggedEvent& event : events_of_kind(store, "ignored_button"))
    x_ignored = x_ignored || event.message.find("button 'x' ") != std::string::npos;
  EXPECT_TRUE(x_ignored);
  const auto summary = events_of_kind(store, "response_device_summary");
  ASSERT_EQ(summary.size(), 1u);
  EXPECT_NE(summary[0].message.find("0 unplug(s)"), std::string::npos) << summary[0].message;
  EXPECT_EQ(store.integrity_check(), "ok");
}

// A button box may have no Space: any button continues an instruction screen (after its minimum),
// and the trials that follow are answered as usual.
TEST(HidSession, AnyButtonContinuesTheInstructionScreen) {
  const test::ScratchDir scratch;
  test::FakeHidPort port;
  const RunOptions options = device_session_options(scratch, port);
  {
    std::ofstream experiment(options.experiment_path, std::ios::app);
    experiment << "\n[presentation]\ninstructions = \"Press a button to begin.\"\n";
  }
  SessionThread session(options);
  DeviceDriver driver(session, port, options.db_path);
  // The session waits on its instruction screen: the first press continues it.
  ASSERT_TRUE(wait_for(session, [&] { return driver.events("kind = 'display'") > 0; })) << session.error();
  const auto continued = [&] { return driver.events("kind = 'button' AND message LIKE '%instructions screen: button%continued'"); };
  for (int attempt = 0; attempt < 100 && continued() == 0 && !session.done(); ++attempt) {
    port.click(2);  // "x": not a response, but it continues a screen
    wait_for(session, [&] { return driver.events("kind IN ('button', 'ignored_button')") > attempt; });
  }
  ASSERT_EQ(continued(), 1) << session.error();
  for (int k = 0; driver.wait_for_trials(k) && !session.done(); ++k)
    if (!driver.answer(k, k % 2)) break;
  session.join();
  ASSERT_EQ(session.error(), "");
  EXPECT_EQ(session.result().status, "completed");
  const ResultStore store(options.db_path);
  const auto trials = store.load_trials(store.load_sessions().at(0).id);
  ASSERT_EQ(static_cast<int>(trials.size()), session.result().trials_in_design);
  for (std::size_t k = 0; k < trials.size(); ++k) EXPECT_EQ(trials[k].response, expected_response(static_cast<int>(k)));
}

TEST(HidSession, UnplugMidTrialPausesWithAMessageAndReRunsTheTrialAfterReplug) {
  const test::ScratchDir scratch;
  test::FakeHidPort port;
  const RunOptions options = device_session_options(scratch, port);
  SessionThread session(options);
  DeviceDriver driver(session, port, options.db_path);
  for (int k = 0; k < 2; ++k) ASSERT_TRUE(driver.wait_for_trials(k) && driver.answer(k, k % 2)) << session.error();
  // Trial 1 is committed: unplugged now, trial 2 finds the device gone at its first poll.
  ASSERT_TRUE(driver.wait_for_trials(2));
  port.unplug();
  ASSERT_TRUE(driver.wait_for_event("device_unplugged")) << session.error();
  EXPECT_EQ(driver.trials(), 2);  // the interrupted trial is not committed
  EXPECT_FALSE(session.done());
  port.replug();
  ASSERT_TRUE(driver.wait_for_event("device_reconnected")) << session.error();
  for (int k = 2; driver.wait_for_trials(k) && !session.done(); ++k)
    if (!driver.answer(k, k % 2)) break;
  session.join();
  ASSERT_EQ(session.error(), "");
  ASSERT_EQ(session.result().status, "completed");
  EXPECT_GE(port.opens(), 2);

  const ResultStore store(options.db_path);
  const SessionRecord record = store.load_sessions().at(0);
  const auto trials = store.load_trials(record.id);
  ASSERT_EQ(static_cast<int>(trials.size()), session.result().trials_in_design);
  for (std::size_t k = 0; k < trials.size(); ++k) {  // every trial exactly once, in order
    EXPECT_EQ(trials[k].trial_index, static_cast<int>(k));
    EXPECT_EQ(trials[k].response, expected_response(static_cast<int>(k)));
    // The re-run's stimulus frames only. The response phase's flips (negative frame_index) last
    // until the driver answers, so their number depends on the machine's load.
    const auto frames = store.load_frames(trials[k].id);
    EXPECT_EQ(std::count_if(frames.begin(), frames.end(), [](const FrameRecord& f) { return f.frame_index >= 0; }), 3);
  }
  const auto unplugged = events_of_kind(store, "device_unplugged");
  const auto reconnected = events_of_kind(store, "device_reconnected");
  ASSERT_EQ(unplugged.size(), 1u);
  ASSERT_EQ(reconnected.size(), 1u);
  const std::string& message = unplugged[0].message;
  EXPECT_EQ(message.rfind("trial 2: fake button box (1:0=left,1:1=right,1:2=x) unplugged", 0), 0u) << message;
  EXPECT_NE(message.find(std::string("'") + kDeviceUnpluggedMessage + "' on screen"), std::string::npos) << message;
  // The pause screen was read back: its text is lit (a 32 px line of 52 characters lights well
  // over 500 pixels; a blank screen would give 0).
  const auto lit_at = message.find(" pixels of text lit");
  ASSERT_NE(lit_at, std::string::npos) << message;
  const auto number_at = message.rfind('(', lit_at) + 1;
  EXPECT_GT(std::stol(message.substr(number_at, lit_at - number_at)), 500) << message;
  EXPECT_NE(reconnected[0].message.find("the trial re-runs from its onset"), std::string::npos);
  // The re-run starts after the pause.
  EXPECT_LT(unplugged[0].session_time_s, reconnected[0].session_time_s);
  EXPECT_LT(reconnected[0].session_time_s, trials[2].onset_s);
  const auto summary = events_of_kind(store, "response_device_summary");
  ASSERT_EQ(summary.size(), 1u);
  EXPECT_NE(summary[0].message.find("1 unplug(s)"), std::string::npos) << summary[0].message;
}

TEST(HidSession, InterruptDuringThePauseAbortsKeepingTheCommittedTrials) {
  const test::ScratchDir scratch;
  test::FakeHidPort port;
  const RunOptions options = device_session_options(scratch, port);
  {
    SessionThread session(options);
    DeviceDriver driver(session, port, options.db_path);
    ASSERT_TRUE(driver.wait_for_trials(0) && driver.answer(0, 0)) << session.error();
    ASSERT_TRUE(driver.wait_for_trials(1));
    port.unplug();
    ASSERT_TRUE(driver.wait_for_event("device_unplugged")) << session.error();
    std::raise(SIGINT);  // the session's handler raises its flag, as Ctrl-C would
    session.join();
    clear_interrupt();
    ASSERT_EQ(session.error(), "");
    EXPECT_EQ(session.result().status, "aborted");
  }
  const ResultStore store(options.db_path);
  const SessionRecord record = store.load_sessions().at(0);
  EXPECT_EQ(record.status, "aborted");
  const auto trials = store.load_trials(record.id);
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].response, "left");
  ASSERT_EQ(events_of_kind(store, "device_pause_aborted").size(), 1u);
  const auto aborted = events_of_kind(store, "aborted");
  ASSERT_EQ(aborted.size(), 1u);
  EXPECT_EQ(aborted[0].message, "interrupted (Ctrl-C or SIGTERM) while the response device was unplugged");
}

TEST(HidSession, DeviceOptionsAreCheckedBeforeAnythingIsWritten) {
  const test::ScratchDir dir;
  const auto experiment = test::demo_variant(dir.path(), {});
  const std::string db = (dir.path() / "none.db").string();
  const auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> arguments = {"run", experiment.string(), "--display", "offscreen", "--db", db};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return test::run_glarelab(arguments, dir.path());
  };
  // No such device (hidapi finds none with these ids): a device error, exit 3.
  auto result = run({"--response-device", "fffe:fffd", "--buttons", "1:0=left,1:1=right"});
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_NE(result.output.find("HID: no device fffe:fffd"), std::string::npos) << result.output;
  // Bad values: input errors naming the option, exit 2.
  result = run({"--response-device", "12345:1", "--buttons", "1:0=left"});
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--response-device: key 'response-device': HID device '12345:1'"), std::string::npos)
      << result.output;
  result = run({"--response-device", "1209:0001"});
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("needs --buttons"), std::string::npos) << result.output;
  result = run({"--response-device", "1209:0001", "--buttons", "1:9=left"});
  EXPECT_EQ(result.exit_code, 2) << result.output;
  result = run({"--response-device", "1209:0001", "--buttons", "1:0=left", "--observer", "simulated"});
  EXPECT_EQ(result.exit_code, 2) << result.output;
  result = run({"--response-device", "1209:0001", "--buttons", "1:0=left", "--response-device-optional"});
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("cannot be optional"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

TEST(HidSession, SelectorsParseAsHexIds) {
  HidSelector selector = parse_hid_selector("1209:0001");
  EXPECT_EQ(selector.vendor_id, 0x1209);
  EXPECT_EQ(selector.product_id, 0x0001);
  EXPECT_FALSE(selector.usage_page.has_value());
  selector = parse_hid_selector("0x046D:c216:0x0C");
  EXPECT_EQ(selector.vendor_id, 0x046d);
  EXPECT_EQ(selector.product_id, 0xc216);
  EXPECT_EQ(selector.usage_page, 0x000c);
  EXPECT_EQ(describe_hid_selector(selector), "046d:c216 usage page 0x000c");
  for (const char* bad : {"", "1209", "1209:", "1209:0001:", "12g9:0001", "12345:0001", "1209:0001:1:2", "-1:2", "+1:2"})
    EXPECT_THROW(parse_hid_selector(bad), DeviceError) << bad;
}

TEST(HidSession, OnlyTheFirstAllowedPressAtOrAfterOnsetAnswers) {
  const std::vector<std::string> allowed = {"left", "right"};
  const std::vector<ButtonEvent> presses = {
      {"right", true, 0.9},   // before the onset at 1.0
      {"x", true, 1.1},       // not a response
      {"2", true, 1.2},       // the digit of "right": the answer
      {"left", true, 1.3},    // after the answer
  };
  const auto decisions = decide_presses(presses, allowed, 1.0, false);
  ASSERT_EQ(decisions.size(), 4u);
  EXPECT_EQ(decisions[0].ignored_because, "pressed before onset");
  EXPECT_EQ(decisions[1].ignored_because, "is not a response");
  ASSERT_TRUE(decisions[2].response.has_value());
  EXPECT_EQ(*decisions[2].response, "right");
  EXPECT_EQ(decisions[2].press.session_time_s, 1.2);
  EXPECT_EQ(decisions[3].ignored_because, "came after the answer");
  EXPECT_FALSE(decisions[3].response.has_value());
  // A press exactly at the onset flip counts; an earlier answer in the poll makes the rest late.
  EXPECT_TRUE(decide_presses({{"left", true, 1.0}}, allowed, 1.0, false)[0].response.has_value());
  EXPECT_EQ(decide_presses({{"left", true, 1.5}}, allowed, 1.0, true)[0].ignored_because, "came after the answer");
}

}  // namespace
}  // namespace glarelab
