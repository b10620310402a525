#include "runner/session/scene_fingerprints.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/errors.h"
#include "runner/store/sqlite_statement.h"

namespace glarelab {
namespace {

// FNV-1a, 64 bits (Fowler, Noll and Vo): enough to notice a changed file, which is all this is
// for (not a defence against someone forging one). The file is streamed, never held whole.
std::string file_fingerprint(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return "missing";
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  std::uint64_t bytes = 0;
  std::vector<char> buffer(1 << 16);
  while (file) {
    file.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const std::streamsize got = file.gcount();
    for (std::streamsize i = 0; i < got; ++i) {
      hash ^= static_cast<unsigned char>(buffer[static_cast<std::size_t>(i)]);
      hash *= 0x100000001b3ULL;
    }
    bytes += static_cast<std::uint64_t>(got);
  }
  char text[64];
  std::snprintf(text, sizeof text, "fnv1a64=%016llx bytes=%llu", static_cast<unsigned long long>(hash),
                static_cast<unsigned long long>(bytes));
  return text;
}

// NAME -> "fnv1a64=... bytes=..." from the stored lines.
std::map<std::string, std::string> parse(const std::string& stored) {
  std::map<std::string, std::string> by_name;
  std::istringstream lines(stored);
  for (std::string line; std::getline(lines, line);) {
    // NAME \t fnv1a64=... bytes=... \t PATH: a tab, because a quoted TOML key may hold spaces.
    const std::size_t first = line.find('\t');
    const std::size_t second = line.find('\t', first == std::string::npos ? first : first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    by_name[line.substr(0, first)] = line.substr(first + 1, second - first - 1);
  }
  return by_name;
}

}  // namespace

std::vector<std::string> stored_scene_fingerprints(const ResultStore& store, std::int64_t session_id) {
  sqlite::Statement select(store.handle(), store.path(),
                           "SELECT message FROM session_events WHERE session_id = ?1 AND kind = 'scene_fingerprint' "
                           "ORDER BY id",
                           "reading the scene fingerprints of session " + std::to_string(session_id));
  select.bind(1, session_id);
  std::vector<std::string> messages;
  while (select.step()) messages.push_back(select.text(0));
  return messages;
}

std::string scene_fingerprints(const std::map<std::string, SceneSpec>& scenes) {
  std::string lines;
  for (const auto& [name, scene] : scenes)
    if (!scene.file.empty()) lines += name + "\t" + file_fingerprint(scene.file) + "\t" + scene.file + "\n";
  return lines;
}

void check_scene_fingerprints(const std::string& stored, const std::map<std::string, SceneSpec>& scenes,
                              const std::map<std::string, SceneSpec>& scenes_in_file, std::int64_t session_id) {
  const std::map<std::string, std::string> then = parse(stored);
  for (const auto& [name, scene] : scenes) {
    const auto found = then.find(name);
    if (scene.file.empty() || found == then.end()) continue;
    const std::string now = file_fingerprint(scene.file);
    if (now == found->second) continue;
    const auto in_file = scenes_in_file.find(name);
    throw ConfigError(in_file != scenes_in_file.end() ? in_file->second.where : scene.where, "scenes." + name,
                      scene.file + (now == "missing" ? " is gone" : " changed") + " since session " +
                          std::to_string(session_id) + " started (" + found->second + " then, " + now +
                          " now): its remaining trials would show another stimulus; restore the file, or run a new "
                          "session");
  }
}

}  // namespace glarelab
