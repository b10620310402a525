#!/usr/bin/env bash
# The whole test suite: builds first when needed, then runs every test with CTest (the window
# backend's tests under Xvfb). Assumes scripts/setup.sh has installed the packages once.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f build/CMakeCache.txt ]; then
  # The same configuration as scripts/setup.sh's (Ninja where installed, -O2 without debug
  # information), so that either script may come first and both share one build folder.
  generator=()
  if command -v ninja > /dev/null; then generator=(-G Ninja); fi
  cmake "${generator[@]}" -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
    -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG"
fi
cmake --build build -j"$(nproc)"
# The OpenXR runtime the OpenXR display's tests run against, built once into build/monado (about
# 2 minutes on 2 cores); without its source or packages it says why and the tests skip.
scripts/build_monado.sh "$(nproc)"
cd build
# One test more than cores: some tests spend most of their time waiting on a real clock (the races
# for a session's lease, a held database lock, tracker faults, the status line's period: over a
# minute of the suite, at a tenth to a half of a core); they assert what was logged, not that the
# host kept time, so a third test beside two busy ones changes no result (docs/PERFORMANCE.md,
# "The test suite").
ctest --output-on-failure -j"$(( $(nproc) + 1 ))" --timeout 600
