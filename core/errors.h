#pragma once
// The program's error types and what each means to the caller of `glarelab`: the exit code it
// ends with (runner/cli/report_errors.cpp maps each type to its code, README "Exit codes").
// Every layer throws these; none of them knows about experiments, displays or databases beyond
// the words of its message.
#include <stdexcept>
#include <string>

namespace glarelab {

// Exit codes of every `glarelab` subcommand.
enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,     // unexpected internal error
  kExitBadInput = 2,    // experiment file, condition table, scene image, script, options (ConfigError, ImageError)
  kExitDevice = 3,      // display, GL or input device (DisplayError and the device errors of runner/)
  kExitStore = 4,       // database (StoreError)
  kExitAborted = 130,   // Ctrl-C, Escape or window closed: session kept as aborted
};

// Where in an input file something was found.
struct SourceLocation {
  std::string file;
  int line = 0;    // 1-based; 0 when unknown
  int column = 0;  // 1-based; 0 when unknown
  std::string to_string() const;  // "file:line:column" (omits zeros)
};

// Errors in experiment files and condition tables. what() reads "FILE:LINE:COLUMN: key 'KEY': MESSAGE"
// (the key part only when a key is involved), the form compilers use, so editors can jump to it.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(SourceLocation where, std::string key, const std::string& message);
  const SourceLocation& where() const { return where_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }

 private:
  SourceLocation where_;
  std::string key_;
  std::string message_;
};

// "SUBSYSTEM: message" errors of the display and of OpenGL (GLFW, OSMesa, OpenGL): a clear report
// instead of a crash. Thrown by the display backends and by every layer that drives GL.
class DisplayError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A results database could not be opened, read or written ("SQLite: FILE: message").
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace glarelab
