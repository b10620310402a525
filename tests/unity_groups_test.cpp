// The build's unity groups (cmake/UnityGroups.cmake, cmake/unity_groups.py): two files whose
// file-local functions share a name with different parameters would overload each other without a
// compiler error in one unity source, so the grouping must keep them apart and the check before
// each build must fail when an edit brings them together; the test program's groups also keep apart
// a file that names another's file-local name. And this build's own groups pass the check.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "scratch_dir.h"

namespace glarelab {
namespace {

struct Result {
  int exit_code = -1;
  std::string output;
};

// Debian's universal-ctags installs ctags-universal (and ctags as an alternative).
std::string ctags() { return std::system("command -v ctags-universal >/dev/null 2>&1") == 0 ? "ctags-universal" : "ctags"; }

Result run_script(const std::string& arguments) {
  const std::string command = "/usr/bin/python3 " + std::string(GLARELAB_SOURCE_DIR) + "/cmake/unity_groups.py --ctags " +
                              ctags() + " " + arguments + " 2>&1";
  Result result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) result.output += buffer;
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

bool ctags_present() { return std::system((ctags() + " --version 2>/dev/null | grep -q 'Universal Ctags'").c_str()) == 0; }

void write(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

TEST(UnityGroups, FilesSharingAFileLocalNameNeverShareAGroupAndTheCheckNamesThem) {
  if (!ctags_present()) GTEST_SKIP() << "Universal Ctags is missing (install universal-ctags; scripts/setup.sh does)";
  const test::ScratchDir dir;
  const std::string a = (dir.path() / "a.cpp").string();
  const std::string b = (dir.path() / "b.cpp").string();
  const std::string c = (dir.path() / "c.cpp").string();
  const std::string d = (dir.path() / "d.cpp").string();
  const std::string e = (dir.path() / "e.cpp").string();
  write(a, "namespace glarelab {\nnamespace {\ndouble scale(double x) { return 2.0 * x; }\n}  // namespace\n"
           "double twice(double x) { return scale(x); }\n}\n");
  write(b, "namespace glarelab {\nnamespace {\nfloat scale(float x) { return 3.0f * x; }\n}  // namespace\n"
           "float thrice(float x) { return scale(x); }\n}\n");
  write(c, "namespace glarelab {\nstatic int counter_of(int x) { return x; }\nint one() { return counter_of(1); }\n}\n");
  write(d, "#define GLFW_INCLUDE_NONE\nnamespace glarelab { int two() { return 2; } }\n");
  write(e, "namespace glarelab {\nstatic int counter_of(long x) { return int(x); }\nint three() { return counter_of(3L); }\n}\n");

  const Result groups = run_script("--prefix lib --max-files 8 " + a + " " + b + " " + c + " " + d + " " + e);
  ASSERT_EQ(groups.exit_code, 0) << groups.output;
  // First fit in order: a opens lib_0, b (scale) opens lib_1, c joins lib_0, d (a macro) stays alone,
  // e (counter_of, static) cannot join lib_0 and joins lib_1.
  EXPECT_EQ(groups.output, "lib_0|" + a + "|" + c + "\nlib_1|" + b + "|" + e + "\n");

  const std::string groups_file = (dir.path() / "groups.txt").string();
  const std::string stamp = (dir.path() / "checked").string();
  write(groups_file, "lib_0|" + a + "|" + c + "\nlib_1|" + b + "|" + e + "\n");
  const Result clean = run_script("--check " + groups_file + " --stamp " + stamp);
  EXPECT_EQ(clean.exit_code, 0) << clean.output;
  EXPECT_TRUE(std::filesystem::exists(stamp));

  // An edit that puts both scale()s (and the macro file) into one group since configuring.
  std::filesystem::remove(stamp);
  write(groups_file, "lib_0|" + a + "|" + b + "|" + d + "\n");
  const Result stale = run_script("--check " + groups_file + " --stamp " + stamp);
  EXPECT_EQ(stale.exit_code, 1) << stale.output;
  EXPECT_NE(stale.output.find(b + " and " + a + " both define the file-local name 'scale'"), std::string::npos)
      << stale.output;
  EXPECT_NE(stale.output.find(d + " defines the macro(s) GLFW_INCLUDE_NONE"), std::string::npos) << stale.output;
  EXPECT_NE(stale.output.find("configure again"), std::string::npos) << stale.output;
  EXPECT_FALSE(std::filesystem::exists(stamp));
}

// A test file's tests and a benchmark file's registrations are no file-local names: the macros
// define classes and variables named after each test and function (unique in the program), so two
// files with tests share a group unless their helpers share a name.
TEST(UnityGroups, TestsAndBenchmarksShareAGroupUnlessTheirHelpersShareAName) {
  if (!ctags_present()) GTEST_SKIP() << "Universal Ctags is missing (install universal-ctags; scripts/setup.sh does)";
  const test::ScratchDir dir;
  const std::string a = (dir.path() / "a_test.cpp").string();
  const std::string b = (dir.path() / "b_test.cpp").string();
  const std::string c = (dir.path() / "c_test.cpp").string();
  const std::string d = (dir.path() / "d_bench.cpp").string();
  const std::string e = (dir.path() / "e_bench.cpp").string();
  write(a, "namespace glarelab {\nnamespace {\nint frame_of(int x) { return x; }\n"
           "TEST(Alpha, One) { EXPECT_EQ(frame_of(1), 1); }\nTEST_F(AlphaFixture, Two) {}\n}  // namespace\n}\n");
  write(b, "namespace glarelab {\nnamespace {\nTEST(Beta, One) {}\nTEST_P(BetaParam, Two) {}\n}  // namespace\n}\n");
  write(c, "namespace glarelab {\nnamespace {\nlong frame_of(long x) { return x; }\nTEST(Gamma, One) {}\n}  // namespace\n}\n");
  write(d, "namespace {\nvoid BM_Frame(benchmark::State& state) {}\n"
           "BENCHMARK(BM_Frame)->Arg(256)->Arg(512);\n}  // namespace\n");
  write(e, "namespace {\nvoid fft(benchmark::State& state, int n) {}\n"
           "BENCHMARK_CAPTURE(fft, small, 256)->Unit(benchmark::kMillisecond);\n}  // namespace\n");

  const Result groups = run_script("--prefix t --max-files 8 " + a + " " + b + " " + c + " " + d + " " + e);
  ASSERT_EQ(groups.exit_code, 0) << groups.output;
  // c's frame_of keeps it from a's group; the benchmark files join the first.
  EXPECT_EQ(groups.output, "t_0|" + a + "|" + b + "|" + d + "|" + e + "\n") << "c alone, in no printed group";
}

// In one unity source a file-local name also meets every later file that names it: a later local
// constexpr kWidth shadows it (-Wshadow), a later unqualified call analyse(data, options) finds it
// first. The test program's groups (--apart-when-named) keep such files apart; a name in a comment,
// a string, a member access or after a scope is no use of it.
TEST(UnityGroups, TheTestProgramsRuleKeepsApartAFileThatNamesAnothersFileLocalName) {
  if (!ctags_present()) GTEST_SKIP() << "Universal Ctags is missing (install universal-ctags; scripts/setup.sh does)";
  const test::ScratchDir dir;
  const std::string a = (dir.path() / "a_test.cpp").string();
  const std::string b = (dir.path() / "b_test.cpp").string();
  const std::string c = (dir.path() / "c_test.cpp").string();
  const std::string d = (dir.path() / "d_test.cpp").string();
  write(a, "namespace glarelab {\nnamespace {\nconstexpr int kWidth = 4;\n"
           "double analyse(const double& data) { return data * kWidth; }\n}  // namespace\n"
           "double width_of(double x) { return analyse(x); }\n}\n");
  write(b, "namespace glarelab {\nint area(int height) {\n  constexpr int kWidth = 8;\n  return kWidth * height;\n}\n}\n");
  write(c, "namespace glarelab {\n// kWidth and analyse() in a comment\n"
           "const char* label() { return \"kWidth analyse\"; }\n"
           "const char* raw() { return R\"x(kWidth \"analyse\")x\"; }\n"
           "int big() { return 1'000; }\n"
           "int width(const Layout& f, const Layout* p) { return f.kWidth + p->kWidth + Layout::kWidth; }\n}\n");
  write(d, "namespace glarelab {\ndouble fit(Data data, Options options) { return analyse(std::move(data), options); }\n}\n");
  const std::string files = " --prefix t --max-files 8 " + a + " " + b + " " + c + " " + d;

  // The libraries' rule alone: no two files define one name, so all four share a group.
  const Result first_rule = run_script(files);
  ASSERT_EQ(first_rule.exit_code, 0) << first_rule.output;
  EXPECT_EQ(first_rule.output, "t_0|" + a + "|" + b + "|" + c + "|" + d + "\n");

  // b names kWidth and d names analyse, a's file-local names; c only mentions them.
  const Result named = run_script("--apart-when-named" + files);
  ASSERT_EQ(named.exit_code, 0) << named.output;
  EXPECT_EQ(named.output, "t_0|" + a + "|" + c + "\nt_1|" + b + "|" + d + "\n");

  // The check before each build applies the same rule to groups formed without it.
  const std::string groups_file = (dir.path() / "groups.txt").string();
  const std::string stamp = (dir.path() / "checked").string();
  write(groups_file, first_rule.output);
  EXPECT_EQ(run_script("--check " + groups_file + " --stamp " + stamp).exit_code, 0);
  std::filesystem::remove(stamp);
  const Result stale = run_script("--apart-when-named --check " + groups_file + " --stamp " + stamp);
  EXPECT_EQ(stale.exit_code, 1) << stale.output;
  EXPECT_NE(stale.output.find(b + " names " + a + "'s file-local name(s) kWidth"), std::string::npos) << stale.output;
  EXPECT_NE(stale.output.find(d + " names " + a + "'s file-local name(s) analyse"), std::string::npos) << stale.output;
  EXPECT_EQ(stale.output.find(c + " names"), std::string::npos) << stale.output;
  EXPECT_FALSE(std::filesystem::exists(stamp));
  write(groups_file, named.output);
  EXPECT_EQ(run_script("--apart-when-named --check " + groups_file + " --stamp " + stamp).exit_code, 0);
}

TEST(UnityGroups, ThisBuildsGroupsHoldNoSharedFileLocalName) {
  if (!ctags_present()) GTEST_SKIP() << "Universal Ctags is missing (install universal-ctags; scripts/setup.sh does)";
  const std::filesystem::path folder = std::filesystem::path(GLARELAB_BINARY).parent_path() / "unity_groups";
  if (!std::filesystem::exists(folder)) GTEST_SKIP() << "this build has no unity groups (GLARELAB_UNITY_GROUPS=OFF)";
  const test::ScratchDir dir;
  std::set<std::string> targets;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".txt") continue;
    const std::string target = entry.path().stem().string();
    targets.insert(target);
    // The test program's groups with its own rule (tests/CMakeLists.txt).
    const std::string rule = target == "glarelab_tests" ? "--apart-when-named " : "";
    const Result check =
        run_script(rule + "--check " + entry.path().string() + " --stamp " + (dir.path() / "stamp").string());
    EXPECT_EQ(check.exit_code, 0) << entry.path() << "\n" << check.output;
  }
  // One groups file per library and the test program (and the benchmarks' where Google Benchmark is
  // installed).
  targets.erase("glarelab_benchmarks");
  EXPECT_EQ(targets, (std::set<std::string>{"glarelab_core", "glarelab_glare", "glarelab_stimuli", "glarelab_protocols",
                                            "glarelab_analysis", "glarelab_runner", "glarelab_tests"}));
}

}  // namespace
}  // namespace glarelab
