#include "glare/analytic/kernel_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "core/user_cache_folder.h"

namespace glarelab {
namespace {

// Raised when the file's layout changes.
constexpr std::uint32_t kFormatVersion = 1;
constexpr char kMagic[8] = {'G', 'L', 'K', 'E', 'R', 'N', 'E', 'L'};

std::mutex& place_mutex() {
  static std::mutex mutex;
  return mutex;
}

KernelCachePlace place_at(const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) return {"", "glare/analytic/kernel_cache: cannot make " + folder.string() + ": " + error.message()};
  return {folder.string(), ""};
}

KernelCachePlace place_from_environment() {
  if (const char* chosen = std::getenv("GLARELAB_KERNEL_CACHE"); chosen != nullptr) {
    const std::string value(chosen);
    if (value.empty() || value == "none") return {"", "GLARELAB_KERNEL_CACHE=none"};
    return place_at(value);
  }
  if (const std::optional<std::filesystem::path> folder = user_cache_folder()) return place_at(*folder / "kernels");
  return {"", "neither GLARELAB_KERNEL_CACHE, XDG_CACHE_HOME nor HOME is set"};
}

KernelCachePlace& current_place() {
  static KernelCachePlace place = place_from_environment();
  return place;
}

// A double exactly, as text ("%a": hexadecimal floating point).
std::string exact(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%a", value);
  return text;
}

// Every input of the kernel, and the fingerprint of the formula that integrates it.
std::string key_text(const AnalyticPsf& psf, const DisplayGeometry& geometry, int half_width_px, int half_height_px) {
  const ObserverEye& eye = psf.eye();
  std::string key = "glarelab display kernel, format " + std::to_string(kFormatVersion) + "\nmodel " +
                    to_string(psf.model()) + "\nage_years " + exact(eye.age_years) + "\npigmentation " +
                    exact(eye.pigmentation) + "\nstraylight_log_s " +
                    (eye.straylight_log_s ? exact(*eye.straylight_log_s) : std::string("none")) +
                    "\nviewing_distance_mm " + exact(geometry.viewing_distance_mm) + "\npixel_pitch_mm " +
                    exact(geometry.pixel_pitch_mm) + "\nhalf_px " + std::to_string(half_width_px) + " " +
                    std::to_string(half_height_px) + "\npeak_fraction " + exact(psf.peak_fraction()) + "\nprobes";
  // Pixels near the source (the polar rule), past CIE's 0.1 degree kink, far out (the tensor rule)
  // and the corner: a change to either rule or to the function changes at least one of them.
  const int probes[][2] = {{0, 0}, {1, 0}, {2, 1}, {7, 3}, {half_width_px / 2, half_height_px / 3},
                           {half_width_px, half_height_px}};
  for (const auto& probe : probes)
    key += " " + exact(pixel_energy(psf, 0, std::min(probe[0], half_width_px), std::min(probe[1], half_height_px), geometry));
  return key + "\n";
}

// FNV-1a over 64-bit words (the tail byte by byte): a damaged or truncated file shows.
std::uint64_t checksum(const char* data, std::size_t size) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  std::size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    std::uint64_t word;
    std::memcpy(&word, data + i, 8);
    hash = (hash ^ word) * 0x100000001b3ULL;
  }
  for (; i < size; ++i) hash = (hash ^ static_cast<unsigned char>(data[i])) * 0x100000001b3ULL;
  return hash;
}

template <typename T>
void put(std::vector<char>& out, const T& value) {
  const char* bytes = reinterpret_cast<const char*>(&value);
  out.insert(out.end(), bytes, bytes + sizeof(T));
}

template <typename T>
bool take(const std::vector<char>& in, std::size_t& at, T& value) {
  if (in.size() - at < sizeof(T)) return false;
  std::memcpy(&value, in.data() + at, sizeof(T));
  at += sizeof(T);
  return true;
}

std::vector<char> encode(const std::string& key, const DisplayKernel& kernel) {
  std::vector<char> out(kMagic, kMagic + sizeof kMagic);
  put(out, kFormatVersion);
  put(out, static_cast<std::uint32_t>(key.size()));
  out.insert(out.end(), key.begin(), key.end());
  put(out, static_cast<std::int32_t>(kernel.half_width_px));
  put(out, static_cast<std::int32_t>(kernel.half_height_px));
  put(out, static_cast<std::int32_t>(kernel.channels));
  put(out, static_cast<std::uint64_t>(kernel.values.size()));
  const char* values = reinterpret_cast<const char*>(kernel.values.data());
  out.insert(out.end(), values, values + kernel.values.size() * sizeof(double));
  put(out, checksum(out.data(), out.size()));
  return out;
}

// The kernel in `in`, or why not.
std::optional<DisplayKernel> decode(const std::vector<char>& in, const std::string& key, std::string& why) {
  std::size_t at = sizeof kMagic;
  std::uint32_t version = 0, key_size = 0;
  std::uint64_t stored_sum = 0;
  if (in.size() < sizeof kMagic + 8 || std::memcmp(in.data(), kMagic, sizeof kMagic) != 0) return why = "not a kernel file", std::nullopt;
  std::memcpy(&stored_sum, in.data() + in.size() - 8, 8);
  if (checksum(in.data(), in.size() - 8) != stored_sum) return why = "checksum mismatch (damaged or truncated)", std::nullopt;
  if (!take(in, at, version) || version != kFormatVersion) return why = "format version " + std::to_string(version), std::nullopt;
  if (!take(in, at, key_size) || in.size() - at < key_size || std::string(in.data() + at, key_size) != key)
    return why = "written for other inputs (key mismatch)", std::nullopt;
  at += key_size;
  std::int32_t half_width = 0, half_height = 0, channels = 0;
  std::uint64_t count = 0;
  if (!take(in, at, half_width) || !take(in, at, half_height) || !take(in, at, channels) || !take(in, at, count))
    return why = "truncated header", std::nullopt;
  DisplayKernel kernel;
  kernel.half_width_px = half_width;
  kernel.half_height_px = half_height;
  kernel.channels = channels;
  const std::uint64_t expected = static_cast<std::uint64_t>(channels) * static_cast<std::uint64_t>(kernel.width_px()) *
                                 static_cast<std::uint64_t>(kernel.height_px());
  if (channels < 1 || count != expected || in.size() - 8 - at != count * sizeof(double))
    return why = "sizes do not add up", std::nullopt;
  kernel.values.resize(count);
  std::memcpy(kernel.values.data(), in.data() + at, count * sizeof(double));
  return kernel;
}

// The file's bytes; nothing when it is missing (not an error), `why` set when it cannot be read or
// is a symbolic link.
std::optional<std::vector<char>> read_entry(const std::string& path, std::string& why) {
  const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    if (errno != ENOENT) why = errno == ELOOP ? "a symbolic link" : std::string("unreadable: ") + std::strerror(errno);
    return std::nullopt;
  }
  std::vector<char> bytes;
  struct stat info {};
  if (fstat(fd, &info) == 0 && S_ISREG(info.st_mode)) {
    bytes.resize(static_cast<std::size_t>(info.st_size));
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t got = read(fd, bytes.data() + done, bytes.size() - done);
      if (got <= 0) break;
      done += static_cast<std::size_t>(got);
    }
    bytes.resize(done);
  } else {
    why = "not a regular file";
  }
  close(fd);
  if (!why.empty()) return std::nullopt;
  return bytes;
}

// Beside the entry, exclusively created (never through a link), flushed, renamed over it.
bool write_entry(const std::string& path, const std::vector<char>& bytes) {
  static std::atomic<unsigned> serial{0};
  const std::string temporary = path + ".tmp." + std::to_string(getpid()) + "." + std::to_string(serial++);
  const int fd = open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t wrote = write(fd, bytes.data() + done, bytes.size() - done);
    if (wrote <= 0) break;
    done += static_cast<std::size_t>(wrote);
  }
  const bool written = done == bytes.size() && fsync(fd) == 0;
  if (close(fd) != 0 || !written || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    return false;
  }
  return true;
}

std::string hex64(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace

std::string KernelCachePlace::describe() const {
  return kept() ? "display kernels kept in " + folder : "display kernels not kept (" + reason + ")";
}

KernelCachePlace kernel_cache_place() {
  std::lock_guard lock(place_mutex());
  return current_place();
}

void use_kernel_cache_folder(const std::string& folder) {
  std::lock_guard lock(place_mutex());
  current_place() = folder.empty() || folder == "none" ? KernelCachePlace{"", "no kernel cache folder chosen"} : place_at(folder);
}

std::string kernel_cache_entry_path(const AnalyticPsf& psf, const DisplayGeometry& geometry, int half_width_px,
                                    int half_height_px) {
  const KernelCachePlace place = kernel_cache_place();
  if (!place.kept()) return {};
  const std::string key = key_text(psf, geometry, half_width_px, half_height_px);
  return (std::filesystem::path(place.folder) / (to_string(psf.model()) + "-" + hex64(checksum(key.data(), key.size())) + ".kernel"))
      .string();
}

DisplayKernel cached_analytic_display_kernel(const AnalyticPsf& psf, const DisplayGeometry& geometry, int half_width_px,
                                             int half_height_px, int threads, long long minimum_pixels,
                                             KernelCacheOutcome* outcome) {
  const auto say = [&](KernelCacheOutcome said) {
    if (outcome != nullptr) *outcome = said;
  };
  const long long pixels = (2LL * half_width_px + 1) * (2LL * half_height_px + 1);
  const std::string path =
      psf.model() == GlareModel::cie && pixels >= minimum_pixels
          ? kernel_cache_entry_path(psf, geometry, half_width_px, half_height_px)
          : std::string();
  if (path.empty()) {
    say(KernelCacheOutcome::not_kept);
    return analytic_display_kernel(psf, geometry, half_width_px, half_height_px, threads);
  }
  const std::string key = key_text(psf, geometry, half_width_px, half_height_px);
  std::string why;
  if (const std::optional<std::vector<char>> bytes = read_entry(path, why)) {
    if (std::optional<DisplayKernel> kernel = decode(*bytes, key, why)) {
      say(KernelCacheOutcome::read);
      return std::move(*kernel);
    }
  }
  if (!why.empty())
    std::cerr << "glare/analytic/kernel_cache: " << path << ": " << why << "; the kernel is integrated again\n";
  DisplayKernel kernel = analytic_display_kernel(psf, geometry, half_width_px, half_height_px, threads);
  if (!write_entry(path, encode(key, kernel)))
    std::cerr << "glare/analytic/kernel_cache: cannot write " << path << "; the next session integrates it again\n";
  say(why.empty() ? KernelCacheOutcome::stored : KernelCacheOutcome::recomputed);
  return kernel;
}

}  // namespace glarelab
