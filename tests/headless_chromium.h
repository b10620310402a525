#pragma once
// Debian's chromium (scripts/setup.sh installs it), run headless for the report tests: the path of
// the binary, and the command line every such test uses (its own profile in the test's scratch
// directory, no network, no GPU), to which each adds its output (--screenshot, --dump-dom) and
// redirections.
#include <filesystem>
#include <string>

namespace glarelab::test {

// Empty when chromium is not installed.
inline std::string chromium_binary() {
  for (const char* candidate : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(candidate)) return candidate;
  return "";
}

// `timeout SECONDS chromium --headless ... --user-data-dir=PROFILE FLAGS file://PAGE`. Give it a
// minute: alone it takes a second or two, but on a loaded 2-core machine a start has taken more
// than 20 s.
inline std::string headless_chromium_command(const std::string& chromium, int timeout_s,
                                             const std::filesystem::path& profile, const std::string& flags,
                                             const std::filesystem::path& page) {
  return "timeout " + std::to_string(timeout_s) + " " + chromium +
         " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
         " --disable-background-networking --disable-component-update --disable-sync"
         " --user-data-dir=" + profile.string() + " " + flags + " file://" + page.string();
}

}  // namespace glarelab::test
