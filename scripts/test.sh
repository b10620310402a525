#!/usr/bin/env bash
# The whole test suite: builds first when needed, then runs every test with CTest (the window
# backend's tests under Xvfb). Assumes scripts/setup.sh has installed the packages once.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
fi
cmake --build build -j"$(nproc)"
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 600
