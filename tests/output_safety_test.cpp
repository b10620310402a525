// Outputs as a user (or someone with write access to the output folder) meets them: files appear
// whole or not at all, an analysis folder holds one analysis, links are not written through,
// exports keep the database's permissions, spreadsheet formulas in cells are neutralised, and an
// output path that cannot be a folder is the user's mistake (exit 2), not the storage's (4).
#include <gtest/gtest.h>

#include <sqlite3.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "cli_process.h"
#include "core/atomic_file.h"

namespace glarelab {
namespace {

namespace fs = std::filesystem;
using test::read_bytes;
using test::run_glarelab;
using test::ScratchDir;
using test::write_bytes;

std::string demo() { return std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml"; }

// A short finished demo session in DIR/demo.db.
fs::path demo_database(const ScratchDir& scratch) {
  const auto db = scratch.path() / "demo.db";
  const auto run = run_glarelab(
      {"run", demo(), "--display", "offscreen", "--observer", "simulated", "--db", db.string(), "--stop-after", "4"},
      scratch.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  return db;
}

void execute(const fs::path& db, const std::string& sql) {
  sqlite3* handle = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &handle), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(handle, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(handle);
  sqlite3_close(handle);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(AtomicFile, TheDestinationChangesOnlyOnCommitAndALinkThereIsReplacedNotFollowed) {
  const ScratchDir scratch;
  const std::string path = scratch.write("out.csv", "old\n");
  {
    AtomicFile file(path);
    file.stream() << "new, never committed\n";
  }
  EXPECT_EQ(read_bytes(path), "old\n");
  write_file_atomically(path, "new\n");
  EXPECT_EQ(read_bytes(path), "new\n");
  // A link planted at the name: the file takes its place; the link's target keeps its bytes.
  const std::string victim = scratch.write("victim.txt", "keep\n");
  const auto link = scratch.path() / "linked.csv";
  fs::create_symlink(victim, link);
  write_file_atomically(link.string(), "written\n", 0600u);
  EXPECT_EQ(read_bytes(victim), "keep\n");
  EXPECT_FALSE(fs::is_symlink(link));
  EXPECT_EQ(read_bytes(link.string()), "written\n");
  EXPECT_EQ(fs::status(link).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
  // Nothing is left beside them.
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(scratch.path())) ++entries;
  EXPECT_EQ(entries, 3);
}

TEST(OutputSafety, AnAnalysisFolderHoldsOneAnalysisAndItsManifestReachesNoFurther) {
  const ScratchDir scratch;
  const auto db = demo_database(scratch);
  const auto out = scratch.path() / "analysis";
  ASSERT_EQ(run_glarelab({"analyze", db.string(), "--out", out.string()}, scratch.path()).exit_code, 0);
  const std::vector<std::string> first = lines_of(read_bytes((out / "manifest.txt").string()));
  ASSERT_FALSE(first.empty());
  for (const std::string& name : first) EXPECT_TRUE(fs::is_regular_file(out / name)) << name;

  // A previous analysis' own file (listed), a file of the user's (not listed), and lines that
  // point outside the folder.
  write_bytes((out / "figures" / "old_figure.svg").string(), "<svg/>");
  write_bytes((out / "my_notes.txt").string(), "mine");
  write_bytes((scratch.path() / "outside.txt").string(), "outside");
  std::string manifest = read_bytes((out / "manifest.txt").string());
  manifest += "figures/old_figure.svg\n../outside.txt\n" + (scratch.path() / "outside.txt").string() + "\n";
  write_bytes((out / "manifest.txt").string(), manifest);

  const auto again = run_glarelab({"analyze", db.string(), "--out", out.string()}, scratch.path());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_FALSE(fs::exists(out / "figures" / "old_figure.svg"));
  EXPECT_EQ(read_bytes((out / "my_notes.txt").string()), "mine");
  EXPECT_EQ(read_bytes((scratch.path() / "outside.txt").string()), "outside");
  EXPECT_EQ(lines_of(read_bytes((out / "manifest.txt").string())), first);
  // "wrote N files" is what the folder holds of glarelab's.
  EXPECT_NE(again.output.find("wrote " + std::to_string(first.size()) + " files"), std::string::npos) << again.output;
}

TEST(OutputSafety, AnalyzeReplacesLinksInItsFolderWithoutWritingTheirTargets) {
  const ScratchDir scratch;
  const auto db = demo_database(scratch);
  const auto out = scratch.path() / "analysis";
  fs::create_directories(out);
  const std::string victim = scratch.write("victim.txt", "keep");
  fs::create_symlink(victim, out / "report.html");
  fs::create_symlink(scratch.path() / "created_by_link.csv", out / "trials.csv");  // dangling
  const auto result = run_glarelab({"analyze", db.string(), "--out", out.string()}, scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(read_bytes(victim), "keep");
  EXPECT_FALSE(fs::exists(scratch.path() / "created_by_link.csv"));
  EXPECT_FALSE(fs::is_symlink(out / "report.html"));
  EXPECT_NE(read_bytes((out / "report.html").string()).find("<html"), std::string::npos);
}

TEST(OutputSafety, ExportsTakeTheDatabasesPermissionsNotTheUmask) {
  const ScratchDir scratch;
  const auto db = demo_database(scratch);
  fs::permissions(db, fs::perms::owner_read | fs::perms::owner_write);
  const mode_t previous = ::umask(0);  // the child inherits it: 0666 files without the fix
  const auto result = run_glarelab({"analyze", db.string(), "--out", (scratch.path() / "out").string()}, scratch.path());
  ::umask(previous);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* name : {"trials.csv", "frames.csv", "report.html", "manifest.txt"})
    EXPECT_EQ(fs::status(scratch.path() / "out" / name).permissions() & fs::perms::all,
              fs::perms::owner_read | fs::perms::owner_write)
        << name;
}

TEST(OutputSafety, FormulaCellsAreNeutralisedUnlessAskedRawAndNumbersStayNumbers) {
  const ScratchDir scratch;
  const auto db = demo_database(scratch);
  execute(db, "UPDATE sessions SET participant = '=HYPERLINK(\"http://x\",\"y\")'; "
              "UPDATE trials SET response = '@SUM(A1)', staircase = '-0.5' WHERE trial_index = 0;");
  const auto out = scratch.path() / "out";
  ASSERT_EQ(run_glarelab({"analyze", db.string(), "--out", out.string()}, scratch.path()).exit_code, 0);
  const std::string csv = read_bytes((out / "trials.csv").string());
  EXPECT_NE(csv.find("\"'=HYPERLINK(\"\"http://x\"\",\"\"y\"\")\""), std::string::npos) << csv.substr(0, 600);
  EXPECT_NE(csv.find(",'@SUM(A1),"), std::string::npos);
  EXPECT_NE(csv.find(",-0.5,"), std::string::npos);
  EXPECT_EQ(csv.find(",=HYPERLINK"), std::string::npos);

  const auto raw = scratch.path() / "raw";
  ASSERT_EQ(run_glarelab({"analyze", db.string(), "--out", raw.string(), "--raw-csv-cells"}, scratch.path()).exit_code, 0);
  const std::string raw_csv = read_bytes((raw / "trials.csv").string());
  EXPECT_NE(raw_csv.find(",@SUM(A1),"), std::string::npos);
  EXPECT_NE(raw_csv.find("\"=HYPERLINK("), std::string::npos);
}

TEST(OutputSafety, OutputsNamedThroughALinkAreRefusedAndTheTargetKept) {
  const ScratchDir scratch;
  const std::string victim = scratch.write("victim.csv", "keep");
  const auto link = scratch.path() / "trace.csv";
  fs::create_symlink(victim, link);
  const auto trace = run_glarelab({"eye-trace", "--duration-s", "1", "--out", link.string()}, scratch.path());
  EXPECT_EQ(trace.exit_code, 2) << trace.output;
  EXPECT_NE(trace.output.find("--out: " + link.string() + " is a symbolic link (to " + victim + ")"), std::string::npos)
      << trace.output;
  EXPECT_EQ(read_bytes(victim), "keep");

  const auto dangling = scratch.path() / "frame.exr";
  fs::create_symlink(scratch.path() / "made_through_link.exr", dangling);
  const auto render = run_glarelab({"render", demo(), "--condition", "dynamic_1.000", "--out", dangling.string()},
                                   scratch.path());
  EXPECT_EQ(render.exit_code, 2) << render.output;
  EXPECT_NE(render.output.find("is a symbolic link"), std::string::npos) << render.output;
  EXPECT_FALSE(fs::exists(scratch.path() / "made_through_link.exr"));

  // The file itself, named: written.
  const auto direct = run_glarelab({"eye-trace", "--duration-s", "1", "--out", victim}, scratch.path());
  EXPECT_EQ(direct.exit_code, 0) << direct.output;
  EXPECT_EQ(read_bytes(victim).rfind("time_s,", 0), 0u);
}

// `fit --out`, `calibrate --out` and `psf --profile-csv` as the other outputs: a link is refused (exit 2, before anything
// is computed or shown) and its target kept; the file named itself is written whole.
TEST(OutputSafety, FitCalibrateAndPsfRefuseALinkAtTheirOutput) {
  const ScratchDir scratch;
  const std::string data = scratch.write("data.csv", "level,correct,trials\n1,5,10\n2,6,10\n3,8,10\n4,10,10\n");
  const std::string victim = scratch.write("victim.json", "keep");
  const auto link = scratch.path() / "result.json";
  fs::create_symlink(victim, link);
  const auto fit = run_glarelab({"fit", data, "--out", link.string()}, scratch.path());
  EXPECT_EQ(fit.exit_code, 2) << fit.output;
  EXPECT_NE(fit.output.find("--out: " + link.string() + " is a symbolic link (to " + victim + ")"), std::string::npos)
      << fit.output;
  EXPECT_EQ(read_bytes(victim), "keep");
  const auto direct = run_glarelab({"fit", data, "--out", (scratch.path() / "direct.json").string()}, scratch.path());
  EXPECT_EQ(direct.exit_code, 0) << direct.output;
  EXPECT_EQ(read_bytes((scratch.path() / "direct.json").string()).rfind("{", 0), 0u);

  const auto dangling = scratch.path() / "display.csv";
  fs::create_symlink(scratch.path() / "made_through_link.csv", dangling);
  const auto calibrate = run_glarelab({"calibrate", "--display", "offscreen", "--levels", "2", "--measurements",
                                       scratch.write("readings.txt", "1\n"), "--out", dangling.string()},
                                      scratch.path());
  EXPECT_EQ(calibrate.exit_code, 2) << calibrate.output;
  EXPECT_NE(calibrate.output.find("is a symbolic link"), std::string::npos) << calibrate.output;
  EXPECT_FALSE(fs::exists(scratch.path() / "made_through_link.csv"));

  const std::string profile_victim = scratch.write("profile_victim.csv", "keep");
  const auto profile_link = scratch.path() / "profile.csv";
  fs::create_symlink(profile_victim, profile_link);
  const auto psf = run_glarelab({"psf", "--model", "cie", "--profile-csv", profile_link.string()}, scratch.path());
  EXPECT_EQ(psf.exit_code, 2) << psf.output;
  EXPECT_NE(psf.output.find("--profile-csv: " + profile_link.string() + " is a symbolic link"), std::string::npos)
      << psf.output;
  EXPECT_EQ(read_bytes(profile_victim), "keep");
}

TEST(OutputSafety, AFileWhereAFolderMustBeIsTheUsersMistake) {
  const ScratchDir scratch;
  const auto db = demo_database(scratch);
  const auto sub = db / "sub";
  const auto analyze = run_glarelab({"analyze", db.string(), "--out", sub.string()}, scratch.path());
  EXPECT_EQ(analyze.exit_code, 2) << analyze.output;
  EXPECT_NE(analyze.output.find(sub.string() + ": " + db.string() + " is a file, not a directory"), std::string::npos)
      << analyze.output;

  const std::string file = scratch.write("frames", "a file");
  const auto other_db = scratch.path() / "frames.db";
  const auto run = run_glarelab({"run", demo(), "--display", "offscreen", "--observer", "simulated", "--db",
                                 other_db.string(), "--stop-after", "1", "--save-frames", file},
                                scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--save-frames: " + file + " is a file, not a directory"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(other_db));
  EXPECT_EQ(read_bytes(file), "a file");
}

}  // namespace
}  // namespace glarelab
