// A live session and another process that holds the database's lock (runner/store/lock_wait.h):
// the session waits for as long as the lock is held and loses nothing. Before, a lock held for
// over 5 s ended the run with exit 4.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "cli_process.h"
#include "raw_db.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

int count_rows(const std::string& db, const std::string& table) {
  if (!std::filesystem::exists(db)) return 0;
  sqlite3* handle = nullptr;
  int count = 0;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(handle, 1000);
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(handle, ("SELECT count(*) FROM " + table).c_str(), -1, &statement, nullptr) == SQLITE_OK &&
        sqlite3_step(statement) == SQLITE_ROW)
      count = sqlite3_column_int(statement, 0);
    sqlite3_finalize(statement);
  }
  sqlite3_close_v2(handle);
  return count;
}

TEST(DatabaseLock, ALiveSessionWaitsForALockHeldSevenSecondsAndKeepsEveryTrial) {
  const test::ScratchDir scratch;
  const auto& dir = scratch.path();
  test::write_demo_conditions_without_glare(dir / "conditions.csv");
  // Forty short trials: the run is still going when the lock is taken.
  const auto experiment = test::demo_variant(dir, {{"file", "file = \"" + (dir / "conditions.csv").string() + "\""},
                                                   {"question", "question = \"\""},
                                                   {"stimulus_frames", "stimulus_frames = 4"},
                                                   {"repetitions", "repetitions = 4"},
                                                   {"width_px", "width_px = 256"},
                                                   {"height_px", "height_px = 128"}});
  const std::string db = (dir / "results.db").string();
  test::GlarelabProcess run({"run", experiment.string(), "--db", db, "--display", "offscreen", "--observer",
                             "simulated"},
                            dir / "run.txt");
  ASSERT_TRUE(run.started());
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  // From its first trial on, the session writes through its lock wait.
  while (count_rows(db, "trials") == 0 && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_GE(count_rows(db, "trials"), 1) << test::read_bytes((dir / "run.txt").string());
  ASSERT_LT(count_rows(db, "trials"), 30) << "the run was nearly over before the lock was taken";

  // Another process's write transaction, held for 7 s (beyond the store's 5 s busy timeout).
  sqlite3* holder = nullptr;
  ASSERT_EQ(sqlite3_open_v2(db.c_str(), &holder, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
  // Up to 10 s, asked again every millisecond: the session writes on two connections (its own and
  // its trial commits'), and SQLite's busy timeout, whose sleeps grow to 100 ms, could miss every
  // moment the lock is free until the session has ended.
  sqlite3_busy_handler(
      holder,
      [](void*, int count) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        return count < 10000 ? 1 : 0;
      },
      nullptr);
  ASSERT_EQ(sqlite3_exec(holder, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(holder);
  ASSERT_LT(count_rows(db, "trials"), 40) << "the run ended before the lock was taken";
  std::this_thread::sleep_for(std::chrono::seconds(7));
  ASSERT_EQ(sqlite3_exec(holder, "COMMIT", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close_v2(holder);

  const int exit_code = run.wait();
  const std::string output = test::read_bytes((dir / "run.txt").string());
  ASSERT_EQ(exit_code, 0) << output;
  EXPECT_NE(output.find("waiting for the database: another process has held its lock for 5 s"), std::string::npos)
      << output;
  const test::RawDb store(db);
  EXPECT_EQ(store.value("SELECT status FROM sessions"), "completed");
  EXPECT_EQ(store.value("SELECT count(*) FROM trials"), "40");
  EXPECT_EQ(store.value("SELECT count(DISTINCT trial_index) FROM trials"), "40");
  const std::string locked = store.value("SELECT message FROM session_events WHERE kind = 'database_locked'");
  ASSERT_NE(locked.find("waited for a lock held by another process, the longest "), std::string::npos) << locked;
  const double longest_s = std::stod(locked.substr(locked.find("the longest ") + 12));
  // Beyond the 5 s after which a write used to fail (the line above was printed from this wait).
  EXPECT_GE(longest_s, 5.0);
  EXPECT_EQ(store.value("PRAGMA integrity_check"), "ok");
}

}  // namespace
}  // namespace glarelab
