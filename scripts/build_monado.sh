#!/usr/bin/env bash
# Builds Monado, an open OpenXR runtime, from its source tarball in ../shared/third_party/ into
# build/monado, once: the OpenXR display backend's tests (tests/openxr_*_test.cpp) run against its
# simulated headset and null compositor, headless under Xvfb (docs/STEREO.md). The source stays
# outside the repository; it is unpacked into build/monado/src and the patches of scripts/monado/
# are applied there (a changed patch builds the runtime again).
#   scripts/build_monado.sh [JOBS [FOLDER]]   JOBS defaults to nproc, FOLDER to build/monado
# The suite runs it as its first test (OpenXrRuntime.BuildMonado, tests/CMakeLists.txt) with the
# build folder's monado/, where the tests look for the runtime.
# Exit 0 when the runtime is built (or was already), and also, with a "skipped:" line saying why,
# when the tarball or a package the build needs is missing: the OpenXR tests then skip likewise.
set -euo pipefail
cd "$(dirname "$0")/.."
repository=$PWD
jobs=${1:-$(nproc)}
out=${2:-build/monado}
# The folder is emptied before a build: only one named monado is taken.
if [ "$(basename "$out")" != monado ]; then
  echo "build_monado: the runtime's folder must be named monado (got $out)"
  exit 2
fi
case $out in /*) ;; *) out=$repository/$out ;; esac
manifest=$out/build/openxr_monado-dev.json

# What the build holds: the drivers and the patches applied to the unpacked source (each by its
# content's hash), so that a runtime built before a driver was added, or before a patch changed,
# is built again.
shopt -s nullglob
patches=(scripts/monado/*.patch)
shopt -u nullglob
built_text="simulated remote"
for patch_file in "${patches[@]}"; do
  built_text+=" $(basename "$patch_file"):$(sha256sum "$patch_file" | cut -c1-16)"
done
if [ -f "$manifest" ] && [ -f "$out/built" ] && [ "$(cat "$out/built")" = "$built_text" ]; then
  echo "build_monado: already built ($manifest)"
  exit 0
fi

# ../shared beside the repository; for a git worktree elsewhere, beside its main checkout.
common_dir=$(git rev-parse --path-format=absolute --git-common-dir 2>/dev/null || echo .git)
shopt -s nullglob
tarballs=(../shared/third_party/monado-*.tar.gz "$(dirname "$common_dir")"/../shared/third_party/monado-*.tar.gz)
shopt -u nullglob
if [ ${#tarballs[@]} -eq 0 ]; then
  echo "build_monado: skipped: no Monado source (../shared/third_party/monado-*.tar.gz) beside the repository;" \
       "the OpenXR tests will skip"
  exit 0
fi
tarball=${tarballs[0]}

# What Monado's in-process runtime with the simulated headset needs here (the third-party
# README), beside the OpenXR loader and headers the backend itself builds against.
PACKAGES=(cmake ninja-build pkg-config glslang-tools libvulkan-dev mesa-vulkan-drivers libeigen3-dev
          libx11-dev libx11-xcb-dev libxcb1-dev libxcb-randr0-dev libxrandr-dev libgl-dev libegl-dev libwayland-dev libusb-1.0-0-dev
          libudev-dev libhidapi-dev libbsd-dev libcjson-dev libopenxr-dev patch)
missing=()
for package in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "build_monado: skipped: Debian package(s) missing: ${missing[*]} (scripts/setup.sh installs them);" \
       "the OpenXR tests will skip"
  exit 0
fi

started_s=$SECONDS
rm -rf "$out"
mkdir -p "$out/src"
echo "build_monado: unpacking $(basename "$tarball") into $out/src"
tar -xzf "$tarball" -C "$out/src" --strip-components=1
# The patches (scripts/monado/), applied to the unpacked copy; the tarball stays as it came.
# remote_eye_gaze.patch gives the remote driver an eye tracker (XR_EXT_eye_gaze_interaction,
# REMOTE_EYE_GAZE=1) whose gaze the test client sends: the eye-gaze tests run against it.
for patch_file in "${patches[@]}"; do
  echo "build_monado: applying $(basename "$patch_file")"
  patch -d "$out/src" -p1 --quiet < "$patch_file" \
    || { echo "build_monado: $patch_file does not apply to $(basename "$tarball")"; exit 1; }
done

# Every driver off but the simulated headset and the remote one (those declared with a plain
# option(), such as North Star's, too); an in-process runtime (no service, no IPC). The remote
# driver (src/xrt/drivers/remote, chosen with P_OVERRIDE_ACTIVE_CONFIG=remote) is a headset and two
# Index controllers whose state a TCP client sets (struct r_remote_data): the controller tests press
# its buttons through it. It needs aux_vive (the Index controller's bindings). The main compositor stays on: the
# in-process target always links it (off fails with "cannot find -lcomp_main"); the null
# compositor is chosen at run time with XRT_COMPOSITOR_NULL=1. -O1 without debug information: the
# tests never debug Monado, debug information took about 30 % of its compile time, and -O1 builds
# in 12 % less CPU time than -O2 with the OpenXR tests' own CPU time unchanged (docs/PERFORMANCE.md,
# "The test suite").
drivers_off=()
for driver in $(grep -oE 'option(_with_deps)?\(XRT_BUILD_DRIVER_[A-Z0-9_]*' "$out/src/CMakeLists.txt" | sed 's/.*(//' | sort -u); do
  [ "$driver" = XRT_BUILD_DRIVER_SIMULATED ] || [ "$driver" = XRT_BUILD_DRIVER_REMOTE ] || drivers_off+=("-D$driver=OFF")
done
# ccache where installed: a build made again for a changed patch compiles only what it changed.
launcher=()
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
echo "build_monado: configuring in $out/build"
CCACHE_BASEDIR=$repository cmake -G Ninja -S "$out/src" -B "$out/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_C_FLAGS_RELEASE="-O1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DXRT_FEATURE_SERVICE=OFF -DXRT_MODULE_IPC=OFF -DXRT_MODULE_COMPOSITOR_MAIN=ON \
  -DXRT_MODULE_COMPOSITOR_NULL=ON -DBUILD_TESTING=OFF -DXRT_BUILD_SAMPLES=OFF \
  -DXRT_MODULE_MONADO_CLI=OFF -DXRT_MODULE_AUX_VIVE=ON -DXRT_FEATURE_STEAMVR_PLUGIN=OFF \
  -DXRT_HAVE_OPENCV=OFF -DXRT_HAVE_GST=OFF -DXRT_HAVE_SDL2=OFF \
  "${launcher[@]}" "${drivers_off[@]}" -DXRT_BUILD_DRIVER_SIMULATED=ON -DXRT_BUILD_DRIVER_REMOTE=ON > "$out/configure.log" 2>&1 \
  || { tail -40 "$out/configure.log"; echo "build_monado: configuring Monado failed ($out/configure.log)"; exit 1; }
# Only the runtime the tests load (openxr_monado) and what it links: not the debug GUI's state
# tracker and its bundled imgui and implot (the largest sources of the tree), nor the mock
# compositor, which nothing here loads.
echo "build_monado: building the runtime with $jobs jobs (about 2 minutes on 2 cores)"
CCACHE_BASEDIR=$repository cmake --build "$out/build" -j"$jobs" --target openxr_monado > "$out/build.log" 2>&1 \
  || { tail -40 "$out/build.log"; echo "build_monado: building Monado failed ($out/build.log)"; exit 1; }
if [ ! -f "$manifest" ]; then
  echo "build_monado: the build finished without $manifest"
  exit 1
fi
echo "$built_text" > "$out/built"
echo "build_monado: built in $((SECONDS - started_s)) s: XR_RUNTIME_JSON=$manifest"
