#pragma once
// Focusing a glarelab window with xdotool in the window tests (under xvfb-run).
//
// `xdotool search --sync --name T windowfocus` finds the window as soon as it exists with its
// title, which can be before the window manager-less Xvfb has mapped it; focusing an unmapped
// window fails with BadMatch (X_SetInputFocus), which under load made the suite fail now and then.
// --onlyvisible waits for a mapped (viewable) window, and the loop retries the focus until it holds
// or the time runs out.
#include <string>

namespace glarelab::test {

// A shell command that exits 0 once the window titled `title` (an xdotool name pattern, no single
// quotes) is visible and focused, or non-zero after `timeout_s` seconds.
inline std::string focus_window_command(const std::string& title, int timeout_s) {
  return "timeout " + std::to_string(timeout_s) + " sh -c 'until xdotool search --sync --onlyvisible --name \"" + title +
         "\" windowfocus --sync > /dev/null 2>&1; do sleep 0.2; done'";
}

}  // namespace glarelab::test
