#pragma once
// Which process on which machine: enough to tell, later and from another process, whether that
// process still runs (runner/store/session_lease.h). A pid alone is not: the kernel reuses pids,
// so the process's start time (in clock ticks since boot) and the boot's id go with it.
#include <cstdint>
#include <string>

namespace glarelab {

struct ProcessIdentity {
  std::int64_t pid = 0;
  std::int64_t start_ticks = 0;  // /proc/PID/stat field 22: clock ticks after boot
  std::string boot_id;           // /proc/sys/kernel/random/boot_id
  std::string host;              // gethostname
};

// This process. Throws StoreError when /proc cannot be read (it always can on Linux).
ProcessIdentity this_process();

// Whether `process` still runs here: the same machine and boot, its pid alive, not a zombie, and
// started at the same tick (a reused pid is another process). A process of another machine or an
// earlier boot cannot be running against this database file: SQLite's WAL journal works only
// between processes of one machine.
bool still_running(const ProcessIdentity& process);

// "process 1234 on host lab-pc" for messages.
std::string describe(const ProcessIdentity& process);

}  // namespace glarelab
