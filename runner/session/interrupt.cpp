#include "runner/session/interrupt.h"

#include <atomic>
#include <csignal>

namespace glarelab {
namespace {
std::atomic<bool> interrupted{false};
extern "C" void on_interrupt(int) { interrupted.store(true); }
}  // namespace

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool interrupt_requested() { return interrupted.load(); }
void clear_interrupt() { interrupted.store(false); }

}  // namespace glarelab
