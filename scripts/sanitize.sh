#!/usr/bin/env bash
# Builds everything with AddressSanitizer + UndefinedBehaviorSanitizer in build-asan/ and runs the
# whole CTest suite there (docs/HARDENING.md). Warnings stay errors.
#   scripts/sanitize.sh            gcc (the project's compiler)
#   CC=clang CXX=clang++ scripts/sanitize.sh
# Environment: JOBS (build and test jobs, default 2).
# Leaks: LeakSanitizer is on; leaks whose allocation stack lies wholly in the third-party libraries
# named in scripts/lsan_suppressions.txt (Mesa's OpenGL stack, see the comments there) are not
# ours and are suppressed. Any other leak, any ASan report and any UBSan report fails the test it
# happens in.
set -euo pipefail
cd "$(dirname "$0")/.."

launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
start=$(date +%s)
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGLARELAB_SANITIZE=ON "${launcher[@]}"
cmake --build build-asan -j"${JOBS:-2}"
built=$(date +%s)

status=0
(
  cd build-asan
  export ASAN_OPTIONS="detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
  export LSAN_OPTIONS="suppressions=$(pwd)/../scripts/lsan_suppressions.txt:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
  ctest -j"${JOBS:-2}" --timeout 900 --output-on-failure
) || status=$?
end=$(date +%s)
echo "sanitize: build $((built - start)) s, tests $((end - built)) s; ctest exit status $status"
exit "$status"
