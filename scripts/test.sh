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
# The OpenXR runtime the OpenXR display's tests run against is built once into build/monado by the
# suite's first test (OpenXrRuntime.BuildMonado, tests/CMakeLists.txt), beside the other tests;
# without its source or packages it says why and the OpenXR tests skip.
cd build
# The tests' processes and the glarelab processes they start, in two settings that change no
# result, only the CPU time (docs/PERFORMANCE.md, "The suite's environment"):
# - glibc.malloc.hugetlb=1: malloc asks the kernel for transparent huge pages (madvise) for what it
#   maps, the frame-sized buffers of the glare and perception stages among them, so that a 33 MB
#   frame is faulted in as 17 huge pages instead of 8100 small ones. On the 2-core VM a page fault
#   costs about 11 us; ten of the longest tests took 50.3 CPU-s with it against 71.5 without. Not
#   for compilers: GCC took 40 % longer with it, so the build above and Monado's (the suite's
#   first test, tests/CMakeLists.txt) run without it.
# - LP_NUM_THREADS=0: Mesa's llvmpipe rasterises in the thread that draws instead of handing each
#   draw to threads of its own, one per core; with one test more than cores running those add
#   hand-offs and no speed (seven GL tests run one at a time: 49.3 CPU-s against 59.3).
export GLIBC_TUNABLES=glibc.malloc.hugetlb=1 LP_NUM_THREADS=0
# One test more than cores: some tests spend most of their time waiting on a real clock (the races
# for a session's lease, a held database lock, tracker faults, the status line's period: over a
# minute of the suite, at a tenth to a half of a core); they assert what was logged, not that the
# host kept time, so a third test beside two busy ones changes no result (docs/PERFORMANCE.md,
# "The test suite").
ctest --output-on-failure -j"$(( $(nproc) + 1 ))" --timeout 600
