#include "runner/store/process_identity.h"

#include <unistd.h>

#include <array>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

#include "core/errors.h"

namespace glarelab {
namespace {

struct ProcStat {
  char state = '?';
  std::int64_t start_ticks = 0;
};

// /proc/PID/stat: "pid (comm) state ppid ... starttime ...". The command name may hold spaces and
// parentheses, so the fields are counted from the last ')'; state is field 3, starttime field 22.
std::optional<ProcStat> read_proc_stat(std::int64_t pid) {
  std::ifstream file("/proc/" + std::to_string(pid) + "/stat");
  if (!file) return std::nullopt;
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::size_t close = text.rfind(')');
  if (close == std::string::npos) return std::nullopt;
  std::istringstream fields(text.substr(close + 1));
  ProcStat stat;
  fields >> stat.state;
  std::string skipped;
  for (int field = 4; field < 22 && fields >> skipped; ++field) {
  }
  if (!(fields >> stat.start_ticks)) return std::nullopt;
  return stat;
}

std::string read_boot_id() {
  std::ifstream file("/proc/sys/kernel/random/boot_id");
  std::string id;
  std::getline(file, id);
  return id;
}

std::string host_name() {
  std::array<char, 256> name{};
  if (::gethostname(name.data(), name.size() - 1) != 0) return "unknown";
  return name.data();
}

}  // namespace

ProcessIdentity this_process() {
  ProcessIdentity process;
  process.pid = static_cast<std::int64_t>(::getpid());
  const std::optional<ProcStat> stat = read_proc_stat(process.pid);
  process.boot_id = read_boot_id();
  if (!stat || process.boot_id.empty())
    throw StoreError("session lease: cannot read this process's start time and boot id from /proc");
  process.start_ticks = stat->start_ticks;
  process.host = host_name();
  return process;
}

bool still_running(const ProcessIdentity& process) {
  if (process.boot_id != read_boot_id() || process.host != host_name()) return false;
  const std::optional<ProcStat> stat = read_proc_stat(process.pid);
  return stat && stat->state != 'Z' && stat->state != 'X' && stat->start_ticks == process.start_ticks;
}

std::string describe(const ProcessIdentity& process) {
  return "process " + std::to_string(process.pid) + " on host " + process.host;
}

}  // namespace glarelab
