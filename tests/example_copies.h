#pragma once
// The shipped examples copied into a test's scratch folder with every stimulus a few frames long:
// the tests that run whole example sessions to compare their frames (GPU engine against CPU engine,
// render against session, read-backs) check what each frame is, which a stimulus of two frames
// shows as well as one of fifteen or thirty, for a fraction of the dynamic glare frames; a test that
// reads only a session's answers (the rating analysis) needs one frame.
#include <filesystem>
#include <sstream>
#include <string>

#include "scratch_dir.h"

namespace glarelab::test {

// The examples folder copied into `dir` (as `dir`/examples, scenes and condition tables beside
// them) with each file's stimulus_frames or stimulus_duration_s line replaced by
// `stimulus_frames = frames`; returns the copy's folder.
inline std::filesystem::path examples_with_frames(const std::filesystem::path& dir, int frames) {
  namespace fs = std::filesystem;
  const fs::path examples = fs::path(GLARELAB_SOURCE_DIR) / "examples";
  fs::copy(examples, dir / "examples", fs::copy_options::recursive);
  for (const fs::directory_entry& entry : fs::directory_iterator(dir / "examples")) {
    if (entry.path().extension() != ".toml") continue;
    std::istringstream in(read_bytes(entry.path().string()));
    std::ostringstream out;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("stimulus_frames", 0) == 0 || line.rfind("stimulus_duration_s", 0) == 0)
        line = "stimulus_frames = " + std::to_string(frames);
      out << line << "\n";
    }
    write_bytes(entry.path().string(), out.str());
  }
  return dir / "examples";
}

}  // namespace glarelab::test
