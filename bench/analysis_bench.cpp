// `glarelab analyze` at scale: 100 sessions x 500 forced-choice trials x 30 frames (1.5 million
// frame rows) plus 20 staircase trials per session, generated once into a temporary database;
// the benchmark loads it, analyses it (bootstrap 200 per fit) and writes CSV, HTML and SVG.
#include <benchmark/benchmark.h>
#include <sqlite3.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>

#include <cmath>
#include <filesystem>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "core/parallel_for.h"
#include "core/random.h"
#include "runner/store/result_store.h"

namespace {

constexpr int kSessions = 100;
constexpr int kTrialsPerSession = 500;
constexpr int kFramesPerTrial = 30;

std::filesystem::path bench_dir() {
  static const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("glarelab-analysis-bench-" + std::to_string(::getpid()));
  return dir;
}

std::string generate_database() {
  std::filesystem::create_directories(bench_dir());
  const std::string path = (bench_dir() / "scale.db").string();
  std::filesystem::remove(path);
  glarelab::ResultStore store(path);
  // Generation only: the benchmark measures analysis, not fsync.
  sqlite3_exec(store.handle(), "PRAGMA synchronous = OFF", nullptr, nullptr, nullptr);
  const glarelab::CounterRandom random(5, glarelab::RandomStream::observer);
  const char* scenes[] = {"Gem", "Park", "Trees", "Bridge"};
  for (int s = 0; s < kSessions; ++s) {
    glarelab::SessionRecord session;
    session.experiment = "scale";
    session.participant = "P" + std::to_string(s);
    session.started_utc = "2026-01-01T00:00:00.000Z";
    session.software_version = "bench";
    session.renderer = "none";
    session.display_backend = "offscreen";
    session.clock = "virtual";
    session.observer = "simulated";
    const auto id = store.begin_session(session);
    for (int t = 0; t < kTrialsPerSession + 20; ++t) {
      glarelab::TrialRecord trial;
      trial.session_id = id;
      trial.trial_index = t;
      trial.onset_s = 1.0 + 0.6 * t;
      trial.response_time_s = 0.3 + 0.5 * random.uniform(static_cast<std::uint64_t>(s * 1000 + t), 1);
      trial.started_utc = session.started_utc;
      const double u = random.uniform(static_cast<std::uint64_t>(s * 1000 + t));
      if (t < kTrialsPerSession) {
        const bool dynamic_left = t % 2 == 0;
        trial.procedure = "forced_choice";
        trial.condition = std::string("{\"scene\":\"") + scenes[t % 4] + "\",\"instruction\":\"brighter\",\"left\":\"" +
                          (dynamic_left ? "dynamic" : "static") + "\",\"right\":\"" + (dynamic_left ? "static" : "dynamic") + "\"}";
        trial.response = (u < 0.7) == dynamic_left ? "left" : "right";
      } else {
        const double intensity = 0.2 + 0.1 * ((t - kTrialsPerSession) % 8);
        trial.procedure = "staircase";
        trial.condition = "{\"name\":\"contrast\"}";
        trial.staircase = "contrast";
        trial.intensity = intensity;
        trial.correct = u < 0.5 + 0.5 / (1.0 + std::exp(-10.0 * (intensity - 0.5))) ? 1 : 0;
        trial.response = *trial.correct ? "left" : "right";
        trial.reversal = (t % 3 == 0) ? 1 : 0;
      }
      std::vector<glarelab::FrameRecord> frames(kFramesPerTrial);
      for (int f = 0; f < kFramesPerTrial; ++f) {
        frames[static_cast<std::size_t>(f)] = {f, trial.onset_s + f / 60.0, trial.onset_s + f / 60.0, false, {}};
      }
      store.commit_trial(trial, frames);
    }
    store.finish_session(id, "completed");
  }
  return path;
}

// CPU seconds of the whole process (all threads), user + system.
double process_cpu_s() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Stage timers (wall seconds) and the process CPU time are reported as counters, so the output
// says where the time goes: load (SQLite + condition parsing), analyse (mostly the bootstrap
// fits, on one thread per core), write (CSV, HTML, SVG).
void BM_AnalyzeHundredSessions(benchmark::State& state) {
  static const std::string path = generate_database();
  const std::string out = (bench_dir() / "out").string();
  double load_s = 0.0, analyse_s = 0.0, write_s = 0.0, cpu_s = 0.0;
  double load_cpu_s = 0.0, analyse_cpu_s = 0.0, write_cpu_s = 0.0;
  for (auto _ : state) {
    const double cpu_start = process_cpu_s();
    auto start = std::chrono::steady_clock::now();
    auto data = glarelab::analysis::load_databases({path});
    load_s += seconds_since(start);
    const double cpu_loaded = process_cpu_s();
    start = std::chrono::steady_clock::now();
    glarelab::analysis::AnalysisOptions options;
    const auto report = glarelab::analysis::analyse(std::move(data), options);
    analyse_s += seconds_since(start);
    const double cpu_analysed = process_cpu_s();
    start = std::chrono::steady_clock::now();
    const auto written = glarelab::analysis::write_report(report, out);
    write_s += seconds_since(start);
    const double cpu_end = process_cpu_s();
    load_cpu_s += cpu_loaded - cpu_start;
    analyse_cpu_s += cpu_analysed - cpu_loaded;
    write_cpu_s += cpu_end - cpu_analysed;
    cpu_s += cpu_end - cpu_start;
    benchmark::DoNotOptimize(written.size());
  }
  const auto runs = static_cast<double>(state.iterations());
  state.counters["load_s"] = load_s / runs;
  state.counters["analyse_s"] = analyse_s / runs;
  state.counters["write_s"] = write_s / runs;
  state.counters["process_cpu_s"] = cpu_s / runs;
  state.counters["load_cpu_s"] = load_cpu_s / runs;
  state.counters["analyse_cpu_s"] = analyse_cpu_s / runs;
  state.counters["write_cpu_s"] = write_cpu_s / runs;
  state.counters["threads"] = glarelab::resolved_threads(0);
  state.counters["sessions"] = kSessions;
  state.counters["trials"] = kSessions * (kTrialsPerSession + 20);
  state.counters["frames"] = static_cast<double>(kSessions) * (kTrialsPerSession + 20) * kFramesPerTrial;
}
BENCHMARK(BM_AnalyzeHundredSessions)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
