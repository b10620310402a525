#pragma once
// Shared objects kept mapped until the process exits (RTLD_NODELETE). A library that dlcloses a
// driver it loaded (glvnd and EGL their OpenGL drivers, the OpenXR loader its runtime and API
// layers) unmaps code whose allocations are still referenced from that code's own globals: once the
// module is gone they look unreachable, and LeakSanitizer reports them at exit as leaked from
// "<unknown module>" (docs/HARDENING.md). Kept mapped, they stay reachable; the process frees
// everything at exit either way.
#include <functional>
#include <set>
#include <string>

namespace glarelab {

// The paths of the shared objects mapped now (the executable itself, which has no path here, left
// out).
std::set<std::string> loaded_module_paths();

// Marks every mapped module whose path `keep` accepts RTLD_NODELETE: no dlclose unmaps it.
void keep_modules_loaded(const std::function<bool(const std::string& path)>& keep);

// Keeps mapped, when it is destroyed, every module loaded while it lived (a runtime, the layers and
// drivers it pulled in), and none of those mapped before it was made.
class ModulesLoadedMeanwhileKept {
 public:
  ModulesLoadedMeanwhileKept() : mapped_before_(loaded_module_paths()) {}
  ~ModulesLoadedMeanwhileKept();
  ModulesLoadedMeanwhileKept(const ModulesLoadedMeanwhileKept&) = delete;
  ModulesLoadedMeanwhileKept& operator=(const ModulesLoadedMeanwhileKept&) = delete;

 private:
  std::set<std::string> mapped_before_;
};

}  // namespace glarelab
