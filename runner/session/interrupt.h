#pragma once
// Ctrl-C (SIGINT) and SIGTERM end a session cleanly: the handler only raises a flag, which the
// frame loop checks once per frame; the session is then marked aborted with its data kept.
namespace glarelab {
void install_interrupt_handlers();
bool interrupt_requested();
void clear_interrupt();
}  // namespace glarelab
