#pragma once
// Standard error taken into a string while a library speaks (runner/display/openxr_session.cpp).
#include <unistd.h>

#include <cstdio>
#include <string>

namespace glarelab {

// What the loader writes to stderr while it looks for a runtime (it has no other way to say why
// none was found), taken so that the error can quote it; on success it is written back.
class StderrCapture {
 public:
  StderrCapture() {
    std::fflush(stderr);
    file_ = std::tmpfile();
    if (file_ != nullptr) {
      saved_ = dup(STDERR_FILENO);
      if (saved_ >= 0) dup2(fileno(file_), STDERR_FILENO);
    }
  }
  ~StderrCapture() { restore(); }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  // Stops capturing; what was written, as it was.
  std::string finish() {
    restore();
    std::string text;
    if (file_ == nullptr) return text;
    std::rewind(file_);
    char chunk[4096];
    for (std::size_t n; (n = std::fread(chunk, 1, sizeof chunk, file_)) > 0;) text.append(chunk, n);
    std::fclose(file_);
    file_ = nullptr;
    return text;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    dup2(saved_, STDERR_FILENO);
    close(saved_);
    saved_ = -1;
  }
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

}  // namespace glarelab
