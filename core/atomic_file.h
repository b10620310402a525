#pragma once
// Output files that are never seen half written: the content goes to a file beside the
// destination (same folder, so the same file system) and is renamed over it only when complete
// and closed. A process killed mid-write leaves the previous file whole (and a stray ".tmp-*-NAME"
// beside it at worst), never a truncated one. rename(2) replaces the destination's directory entry:
// a symbolic link standing there is replaced, its target is not written.
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

namespace glarelab {

// Thrown when an output path is a symbolic link the caller did not name as such: a link planted
// where glarelab writes (or left dangling) must not redirect the write elsewhere.
class OutputPathError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class AtomicFile {
 public:
  // `mode`: the permission bits of the file (umask not applied), e.g. a database's 0600 for its
  // exports; nullopt: 0666 less the umask, as a plain open would give.
  explicit AtomicFile(std::string path, std::optional<unsigned> mode = std::nullopt);
  ~AtomicFile();  // without commit(): nothing at `path` changes
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return content_; }
  // Writes the content beside the destination, flushes it to disk and renames it into place.
  // Throws StoreError (core/errors.h) naming the path when the file system refuses.
  void commit();

 private:
  std::string path_;
  std::optional<unsigned> mode_;
  std::ostringstream content_;
};

// The whole of `content` to `path` through an AtomicFile.
void write_file_atomically(const std::string& path, const std::string& content,
                           std::optional<unsigned> mode = std::nullopt);

// For writers that take a path (write_exr, write_png_encoded): `writer` writes the temporary
// path beside `path` (same folder, same extension), which is then renamed into place; when the
// writer throws, the temporary is removed and nothing at `path` changes.
void write_through_temporary(const std::string& path, const std::function<void(const std::string&)>& writer);

// For an output folder to be made: the folder itself or the nearest folder above it that exists,
// when that is not a folder (--out results.db/sub); nullopt when the path can be a folder.
std::optional<std::string> file_in_the_way_of_folder(const std::string& directory);

// Refuses (OutputPathError) a `path` that is a symbolic link, dangling or not: the file a user
// names for output is written only when it is the file itself. `option` names the flag in the
// message ("--out").
void refuse_symbolic_link(const std::string& path, const std::string& option);

}  // namespace glarelab
