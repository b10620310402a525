#include "glare/cpu/fftw_wisdom.h"

#include <fcntl.h>
#include <fftw3.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>
#include <system_error>
#include <vector>

#include "core/user_cache_folder.h"

namespace glarelab {
namespace {

// FFTW_MEASURE's time for one plan, at most: past it FFTW keeps the best plan it has timed. The
// convolution's largest plans (three 2048 x 2048 channels) measure in about 1 s on two cores.
constexpr double kMeasureLimitS = 4.0;

std::mutex& place_mutex() {
  static std::mutex mutex;
  return mutex;
}

FftwWisdomPlace place_at(const std::filesystem::path& file) {
  std::error_code error;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), error);
  if (error)
    return {"", "glare/cpu/fftw_wisdom: cannot make " + file.parent_path().string() + " for the FFTW wisdom: " + error.message()};
  return {file.string(), ""};
}

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "host";
  std::string host(name);
  for (char& c : host)
    if (c == '/' || c == ' ') c = '_';
  return host;
}

FftwWisdomPlace place_from_environment() {
  if (const char* chosen = std::getenv("GLARELAB_FFTW_WISDOM"); chosen != nullptr) {
    const std::string value(chosen);
    if (value.empty() || value == "none") return {"", "GLARELAB_FFTW_WISDOM=none"};
    return place_at(value);
  }
  const std::string file = "fftwf-" + host_name() + ".wisdom";
  if (const std::optional<std::filesystem::path> folder = user_cache_folder()) return place_at(*folder / file);
  return {"", "neither GLARELAB_FFTW_WISDOM, XDG_CACHE_HOME nor HOME is set"};
}

FftwWisdomPlace& current_place() {
  static FftwWisdomPlace place = place_from_environment();
  return place;
}

// FFTW's export lists its wisdom in the order of its hash table, which importing changes: the same
// wisdom can come out in another order. Sorted, the entries between the header line and the closing
// parenthesis give one text per wisdom, so the file is rewritten only when planning added to it.
std::string canonical_wisdom(const std::string& exported) {
  std::istringstream in(exported);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  if (lines.size() < 2) return exported;
  std::sort(lines.begin() + 1, lines.end() - 1);
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

std::string read_whole(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

std::string FftwWisdomPlace::describe() const {
  return kept() ? "FFTW plans measured once and kept in " + path : "FFTW plans estimated (" + reason + ")";
}

FftwWisdomPlace fftw_wisdom_place() {
  std::lock_guard lock(place_mutex());
  return current_place();
}

void use_fftw_wisdom_file(const std::string& path) {
  std::lock_guard lock(place_mutex());
  current_place() = path.empty() || path == "none" ? FftwWisdomPlace{"", "no wisdom file chosen"} : place_at(path);
}

fftwf_plan_s* plan_with_kept_wisdom(const std::function<fftwf_plan_s*(unsigned rigor_flags)>& make_plan) {
  const FftwWisdomPlace place = fftw_wisdom_place();
  if (!place.kept()) return make_plan(FFTW_ESTIMATE);
  const std::string lock_path = place.path + ".lock";
  const int lock_fd = open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd < 0 || flock(lock_fd, LOCK_EX) != 0) {
    if (lock_fd >= 0) close(lock_fd);
    std::cerr << "glare/cpu/fftw_wisdom: cannot lock " << lock_path << "; this plan is estimated\n";
    return make_plan(FFTW_ESTIMATE);
  }
  // The file's wisdom joins what this process has (a missing or unreadable file adds nothing; a
  // damaged one is replaced below by what this process knows).
  const std::string before = read_whole(place.path);
  if (!before.empty()) fftwf_import_wisdom_from_string(before.c_str());
  fftwf_set_timelimit(kMeasureLimitS);
  fftwf_plan plan = make_plan(FFTW_MEASURE);
  fftwf_set_timelimit(FFTW_NO_TIMELIMIT);
  // The plan counts as kept only if the wisdom now holds it (FFTW_WISDOM_ONLY plans from wisdom
  // alone, or not at all): a measurement cut short by the time limit, for one, may not be recorded,
  // and the next run would measure again and could pick another plan. Such a problem is estimated.
  if (plan != nullptr) {
    if (fftwf_plan check = make_plan(FFTW_MEASURE | FFTW_WISDOM_ONLY); check != nullptr) {
      fftwf_destroy_plan(check);
    } else {
      fftwf_destroy_plan(plan);
      plan = make_plan(FFTW_ESTIMATE);
      std::cerr << "glare/cpu/fftw_wisdom: a measured plan was not kept in the wisdom; this plan is estimated\n";
    }
  }
  if (char* exported = fftwf_export_wisdom_to_string(); exported != nullptr) {
    const std::string after = canonical_wisdom(exported);
    std::free(exported);
    if (before != after) {
      const std::string temporary = place.path + ".tmp." + std::to_string(getpid());
      bool written = false;
      if (std::FILE* out = std::fopen(temporary.c_str(), "wb"); out != nullptr) {
        written = std::fwrite(after.data(), 1, after.size(), out) == after.size();
        written = std::fflush(out) == 0 && fsync(fileno(out)) == 0 && written;
        written = std::fclose(out) == 0 && written;
      }
      if (!written || std::rename(temporary.c_str(), place.path.c_str()) != 0) {
        std::remove(temporary.c_str());
        std::cerr << "glare/cpu/fftw_wisdom: cannot write " << place.path
                  << "; this run's measured plans may differ from the next run's\n";
      }
    }
  }
  // Forgotten in memory (it stays in the file): an FFTW_ESTIMATE plan made later would otherwise
  // follow this wisdom where it holds the same problem, in some runs and not in others.
  fftwf_forget_wisdom();
  flock(lock_fd, LOCK_UN);
  close(lock_fd);
  return plan;
}

}  // namespace glarelab
