#pragma once
// The real OpenXR runtime the OpenXR display's tests run against: Monado, built by
// scripts/build_monado.sh into build/monado, as an in-process runtime with its simulated headset
// and null compositor (20 Hz, no window) under Xvfb (../shared/third_party/README.md). Where it is
// not built, or Xvfb or the validation layer is missing, the tests skip and say why.
#include <cstdio>
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

// Why Monado's remote driver cannot be used here, or nothing when it can: it is built with the
// runtime since its controllers were first needed, and patched since its eye tracker was
// (scripts/monado/remote_eye_gaze.patch, which also sets the layout of the data the tests send;
// build/monado/built names the drivers and the patches).
inline std::optional<std::string> monado_remote_missing() {
  if (const auto missing = openxr_runtime_missing(true)) return missing;
  const std::filesystem::path built = monado_manifest().parent_path().parent_path() / "built";
  std::FILE* file = std::fopen(built.c_str(), "r");
  char drivers[128] = {};
  if (file != nullptr) {
    if (std::fgets(drivers, sizeof drivers, file) == nullptr) drivers[0] = '\0';
    std::fclose(file);
  }
  if (std::string(drivers).find("remote") == std::string::npos)
    return "Monado was built without its remote driver (" + built.string() + "): scripts/build_monado.sh builds it again";
  if (std::string(drivers).find("remote_eye_gaze.patch") == std::string::npos)
    return "Monado was built without scripts/monado/remote_eye_gaze.patch (" + built.string() +
           "): scripts/build_monado.sh builds it again";
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

// Monado's remote driver instead of the simulated headset (scripts/build_monado.sh builds it): a
// headset and two Valve Index controllers whose state a TCP client on `port` sets (struct
// r_remote_data, src/xrt/drivers/remote/r_interface.h). The port is read from Monado's
// configuration file, config_v0.json in $XDG_CONFIG_HOME/monado, which this writes under
// `config_home`; P_OVERRIDE_ACTIVE_CONFIG=remote chooses the driver (u_config_json.c). With
// `eye_gaze`, REMOTE_EYE_GAZE=1 adds the patch's eye tracker (XR_EXT_eye_gaze_interaction), whose
// gaze the client sends too; without, the remote headset has none, as the stock driver.
inline std::string monado_remote_environment(const std::filesystem::path& config_home, int port,
                                             bool eye_gaze = false) {
  std::filesystem::create_directories(config_home / "monado");
  std::FILE* file = std::fopen((config_home / "monado" / "config_v0.json").c_str(), "w");
  if (file != nullptr) {
    std::fprintf(file, "{\"remote\": {\"version\": 0, \"port\": %d, \"view_count\": 2}}\n", port);
    std::fclose(file);
  }
  return "XR_RUNTIME_JSON=" + monado_manifest().string() + " XDG_CONFIG_HOME=" + config_home.string() +
         " P_OVERRIDE_ACTIVE_CONFIG=remote XRT_COMPOSITOR_NULL=1 LIBGL_ALWAYS_SOFTWARE=1" +
         std::string(eye_gaze ? " REMOTE_EYE_GAZE=1" : "") +
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
