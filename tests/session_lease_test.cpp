// One owner per session (runner/store/session_lease.h, docs/DATABASE.md "session_owners"): a run
// and resumes of its session raced as users would start them, with the processes killed at random
// moments. Every race must leave one owner at a time, a session status that tells the truth and
// every trial of the uninterrupted run.
#include <gtest/gtest.h>
#include <signal.h>

#include <sqlite3.h>
#include <unistd.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/random.h"
#include "runner/store/result_store.h"
#include "cli_process.h"
#include "scratch_dir.h"
#include "raw_db.h"

namespace glarelab {
namespace {

using test::GlarelabProcess;
using test::read_bytes;

struct Finished {
  int exit_code = -1;
  pid_t pid = -1;
  std::string output;
};

// Starts every command at once and waits for all of them.
std::vector<Finished> run_together(const std::vector<std::vector<std::string>>& commands,
                                   const std::filesystem::path& dir, const std::string& tag) {
  std::vector<std::unique_ptr<GlarelabProcess>> processes;
  std::vector<std::filesystem::path> outputs;
  std::vector<pid_t> pids;
  for (std::size_t i = 0; i < commands.size(); ++i) {
    outputs.push_back(dir / (tag + "-" + std::to_string(i) + ".txt"));
    processes.push_back(std::make_unique<GlarelabProcess>(commands[i], outputs.back()));
    pids.push_back(processes.back()->pid());
  }
  std::vector<Finished> finished;
  for (std::size_t i = 0; i < processes.size(); ++i) {
    Finished result;
    result.pid = pids[i];
    result.exit_code = processes[i]->wait();
    result.output = read_bytes(outputs[i].string());
    finished.push_back(result);
  }
  return finished;
}

// What `sql` (a count) gives in `db` now; -1 while the file, its schema or the row are not there
// yet (a run still starting), on a read-only connection of its own that never fails the test.
long long count_now(const std::filesystem::path& db, const std::string& sql) {
  if (!std::filesystem::exists(db)) return -1;
  sqlite3* handle = nullptr;
  long long count = -1;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(handle, 1000);
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(handle, sql.c_str(), -1, &statement, nullptr) == SQLITE_OK &&
        sqlite3_step(statement) == SQLITE_ROW)
      count = sqlite3_column_int64(statement, 0);
    sqlite3_finalize(statement);
  }
  sqlite3_close_v2(handle);
  return count;
}

// Waits until the run has logged what `sql` counts, at least `at_least` of it (at most 120 s: a
// run that never gets there fails the race's checks after it).
void wait_until_logged(const std::filesystem::path& db, const std::string& sql, long long at_least) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (count_now(db, sql) < at_least && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Whether a writer could take `db`'s write lock now (asked with no wait, then let go).
bool write_lock_free(const std::filesystem::path& db) {
  sqlite3* handle = nullptr;
  bool free = false;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(handle, 0);
    free = sqlite3_exec(handle, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr) == SQLITE_OK;
    if (free) sqlite3_exec(handle, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  sqlite3_close_v2(handle);
  return free;
}

// Whether process `pid` is stopped (state T in /proc/PID/stat, after the name in parentheses).
bool stopped(pid_t pid) {
  const std::string stat = read_bytes("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t name_end = stat.rfind(')');
  return name_end != std::string::npos && name_end + 2 < stat.size() && stat[name_end + 2] == 'T';
}

// Stops `run` at a moment it holds no write lock on `db`: a process stopped inside a transaction
// would hold back every other writer until it is killed. A stopped process still runs, for the
// lease (runner/store/process_identity.h): its session has a live owner however long it stays
// stopped, on however slow a host.
void stop_outside_a_write(const GlarelabProcess& run, const std::filesystem::path& db) {
  for (;;) {
    run.signal(SIGSTOP);
    while (!stopped(run.pid())) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (write_lock_free(db)) return;
    run.signal(SIGCONT);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

// What a refused resume may say: the session's live holder named, the session not yet written
// (its run had not got that far), or already completed by the one that ran it.
bool refused_truthfully(const Finished& resume, const std::vector<pid_t>& live_holders) {
  if (resume.exit_code == 2) return contains(resume.output, "is already completed");
  if (resume.exit_code != 4) return false;
  for (const pid_t holder : live_holders)
    if (contains(resume.output, "is being run by process " + std::to_string(holder) + " on host")) return true;
  return contains(resume.output, "no session 1") || contains(resume.output, "no such database");
}

std::vector<std::string> column_of(const std::string& db, const std::string& sql) {
  std::vector<std::string> values;
  for (const auto& row : test::RawDb(db).rows(sql)) values.push_back(row.at(0));
  return values;
}

std::vector<std::string> trial_rows(const std::string& db) {
  return column_of(db,
      "SELECT trial_index || ' ' || condition || ' ' || response || ' ' || ifnull(correct, '') FROM trials "
      "WHERE session_id = 1 ORDER BY trial_index");
}

TEST(SessionLease, ARunAndTwoResumesRacedTwentyTimesLeaveOneOwnerAndEveryTrial) {
  const test::ScratchDir scratch;
  const auto& dir = scratch.path();
  test::write_demo_conditions_without_glare(dir / "conditions.csv");
  // Ten short trials on the real clock, so that a run lasts long enough to be raced (about 2 s).
  const auto experiment = test::demo_variant(dir, {{"file", "file = \"" + (dir / "conditions.csv").string() + "\""},
                                                   {"question", "question = \"\""},
                                                   {"stimulus_frames", "stimulus_frames = 8"},
                                                   {"width_px", "width_px = 256"},
                                                   {"height_px", "height_px = 128"}})
                              .string();
  auto command = [&](const std::filesystem::path& db, bool resume) {
    std::vector<std::string> arguments = {"run", experiment, "--db", db.string(), "--display", "offscreen",
                                          "--observer", "simulated", "--clock", "real"};
    if (resume) arguments.insert(arguments.end(), {"--resume", "1"});
    return arguments;
  };
  const auto reference_start = std::chrono::steady_clock::now();
  const auto reference = test::run_glarelab(command(dir / "reference.db", false), dir);
  ASSERT_EQ(reference.exit_code, 0) << reference.output;
  const double run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - reference_start).count();
  const std::vector<std::string> expected = trial_rows((dir / "reference.db").string());
  ASSERT_EQ(expected.size(), 10u);

  const CounterRandom random(2026, RandomStream::trial_order);
  int refused_by_a_live_run = 0;
  int orphans_raced = 0;
  for (int race = 0; race < 20; ++race) {
    const auto db = dir / ("race-" + std::to_string(race) + ".db");
    // Odd races meet the run at random moments of a run as long as the reference (from before its
    // session row to after its completion). Even ones stop it once it has committed 1 to 8 of its
    // 10 trials, start the resumes while it is stopped and kill it after them, so that however
    // much faster or slower than the reference a loaded host makes the run and the resumes (under
    // the sanitizers a resume takes longer than the rest of a run), half the races meet a live
    // owner and race for a killed run's session.
    const bool at_logged_moments = race % 2 == 0;
    // 1. Two resumes while the run lives: both refused, the run untouched.
    GlarelabProcess run(command(db, false), dir / ("run-" + std::to_string(race) + ".txt"));
    ASSERT_TRUE(run.started());
    const pid_t run_pid = run.pid();
    if (at_logged_moments) {
      wait_until_logged(db, "SELECT count(*) FROM trials",
                        1 + static_cast<long long>(random.uniform(2 * race + 1) * 8.0));
      stop_outside_a_write(run, db);
    } else {
      std::this_thread::sleep_for(std::chrono::duration<double>(random.uniform(2 * race) * 0.6 * run_s));
    }
    const std::vector<Finished> while_live =
        run_together({command(db, true), command(db, true)}, dir, "live-" + std::to_string(race));
    // 2. The run killed after that (at once where it was stopped, else at a random moment); two
    // resumes race for what it left.
    if (!at_logged_moments)
      std::this_thread::sleep_for(std::chrono::duration<double>(random.uniform(2 * race + 1) * 0.4 * run_s));
    run.signal(SIGKILL);
    const int run_exit = run.wait();
    const std::string run_output = read_bytes((dir / ("run-" + std::to_string(race) + ".txt")).string());
    for (const Finished& resume : while_live) {
      if (resume.exit_code == 0) {
        // Only possible in the moment between the run's session row and its claim on it: the
        // resume then holds the session and the run stops, naming it.
        EXPECT_EQ(run_exit, 4) << "race " << race << ": a resume ran beside a live run";
        EXPECT_TRUE(contains(run_output, "is being run by process " + std::to_string(resume.pid))) << run_output;
        continue;
      }
      EXPECT_TRUE(refused_truthfully(resume, {run_pid})) << "race " << race << ": " << resume.output;
      if (contains(resume.output, "is being run by process")) ++refused_by_a_live_run;
    }
    // Killed before its session row: no file yet, a file whose schema had not been committed, or
    // a schema without a session.
    if (!std::filesystem::exists(db) ||
        test::RawDb(db.string()).value("SELECT count(*) FROM sqlite_master WHERE name = 'sessions'") == "0" ||
        test::RawDb(db.string()).value("SELECT count(*) FROM sessions") == "0")
      continue;
    const bool completed_before =
        test::RawDb(db.string()).value("SELECT status FROM sessions WHERE id = 1") == "completed";
    const bool owner_left = test::RawDb(db.string()).value("SELECT count(*) FROM session_owners") == "1";
    const std::vector<Finished> orphaned =
        run_together({command(db, true), command(db, true)}, dir, "orphan-" + std::to_string(race));
    int winners = 0;
    for (const Finished& resume : orphaned) {
      if (resume.exit_code == 0) {
        ++winners;
        continue;
      }
      std::vector<pid_t> others;
      for (const Finished& other : orphaned)
        if (other.pid != resume.pid) others.push_back(other.pid);
      EXPECT_TRUE(refused_truthfully(resume, others)) << "race " << race << ": " << resume.output;
    }
    if (!completed_before) {
      ++orphans_raced;
      EXPECT_EQ(winners, 1) << "race " << race << ": exactly one resume runs a killed run's session";
    } else {
      EXPECT_EQ(winners, 0) << "race " << race << ": a completed session was run again";
    }
    const test::RawDb store(db.string());
    EXPECT_EQ(store.value("SELECT status FROM sessions WHERE id = 1"), "completed") << "race " << race;
    EXPECT_EQ(trial_rows(db.string()), expected) << "race " << race;
    EXPECT_EQ(store.value("SELECT count(*) FROM session_owners"), "0") << "race " << race << ": an owner left behind";
    EXPECT_EQ(store.value("PRAGMA integrity_check"), "ok");
    // The winner says whose session it took over when the run was killed holding it.
    if (!completed_before && owner_left) {
      EXPECT_EQ(store.value("SELECT count(*) FROM session_events WHERE kind = 'resumed' AND message LIKE "
                            "'%taken over from process " +
                            std::to_string(run_pid) + " on host%'"),
                "1")
          << "race " << race;
    }
  }
  // The races must really have met a live run and raced for killed runs' sessions.
  EXPECT_GE(refused_by_a_live_run, 10);
  EXPECT_GE(orphans_raced, 10);
  std::cout << "races: 20, resumes refused by a live run: " << refused_by_a_live_run
            << ", killed runs' sessions raced for: " << orphans_raced << " (one run " << run_s << " s)\n";
}

}  // namespace
}  // namespace glarelab
