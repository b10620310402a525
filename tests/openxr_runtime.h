#pragma once
// The real OpenXR runtime the OpenXR display's tests run against: Monado, built by
// scripts/build_monado.sh into build/monado, as an in-process runtime with its simulated headset
// and null compositor (20 Hz, no window) under Xvfb (../shared/third_party/README.md). Where it is
// not built, or Xvfb or the validation layer is missing, the tests skip and say why.
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "openxr_available.h"

namespace glarelab::test {

// Monado's manifest beside the glarelab binary (build/monado/build/openxr_monado-dev.json).
inline std::filesystem::path monado_manifest() {
  return std::filesystem::path(GLARELAB_BINARY).parent_path() / "monado" / "build" / "openxr_monado-dev.json";
}

inline const char* kCoreValidationManifest =
    "/usr/share/openxr/1/api_layers/explicit.d/XrApiLayer_core_validation.x86_64-linux-gnu.json";

// Why the runtime tests cannot run here, or nothing when they can.
inline std::optional<std::string> openxr_runtime_missing(bool needs_xvfb_run) {
  if (!GLARELAB_HAVE_OPENXR) return "built without the OpenXR loader (install libopenxr-dev: scripts/setup.sh)";
  if (!std::filesystem::exists(monado_manifest()))
    return "Monado is not built (" + monado_manifest().string() + "): scripts/build_monado.sh builds it";
  if (!std::filesystem::exists(kCoreValidationManifest))
    return "the OpenXR core validation layer is not installed (openxr-layer-corevalidation: scripts/setup.sh)";
  if (needs_xvfb_run && std::system("command -v xvfb-run > /dev/null") != 0)
    return "xvfb-run is missing (xvfb: scripts/setup.sh)";
  return std::nullopt;
}

// The environment that selects Monado's simulated headset and null compositor, software GL and
// Vulkan, and the core validation layer, as "NAME=value" words for env(1).
inline std::string monado_environment() {
  return "XR_RUNTIME_JSON=" + monado_manifest().string() +
         " XRT_COMPOSITOR_NULL=1 SIMULATED_ENABLE=1 LIBGL_ALWAYS_SOFTWARE=1"
         " VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"
         " XR_ENABLE_API_LAYERS=XR_APILAYER_LUNARG_core_validation";
}

// The same set in this process (for a display made in the test itself).
inline void set_monado_environment() {
  setenv("XR_RUNTIME_JSON", monado_manifest().c_str(), 1);
  setenv("XRT_COMPOSITOR_NULL", "1", 1);
  setenv("SIMULATED_ENABLE", "1", 1);
  setenv("LIBGL_ALWAYS_SOFTWARE", "1", 1);
  setenv("VK_ICD_FILENAMES", "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json", 1);
  setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
}

}  // namespace glarelab::test
