#pragma once
// A fresh directory under the system temp directory for one test, removed afterwards.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace glarelab::testing {

class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "glarelab-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
                       std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
    if (info != nullptr) name += std::string("-") + info->name();
    path_ = (std::filesystem::temp_directory_path() / name).lexically_normal();
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // Writes `content` to `name` (relative to the directory) and returns the absolute path.
  std::string write(const std::string& name, const std::string& content) const {
    const std::filesystem::path file = path_ / name;
    std::ofstream(file, std::ios::binary) << content;
    return file.string();
  }

 private:
  std::filesystem::path path_;
};

}  // namespace glarelab::testing
