#pragma once
// Shared by the fuzz targets: most entry points of glarelab read files, not buffers, so a target
// writes its input into a scratch folder of its own process (several targets may run at once,
// under ctest -j or side by side under libFuzzer) and hands the path to the real reader.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace glarelab::fuzz {

// The bytes as text (files may hold anything, including NUL).
inline std::string as_text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// <temp>/glarelab-fuzz-<pid>: made on first use, removed when the process ends normally.
class ScratchFolder {
 public:
  static ScratchFolder& instance();
  const std::filesystem::path& path() const { return path_; }
  // Writes `bytes` to <folder>/<name> (replacing it) and returns the path.
  std::string write(const std::string& name, std::string_view bytes) const;
  // Removes <folder>/<name> if present.
  void remove(const std::string& name) const;
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

 private:
  ScratchFolder();
  std::filesystem::path path_;
};

}  // namespace glarelab::fuzz
