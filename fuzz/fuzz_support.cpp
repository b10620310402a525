#include "fuzz/fuzz_support.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>

namespace glarelab::fuzz {

ScratchFolder& ScratchFolder::instance() {
  static ScratchFolder folder;
  return folder;
}

ScratchFolder::ScratchFolder()
    : path_(std::filesystem::temp_directory_path() / ("glarelab-fuzz-" + std::to_string(::getpid()))) {
  std::filesystem::create_directories(path_);
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::string ScratchFolder::write(const std::string& name, std::string_view bytes) const {
  const std::filesystem::path file = path_ / name;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  // A harness that cannot write its input would test nothing: stop loudly instead.
  if (!out) throw std::runtime_error("fuzz harness: cannot write " + file.string());
  return file.string();
}

void ScratchFolder::remove(const std::string& name) const {
  std::error_code ignored;
  std::filesystem::remove(path_ / name, ignored);
}

}  // namespace glarelab::fuzz
