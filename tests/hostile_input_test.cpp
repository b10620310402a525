// Inputs written to crash, hang or take over the terminal, run through the command line as a user
// would: each ends in its documented exit code and a message that says what is wrong and where,
// within time and memory, with nothing written.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>

#include "cli_process.h"
#include "core/exr_io.h"
#include "core/image.h"

namespace glarelab {
namespace {

using test::demo_variant;
using test::run_glarelab;
using test::ScratchDir;

std::filesystem::path demo_conditions() { return std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples/demo_conditions.csv"; }

// The demo with its condition table replaced by `csv` (written beside it; the demo's own when
// empty), its description line by `description_line` when given, and `extra` lines put right
// after the [experiment] header (line 17, so the first extra line is line 18).
std::filesystem::path demo_with(const ScratchDir& scratch, const std::string& csv, const std::string& extra = "",
                                const std::string& description_line = "") {
  const std::string table = csv.empty() ? demo_conditions().string() : scratch.write("conditions.csv", csv);
  std::vector<std::pair<std::string, std::string>> replacements = {{"file", "file = \"" + table + "\""}};
  if (!description_line.empty()) replacements.emplace_back("description", description_line);
  const auto path = demo_variant(scratch.path(), replacements);
  std::string text = test::read_bytes(path.string());
  const auto header = text.find("[experiment]\n");
  text.insert(header + 13, extra.empty() ? "" : extra + "\n");
  test::write_bytes(path.string(), text);
  return path;
}

// A POSIX shell word, written independently of core/text_limits.h's shell_quoted: always quoted.
std::string shell_word(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\"'\"'") : std::string(1, c);
  return out + "'";
}

bool has_control_bytes(const std::string& text) {
  for (const char c : text)
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') || c == 0x7F) return true;
  return false;
}

// `script` run by /bin/sh -c (output of both streams).
test::RunOutput run_glarelab_shell(const std::string& script, const std::filesystem::path& dir) {
  const auto output = dir / "shell-output.txt";
  test::RunOutput result;
  const int status = std::system(("/bin/sh -c " + shell_word(script) + " > '" + output.string() + "' 2>&1").c_str());
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.output = test::read_bytes(output.string());
  return result;
}

double seconds_of(const std::function<void()>& body) {
  const auto start = std::chrono::steady_clock::now();
  body();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(HostileInput, ADottedKeyOfManyPartsIsRefusedAtItsPlaceNotByTheStack) {
  const ScratchDir scratch;
  // 300,000 parts: toml++ made one nested table per part and overflowed the stack (exit 139).
  std::string key = "a";
  for (int i = 1; i < 300000; ++i) key += ".a";
  const auto experiment = demo_with(scratch, "", key + " = 1");
  const auto db = scratch.path() / "results.db";
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"validate", experiment.string()},
        {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db", db.string()}}) {
    const auto result = run_glarelab(command, scratch.path());
    EXPECT_EQ(result.exit_code, 2) << command[0] << ": " << result.output.substr(0, 400);
    // Refused at its 129th dot (column 258): 128 levels are read, the one more is not.
    EXPECT_NE(result.output.find(experiment.string() + ":18:258: nested deeper than 128 levels"), std::string::npos)
        << result.output.substr(0, 400);
    EXPECT_LT(result.output.size(), 2000u);
  }
  EXPECT_FALSE(std::filesystem::exists(db));
}

TEST(HostileInput, DeeplyNestedArraysAndInlineTablesAreRefusedAndShallowOnesRead) {
  const ScratchDir scratch;
  std::string deep = "x = ";
  for (int i = 0; i < 200; ++i) deep += "[{ y = ";
  const auto result = run_glarelab({"validate", demo_with(scratch, "", deep).string()}, scratch.path());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("nested deeper than 128 levels"), std::string::npos) << result.output;
  // Dots in strings and comments are not key parts: a file full of them is read as before.
  std::string dots(1000, '.');
  const auto shallow = run_glarelab(
      {"validate", demo_with(scratch, "", "# " + dots, "description = \"" + dots + "\" # " + dots).string()},
      scratch.path());
  EXPECT_EQ(shallow.exit_code, 0) << shallow.output;
}

TEST(HostileInput, ConditionTablesAreReadInTimeLinearInTheirRows) {
  const ScratchDir scratch;
  // validate of 5k, 10k and 20k rows took 1.2 s, 6.7 s and 88.6 s (each row's refraction scanned
  // every row): the time per row must not grow with the table.
  const auto time_rows = [&](int rows) {
    std::string csv = "name,scene_a,scene_b,glare_a,glare_b,luminance_ratio\n";
    for (int i = 0; i < rows; ++i) csv += "c" + std::to_string(i) + ",lamp_130,lamp_100,control,control,0.769231\n";
    const ScratchDir dir;
    const auto experiment = demo_variant(dir.path(), {{"file", "file = \"" + dir.write("conditions.csv", csv) + "\""}});
    test::RunOutput result;
    const double seconds = seconds_of([&] { result = run_glarelab({"validate", experiment.string()}, dir.path()); });
    EXPECT_EQ(result.exit_code, 0) << result.output.substr(0, 400);
    return seconds;
  };
  const double small_s = time_rows(5000);
  const double large_s = time_rows(40000);
  // Eight times the rows: 8 x the time when linear (plus the fixed start), 64 x when quadratic.
  EXPECT_LT(large_s, 20.0 * small_s) << "5k rows " << small_s << " s, 40k rows " << large_s << " s";
}

TEST(HostileInput, AHugeCellIsQuotedShortWithItsLength) {
  const ScratchDir scratch;
  const std::string huge(20 << 20, 'x');
  const auto experiment =
      demo_with(scratch, "name,scene_a,scene_b,glare_a,glare_b,luminance_ratio\nrow,lamp_130," + huge + ",control,control,1\n");
  const auto result = run_glarelab({"validate", experiment.string()}, scratch.path());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_LT(result.output.size(), 5000u);
  EXPECT_NE(result.output.find("unknown scene 'xxxx"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("... (20971520 bytes in all)'"), std::string::npos) << result.output;
}

// A finished demo session whose database is then edited as `sql` says (an attacker with write
// access to the file, or a damaged one), analysed into `out`.
struct EditedAnalysis {
  test::RunOutput result;
  double seconds = 0.0;
};

EditedAnalysis analyze_edited(const ScratchDir& scratch, const std::string& sql) {
  const auto db = scratch.path() / "demo.db";
  const std::string demo = std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml";
  const auto run = run_glarelab({"run", demo, "--display", "offscreen", "--observer", "simulated", "--db", db.string(),
                                 "--stop-after", "6"},
                                scratch.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  sqlite3* handle = nullptr;
  EXPECT_EQ(sqlite3_open(db.c_str(), &handle), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(handle, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(handle);
  sqlite3_close(handle);
  EditedAnalysis edited;
  edited.seconds = seconds_of([&] {
    edited.result = run_glarelab({"analyze", db.string(), "--out", (scratch.path() / "out").string()}, scratch.path());
  });
  return edited;
}

TEST(HostileInput, AnalyzeReadsInfiniteResponseTimesAsEmptyAndSaysSo) {
  for (const char* value : {"9e999", "-9e999"}) {  // SQLite reads 9e999 as +inf
    const ScratchDir scratch;
    const auto edited =
        analyze_edited(scratch, std::string("UPDATE trials SET response_time_s = ") + value + " WHERE trial_index < 2;");
    EXPECT_EQ(edited.result.exit_code, 0) << edited.result.output;  // was 139: a NaN bin cast to an index
    EXPECT_NE(edited.result.output.find("2 response time(s) or intensit(ies) that are not finite numbers: read as empty"),
              std::string::npos)
        << edited.result.output;
    EXPECT_TRUE(std::filesystem::exists(scratch.path() / "out" / "report.html"));
  }
}

TEST(HostileInput, AnalyzeRefusesADeeplyNestedConditionAndReadsAWideOneInTime) {
  const ScratchDir scratch;
  const std::string deep = "{\"name\":\"deep\",\"v\":" + std::string(100000, '[') + std::string(100000, ']') + "}";
  std::string wide = "{\"name\":\"wide\"";
  for (int i = 0; i < 200000; ++i) wide += ",\"k" + std::to_string(i) + "\":\"" + std::to_string(i) + "\"";
  wide += "}";
  const auto edited = analyze_edited(scratch, "UPDATE trials SET condition = '" + deep + "' WHERE trial_index = 0; " +
                                                  "UPDATE trials SET condition = '" + wide + "' WHERE trial_index = 1;");
  EXPECT_EQ(edited.result.exit_code, 0) << edited.result.output.substr(0, 2000);
  // The deep one is not a condition glarelab reads (it names its trial instead); the wide one is.
  EXPECT_NE(edited.result.output.find("1 trial(s) with a condition that is not a JSON object"), std::string::npos)
      << edited.result.output.substr(0, 2000);
  // 200k keys took over 120 s (nlohmann's ordered_json searches its key vector on every insert).
  EXPECT_LT(edited.seconds, 30.0);
  std::cout << "analyze with a 200k-key condition: " << edited.seconds << " s\n";
}

TEST(HostileInput, ControlCharactersFromConditionTablesAndDatabasesAreEscapedInEveryMessage) {
  // OSC 0 (retitle), CSI 2J (clear), SGR 31 (red), a C1 CSI (U+009B) and a bare carriage return.
  const std::string sequence = "\x1b]0;owned\x07\x1b[2J\x1b[31m\xc2\x9b" "1m\rend";
  const std::string escaped = "\\x1b]0;owned\\x07\\x1b[2J\\x1b[31m\\u009b1m\\rend";
  {
    const ScratchDir scratch;
    const auto bad = demo_with(scratch, "name,scene_a,scene_b,glare_a,glare_b,luminance_ratio\nrow,lamp_130,\"lamp" +
                                            sequence + "\",control,control,1\n");
    const auto refused = run_glarelab({"validate", bad.string()}, scratch.path());
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_FALSE(has_control_bytes(refused.output)) << refused.output;
    EXPECT_EQ(refused.output.find("\xc2\x9b"), std::string::npos);
    EXPECT_NE(refused.output.find("unknown scene 'lamp" + escaped + "'"), std::string::npos) << refused.output;
  }
  {
    // A condition value from the database (JSON escapes, decoded to the same bytes) names a group
    // in analyze's summary.
    const ScratchDir scratch;
    const std::string json_sequence = "\\u001b]0;owned\\u0007\\u001b[2J\\u001b[31m\\u009b1m\\rend";
    const auto edited = analyze_edited(
        scratch, "UPDATE trials SET condition = replace(condition, '\"glare_a\":\"control\"', '\"glare_a\":\"control" +
                     json_sequence + "\"');");
    EXPECT_EQ(edited.result.exit_code, 0) << edited.result.output;
    EXPECT_FALSE(has_control_bytes(edited.result.output)) << edited.result.output;
    EXPECT_NE(edited.result.output.find("control" + escaped), std::string::npos) << edited.result.output;
  }
}

TEST(HostileInput, ThePrintedFinishCommandRunsAsPrintedWhenPastedIntoAShell) {
  const ScratchDir scratch;
  // A folder whose name a shell would run ($(...)) and a quote in the database's name.
  const auto folder = scratch.path() / "$(touch pwned) (x)";
  std::filesystem::create_directories(folder);
  const auto db = folder / "it's.db";
  // The demo's lamps without glare on a small display, its file in that folder too: a session
  // whose paths are hostile, not one whose frames take long.
  test::write_demo_conditions_without_glare(folder / "conditions.csv");
  const std::string demo = demo_variant(folder, {{"file", "file = \"" + (folder / "conditions.csv").string() + "\""},
                                                       {"width_px", "width_px = 256"},
                                                       {"height_px", "height_px = 128"},
                                                       {"stimulus_frames", "stimulus_frames = 2"}})
                               .string();
  const auto stopped = run_glarelab(
      {"run", demo, "--display", "offscreen", "--observer", "simulated", "--db", db.string(), "--stop-after", "1"},
      scratch.path());
  ASSERT_EQ(stopped.exit_code, 0) << stopped.output;
  const std::string marker = "finish with: glarelab ";
  const auto at = stopped.output.find(marker);
  ASSERT_NE(at, std::string::npos) << stopped.output;
  const std::string arguments = stopped.output.substr(at + marker.size(), stopped.output.find('\n', at) - at - marker.size());
  // Pasted into a shell, with glarelab the built binary: the session finishes, nothing else runs.
  const std::string script = "cd '" + scratch.path().string() + "' && '" + GLARELAB_BINARY + "' " + arguments;
  const auto resumed = run_glarelab_shell(script, scratch.path());
  EXPECT_EQ(resumed.exit_code, 0) << script << "\n" << resumed.output;
  EXPECT_NE(resumed.output.find("completed"), std::string::npos) << resumed.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "pwned"));
}

TEST(HostileInput, ATrackerAddressThatIsNoHostIsBadInputBeforeAnythingIsWritten) {
  const ScratchDir scratch;
  const std::string demo = std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml";
  for (const std::string host : {"a b", "*"}) {
    const auto db = scratch.path() / "tracked.db";
    const auto result = run_glarelab({"run", demo, "--display", "offscreen", "--observer", "simulated", "--db",
                                      db.string(), "--tracker", "pupil-labs://" + host + ":50020"},
                                     scratch.path());
    EXPECT_EQ(result.exit_code, 2) << result.output;  // was 1, "internal error" from ZeroMQ
    EXPECT_NE(result.output.find("'" + host + "' is not a host"), std::string::npos) << result.output;
    EXPECT_FALSE(std::filesystem::exists(db));
  }
}

TEST(HostileInput, AScenePastTheSunByOrdersOfMagnitudeIsRefusedNotGlaredToNaN) {
  const ScratchDir scratch;
  // 3e38 cd/m2 (float's top) in one pixel of an otherwise dark scene: glare summed it to inf and NaN.
  ImageRGBA hot(64, 64);
  for (float& value : hot.rgba) value = 0.5f;
  for (int c = 0; c < 3; ++c) hot.rgba[static_cast<std::size_t>(4 * (32 * 64 + 32) + c)] = 3e38f;
  const std::string file = scratch.file("hot.exr");
  write_exr(file, hot);
  const auto experiment = demo_variant(scratch.path(), {{"lamp_100", "lamp_100 = { file = \"" + file + "\" }"}});
  const auto db = scratch.path() / "hot.db";
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"validate", experiment.string()},
        {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db", db.string()}}) {
    const auto result = run_glarelab(command, scratch.path());
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_NE(result.output.find(file + ": scene 'lamp_100' peaks at 3"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("e+38 cd/m2 (pixel values times scale_cd_m2); glarelab takes scenes up to 1e12 cd/m2"),
              std::string::npos)
        << result.output;
  }
  EXPECT_FALSE(std::filesystem::exists(db));
}

}  // namespace
}  // namespace glarelab
