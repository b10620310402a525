// One owner per session (runner/store/session_lease.h, docs/DATABASE.md "session_owners"): a run
// and resumes of its session raced as users would start them, with the processes killed at random
// moments. Every race must leave one owner at a time, a session status that tells the truth and
// every trial of the uninterrupted run.
#include <gtest/gtest.h>
#include <signal.h>

#include <unistd.h>

#include <chrono>
#include <fstream>
#include <set>
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

// The pids of this thread's children (Linux, /proc/self/task/TID/children): which process a test
// just started, to recognise it when a refusal names it.
std::set<pid_t> children() {
  std::ifstream file("/proc/self/task/" + std::to_string(::gettid()) + "/children");
  std::set<pid_t> pids;
  for (pid_t pid; file >> pid;) pids.insert(pid);
  return pids;
}

pid_t started_since(const std::set<pid_t>& before) {
  for (const pid_t pid : children())
    if (!before.count(pid)) return pid;
  return -1;
}

// Starts every command at once and waits for all of them.
std::vector<Finished> run_together(const std::vector<std::vector<std::string>>& commands,
                                   const std::filesystem::path& dir, const std::string& tag) {
  std::vector<std::unique_ptr<GlarelabProcess>> processes;
  std::vector<std::filesystem::path> outputs;
  std::vector<pid_t> pids;
  for (std::size_t i = 0; i < commands.size(); ++i) {
    outputs.push_back(dir / (tag + "-" + std::to_string(i) + ".txt"));
    const std::set<pid_t> before = children();
    processes.push_back(std::make_unique<GlarelabProcess>(commands[i], outputs.back()));
    pids.push_back(started_since(before));
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

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

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
    // 1. Two resumes while the run lives: both refused, the run untouched.
    const std::set<pid_t> before_run = children();
    GlarelabProcess run(command(db, false), dir / ("run-" + std::to_string(race) + ".txt"));
    ASSERT_TRUE(run.started());
    const pid_t run_pid = started_since(before_run);
    ASSERT_GT(run_pid, 0);
    std::this_thread::sleep_for(std::chrono::duration<double>(random.uniform(2 * race) * 0.6 * run_s));
    const std::vector<Finished> while_live =
        run_together({command(db, true), command(db, true)}, dir, "live-" + std::to_string(race));
    // 2. The run killed at a random moment after that; two resumes race for what it left.
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
