#pragma once
// Cross-checks with SciPy: Debian's /usr/bin/python3 with python3-scipy (scripts/setup.sh installs
// it), called by that path because a `python3` earlier on PATH may lack SciPy.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace glarelab::test {

// True when /usr/bin/python3 can import scipy.stats; else false with the reason in `why`.
inline bool scipy_available(std::string& why) {
  if (!std::filesystem::exists("/usr/bin/python3")) {
    why = "/usr/bin/python3 is missing (install python3-scipy; scripts/setup.sh does)";
    return false;
  }
  if (std::system("/usr/bin/python3 -c 'import scipy.stats' >/dev/null 2>&1") != 0) {
    why = "SciPy is missing for /usr/bin/python3 (install python3-scipy; scripts/setup.sh does)";
    return false;
  }
  return true;
}

// What `/usr/bin/python3 SCRIPT CSV` prints (stdout and stderr).
inline std::string run_python(const std::string& script, const std::string& csv) {
  std::string output;
  FILE* pipe = ::popen(("/usr/bin/python3 " + script + " " + csv + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  ::pclose(pipe);
  return output;
}

}  // namespace glarelab::test
