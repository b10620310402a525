#!/usr/bin/env bash
# Builds everything with AddressSanitizer + UndefinedBehaviorSanitizer in build-asan/ and runs the
# whole CTest suite there (docs/HARDENING.md). Warnings stay errors.
#   scripts/sanitize.sh                  gcc (the project's compiler), every target, the whole suite
#   CC=clang CXX=clang++ scripts/sanitize.sh
#   scripts/sanitize.sh REGEX [REGEX...] builds what the suite runs (glarelab, glarelab_tests, the
#                                        fuzz replays) and runs the CTest tests matching any REGEX
#                                        (ctest -R, e.g. '^(TomlReader|ResultStore)\.' or '^fuzz\.')
# Environment: JOBS (build and test jobs, default 2). On a shared machine:
#   JOBS=1 nice -n 19 scripts/sanitize.sh ...
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
selection=()
if [ $# -eq 0 ]; then
  cmake --build build-asan -j"${JOBS:-2}"
else
  replays=(experiment_file_replay csv_table_replay exr_replay script_observer_replay replay_tracker_replay
           pupil_labs_replay condition_json_replay)
  cmake --build build-asan -j"${JOBS:-2}" --target glarelab glarelab_tests "${replays[@]}"
  regex="$(IFS='|'; echo "$*")"
  selection=(-R "$regex")
  echo "sanitize: tests matching $regex"
fi
built=$(date +%s)
# The OpenXR display's tests run against Monado (scripts/build_monado.sh builds it,
# uninstrumented: it is the headset's runtime, not code under test); where the normal build holds
# it in build/monado, the sanitizer build's tests find it there, else the suite's first test
# (OpenXrRuntime.BuildMonado) builds it into build-asan/monado.
if [ -f build/monado/build/openxr_monado-dev.json ] && [ ! -e build-asan/monado ]; then
  ln -s ../build/monado build-asan/monado
fi

status=0
(
  cd build-asan
  # intercept_tls_get_addr=0: GCC 12's sanitizer runtime takes a dynamic TLS block that happens to
  # start 16 bytes into a page for one with glibc 2.19's header and records the two words before it
  # as the block's start and size; LeakSanitizer's tracer then scans that range at exit and dies of
  # SIGSEGV ("Tracer caught signal 11", no report, exit 1), now and then, in processes whose GL
  # driver's threads use dynamic TLS. With glibc 2.25 and later the interceptor records a size of 0
  # for every other block anyway, so turning it off loses no scanned memory (docs/HARDENING.md).
  export ASAN_OPTIONS="detect_leaks=1:intercept_tls_get_addr=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
  export LSAN_OPTIONS="suppressions=$(pwd)/../scripts/lsan_suppressions.txt:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
  ctest -j"${JOBS:-2}" --timeout 900 --output-on-failure "${selection[@]}"
) || status=$?
end=$(date +%s)
echo "sanitize: build $((built - start)) s, tests $((end - built)) s; ctest exit status $status"
exit "$status"
