// The test helper that starts glarelab (tests/cli_process.h): a process that could not be started
// is a failure of the test that started it, and waiting for it neither blocks nor reaps another
// child (waitpid(-1) would take the exit status of whichever child ended first).
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <string>

#include "cli_process.h"

namespace glarelab {
namespace {

TEST(CliProcess, AProcessThatCannotStartFailsItsTestAndLeavesOtherChildrenAlone) {
  const test::ScratchDir scratch;
  // A child that is running, and will exit 2 (a file that is not there), while the failed start is
  // waited for: a wait that reaped it in the other's place would return its 2 there, and leave
  // this one nothing to wait for.
  const std::string absent = (scratch.path() / "absent.toml").string();
  test::GlarelabProcess running({"validate", absent}, scratch.path() / "validate.txt");
  ASSERT_TRUE(running.started());
  const std::string missing = (scratch.path() / "no-such-glarelab").string();
  EXPECT_NONFATAL_FAILURE(
      {
        test::GlarelabProcess never(std::vector<std::string>{"--version"}, scratch.path() / "never.txt", missing);
        EXPECT_FALSE(never.started());
        EXPECT_EQ(never.wait(), -1);
        never.signal(SIGKILL);  // nothing to signal: must not reach pid -1 (every process)
      },
      "could not start " + missing + ": No such file or directory");
  EXPECT_EQ(running.wait(), 2) << "the running child was reaped by the wait for the one that never started";
  EXPECT_NE(test::read_bytes((scratch.path() / "validate.txt").string()).find(absent), std::string::npos);
}

TEST(CliProcess, AFailedStartNamesTheBinaryAndTheReason) {
  const test::ScratchDir scratch;
  EXPECT_NONFATAL_FAILURE(
      {
        test::GlarelabProcess never(std::vector<std::string>{}, scratch.path() / "never.txt", "/nonexistent/glarelab");
        EXPECT_EQ(never.start_error(), "could not start /nonexistent/glarelab: No such file or directory");
      },
      "could not start /nonexistent/glarelab");
}

}  // namespace
}  // namespace glarelab
