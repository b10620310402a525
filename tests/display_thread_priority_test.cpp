// The display's thread at real-time priority for a session on a real clock
// (runner/session/display_thread_priority.h): raised before the display opens, so the threads the
// GL driver starts with the context share it; threads started after the display opened (the trial
// worker, the commit's connection) begin at normal priority; normal again at the end. Where the
// system refuses, nothing changes and the description says why and what grants it. Asserted from
// each thread's policy as the kernel reports it (sched_getscheduler), never from timing.
#include <gtest/gtest.h>

#include <linux/capability.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <string>
#include <thread>

#include "runner/session/display_thread_priority.h"

namespace glarelab {
namespace {

// The scheduling policy of a thread started now from the calling thread, as it begins.
int policy_of_a_new_thread() {
  int policy = -1;
  std::thread([&] { policy = sched_getscheduler(0); }).join();
  return policy;
}

// Whether this process may take SCHED_RR at all (checked on a thread of its own, dropped at once).
bool real_time_permitted() {
  bool permitted = false;
  std::thread([&] {
    sched_param parameters{};
    parameters.sched_priority = 1;
    permitted = sched_setscheduler(0, SCHED_RR, &parameters) == 0;
  }).join();
  return permitted;
}

TEST(DisplayThreadPriority, TheDisplaysThreadAndThreadsItStartsBeforeTheDisplayOpensRunAtRealTimeLaterOnesDoNot) {
  if (!real_time_permitted()) GTEST_SKIP() << "this process may not take real-time scheduling (no CAP_SYS_NICE, RLIMIT_RTPRIO 0)";
  std::thread([] {
    ASSERT_EQ(sched_getscheduler(0), SCHED_OTHER);
    {
      DisplayThreadPriority priority = DisplayThreadPriority::raise_before_display();
      ASSERT_TRUE(priority.asked());
      ASSERT_TRUE(priority.real_time()) << priority.description();
      EXPECT_EQ(sched_getscheduler(0), SCHED_RR);
      sched_param parameters{};
      ASSERT_EQ(sched_getparam(0, &parameters), 0);
      EXPECT_EQ(parameters.sched_priority, 1);
      // A thread the GL driver starts with the context (llvmpipe's rasterisers) inherits it.
      EXPECT_EQ(policy_of_a_new_thread(), SCHED_RR);
      priority.display_opened();
      EXPECT_EQ(sched_getscheduler(0), SCHED_RR | SCHED_RESET_ON_FORK);
      // The trial worker, started after the display opened, begins at normal priority.
      EXPECT_EQ(policy_of_a_new_thread(), SCHED_OTHER);
      EXPECT_NE(priority.description().find("SCHED_RR, priority 1"), std::string::npos) << priority.description();
      // Taken over by another owner (the session's own variable): still one raise, dropped once.
      DisplayThreadPriority owner;
      owner = std::move(priority);
      EXPECT_TRUE(owner.real_time());
      EXPECT_EQ(sched_getscheduler(0), SCHED_RR | SCHED_RESET_ON_FORK);
    }
    EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
    EXPECT_EQ(policy_of_a_new_thread(), SCHED_OTHER);
  }).join();
}

// Without CAP_SYS_NICE and with RLIMIT_RTPRIO at 0 the raise is refused: the thread keeps its
// policy and the session's log says why and what would grant it. The capability is dropped from
// the effective set of one thread only (Linux keeps capabilities per thread); the limit, which is
// the process's, is put back.
TEST(DisplayThreadPriority, ARefusedRaiseChangesNothingAndSaysWhatWouldGrantIt) {
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_RTPRIO, &saved), 0);
  rlimit none = saved;
  none.rlim_cur = 0;
  ASSERT_EQ(setrlimit(RLIMIT_RTPRIO, &none), 0);
  std::thread([] {
    __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
    __user_cap_data_struct data[2]{};
    ASSERT_EQ(syscall(SYS_capget, &header, data), 0);
    data[CAP_SYS_NICE / 32].effective &= ~(1u << (CAP_SYS_NICE % 32));
    ASSERT_EQ(syscall(SYS_capset, &header, data), 0);
    {
      const DisplayThreadPriority priority = DisplayThreadPriority::raise_before_display();
      EXPECT_TRUE(priority.asked());
      EXPECT_FALSE(priority.real_time());
      EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
      EXPECT_EQ(priority.description().rfind("normal: real-time scheduling was refused (sched_setscheduler: ", 0), 0u)
          << priority.description();
      EXPECT_NE(priority.description().find("CAP_SYS_NICE or an RLIMIT_RTPRIO of 1 or more"), std::string::npos);
    }
    EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
  }).join();
  ASSERT_EQ(setrlimit(RLIMIT_RTPRIO, &saved), 0);
}

}  // namespace
}  // namespace glarelab
