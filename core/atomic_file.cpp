#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/errors.h"

namespace glarelab {
namespace {

std::string system_error_text(int number) { return std::strerror(number); }

// ".tmp-PID-N-NAME" beside `path`: hidden, unique in this process, never the name of an output,
// and ending as NAME does (writers that go by the extension write the same format).
std::string temporary_beside(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path target(path);
  return (target.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
                                  target.filename().string()))
      .string();
}

}  // namespace

AtomicFile::AtomicFile(std::string path, std::optional<unsigned> mode) : path_(std::move(path)), mode_(mode) {}

AtomicFile::~AtomicFile() = default;

void AtomicFile::commit() {
  const std::string temporary = temporary_beside(path_);
  // O_EXCL | O_NOFOLLOW: the temporary name is created here, not opened through something planted.
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC,
                        static_cast<mode_t>(mode_.value_or(0666)));
  if (fd < 0) throw StoreError(path_ + ": cannot write: " + system_error_text(errno));
  const auto fail = [&](const std::string& what) {
    const int number = errno;
    ::close(fd);
    ::unlink(temporary.c_str());
    throw StoreError(path_ + ": " + what + ": " + system_error_text(number));
  };
  // An explicit mode is the file's whatever the umask (open() applies the umask to its mode).
  if (mode_ && ::fchmod(fd, static_cast<mode_t>(*mode_)) != 0) fail("cannot set its mode");
  const std::string content = content_.str();
  for (std::size_t done = 0; done < content.size();) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("cannot write");
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) fail("cannot flush to disk");
  if (::close(fd) != 0) {
    const int number = errno;
    ::unlink(temporary.c_str());
    throw StoreError(path_ + ": cannot write: " + system_error_text(number));
  }
  if (::rename(temporary.c_str(), path_.c_str()) != 0) {
    const int number = errno;
    ::unlink(temporary.c_str());
    throw StoreError(path_ + ": cannot put in place: " + system_error_text(number));
  }
}

void write_file_atomically(const std::string& path, const std::string& content, std::optional<unsigned> mode) {
  AtomicFile file(path, mode);
  file.stream() << content;
  file.commit();
}

void write_through_temporary(const std::string& path, const std::function<void(const std::string&)>& writer) {
  const std::string temporary = temporary_beside(path);
  try {
    writer(temporary);
  } catch (...) {
    ::unlink(temporary.c_str());
    throw;
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int number = errno;
    ::unlink(temporary.c_str());
    throw StoreError(path + ": cannot put in place: " + system_error_text(number));
  }
}

std::optional<std::string> file_in_the_way_of_folder(const std::string& directory) {
  std::error_code ignored;
  for (std::filesystem::path at(directory); !at.empty(); at = at.parent_path()) {
    if (std::filesystem::exists(at, ignored)) {
      if (std::filesystem::is_directory(at, ignored)) return std::nullopt;
      return at.string();
    }
    if (at == at.parent_path()) break;
  }
  return std::nullopt;
}

void refuse_symbolic_link(const std::string& path, const std::string& option) {
  std::error_code error;
  const auto status = std::filesystem::symlink_status(path, error);
  if (error || status.type() != std::filesystem::file_type::symlink) return;
  const std::string target = std::filesystem::read_symlink(path, error).string();
  throw OutputPathError(option + ": " + path + " is a symbolic link (to " + (error ? "?" : target) +
                        "): glarelab does not write through links; name the file itself");
}

}  // namespace glarelab
