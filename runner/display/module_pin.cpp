#include "runner/display/module_pin.h"

#include <dlfcn.h>
#include <link.h>

namespace glarelab {
namespace {

int add_module_path(struct dl_phdr_info* info, std::size_t, void* paths) {
  if (info->dlpi_name != nullptr && info->dlpi_name[0] != '\0')
    static_cast<std::set<std::string>*>(paths)->insert(info->dlpi_name);
  return 0;
}

}  // namespace

std::set<std::string> loaded_module_paths() {
  std::set<std::string> paths;
  dl_iterate_phdr(add_module_path, &paths);
  return paths;
}

void keep_modules_loaded(const std::function<bool(const std::string& path)>& keep) {
  // Collected first: dlopen must not run inside dl_iterate_phdr, which holds the loader's lock.
  for (const std::string& path : loaded_module_paths())
    if (keep(path)) dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);  // never closed
}

ModulesLoadedMeanwhileKept::~ModulesLoadedMeanwhileKept() {
  keep_modules_loaded([this](const std::string& path) { return mapped_before_.count(path) == 0; });
}

}  // namespace glarelab
