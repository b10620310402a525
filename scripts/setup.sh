#!/usr/bin/env bash
# One command from a fresh clone on Debian 12: installs the system packages glarelab needs (only
# those missing; idempotent), configures and builds with CMake, and runs the demo experiment
# offscreen with a simulated observer.
#   scripts/setup.sh            everything
#   scripts/setup.sh --no-demo  packages and build only
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake pkg-config git python3 python3-glad glslang-tools  # toolchain, GL loader generator, shader validator
  universal-ctags                                  # the build's unity groups (cmake/UnityGroups.cmake)
  libgl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libglx-mesa0 libosmesa6-dev libglfw3-dev  # OpenGL: EGL and OSMesa offscreen, GLFW window
  xvfb xauth xdotool                               # a real X display and key presses for the window tests
  libopenexr-dev libpng-dev                        # images
  libsqlite3-dev sqlite3                           # results store (sqlite3: the shell, for inspecting results)
  libtomlplusplus-dev libcli11-dev librandom123-dev # experiment files, command line, counter-based random numbers
  libfftw3-dev                                     # FFTs for the glare engine's CPU path (double and float)
  libglm-dev                                       # GLM: vectors and matrices of the display and eye geometry
  libgtest-dev libgmock-dev libbenchmark-dev       # tests and benchmarks
  libboost-dev libnlopt-cxx-dev nlohmann-json3-dev  # analysis: Boost.Math distributions, NLopt fits, JSON conditions
  python3-scipy chromium                           # analysis tests: SciPy cross-check, report rendering
  libzmq3-dev cppzmq-dev libmsgpack-cxx-dev        # eye trackers: Pupil Core network API (ZeroMQ + msgpack)
  libhidapi-dev libusb-1.0-0-dev                   # response devices (HID) and the USB device list
  libfreetype-dev fonts-dejavu-core                # text on instruction and message screens
  libopenxr-dev libopenxr-loader1 openxr-layer-corevalidation libopenxr-utils  # OpenXR: --display openxr, its validation layer, hello_xr
  # Monado, the OpenXR runtime the OpenXR tests run against (scripts/build_monado.sh builds it)
  ninja-build libvulkan-dev mesa-vulkan-drivers libeigen3-dev libx11-dev libx11-xcb-dev libxcb1-dev libxcb-randr0-dev
  libxrandr-dev libwayland-dev libudev-dev libbsd-dev libcjson-dev patch
)

missing=()
for package in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian package(s): ${missing[*]}"
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  "${sudo_cmd[@]}" apt-get update -q
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#PACKAGES[@]} Debian packages are installed"
fi

# Only the glarelab executable here: the tests, benchmarks and fuzz targets (about 190 of the
# build's units) are built by scripts/test.sh. A configured build folder is kept as it is: cmake
# --build configures again by itself when a CMakeLists.txt changed, and a second setup.sh with
# nothing changed compiles nothing.
build_started_s=$SECONDS
if [ ! -f build/CMakeCache.txt ]; then
  echo "setup: configuring in build/"
  launcher=()
  if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
  # Ninja (installed above): a library's sources compile while the libraries below it still
  # build, where Make has each library's target wait for theirs, so both cores stay busy to the end
  # (docs/PERFORMANCE.md, "Ninja"). A folder configured before with Make keeps Make.
  generator=()
  if command -v ninja > /dev/null; then generator=(-G Ninja); fi
  mkdir -p build
  # -O2 as in RelWithDebInfo, without its -g: the tests run the same optimised code, and the first
  # build spends no time on debug information (about a quarter of its CPU time). scripts/test.sh
  # builds in the same folder; for a debugger, configure another folder with RelWithDebInfo.
  cmake "${generator[@]}" -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
    -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" "${launcher[@]}" > build/configure.log \
    || { cat build/configure.log; exit 1; }
fi
echo "setup: building build/glarelab with $(nproc) jobs (the tests are built by scripts/test.sh)"
cmake --build build -j"$(nproc)" --target glarelab
echo "setup: build took $((SECONDS - build_started_s)) s"

if [ "${1:-}" != "--no-demo" ]; then
  echo "setup: running the demo experiment (offscreen, simulated observer)"
  build/glarelab run examples/demo.toml --display offscreen --observer simulated --participant demo
fi
