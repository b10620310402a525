#!/usr/bin/env bash
# The GPU check: on a machine with a GPU, headless (EGL, no display), build glarelab and its tests,
# run the GL tests and the GL rows of `glarelab bench`, and write one markdown report: a table with
# the machine's name, its GPU and OpenGL renderer, the GL tests' result and the load, followed by the
# bench's own speed-against-error tables. Meant to finish in a few minutes on a many-core server.
#
# Usage: scripts/gpu_check.sh [REPORT_FILE]     (default: the file gpu_check.md in build-gpu/)
# Environment: GPU_CHECK_BUILD (build folder, default build-gpu), GPU_CHECK_QUICK=1 (the bench's
# quick grids only), GPU_CHECK_BUILD_TYPE (default Release), GPU_CHECK_PREBUILT=1 (no configure or
# build: the folder already holds glarelab and tests/glarelab_tests, built on another machine, for a
# GPU server without the build's packages; their shared libraries must be on its loader's path).
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1

build=${GPU_CHECK_BUILD:-build-gpu}
report=${1:-$build/gpu_check.md}
jobs=$(nproc)
mkdir -p "$build" "$(dirname "$report")"
unset DISPLAY WAYLAND_DISPLAY  # EGL without a display, as on a server

step() { printf '[gpu_check] %s\n' "$*" >&2; }
fail() {
  step "FAILED: $1 (log: $2)"
  tail -n 30 "$2" >&2
  exit 1
}

started=$(date +%s)
if [ "${GPU_CHECK_PREBUILT:-0}" = 1 ]; then
  for binary in "$build/glarelab" "$build/tests/glarelab_tests"; do
    [ -x "$binary" ] || { step "FAILED: GPU_CHECK_PREBUILT=1 but $binary is not an executable"; exit 1; }
  done
  step "using the binaries already built in $build"
else
  step "configuring $build (${GPU_CHECK_BUILD_TYPE:-Release})"
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE="${GPU_CHECK_BUILD_TYPE:-Release}" > "$build/configure.log" 2>&1 ||
    fail "configure" "$build/configure.log"
  step "building glarelab and glarelab_tests with $jobs jobs"
  cmake --build "$build" -j"$jobs" --target glarelab glarelab_tests > "$build/build.log" 2>&1 ||
    fail "build" "$build/build.log"
fi
built=$(date +%s)

# The tests that run OpenGL: the GL glare backend's transforms, PSFs and convolution against the
# CPU double reference, the GL frame engine against the CPU engine, and the offscreen display.
gl_tests='Gl*:FrameEngineGl*:GlareBackendAgreement*:OffscreenBackend*:GpuRoundTrip*:Examples/NoRoundTrip*:Examples/GpuEngineFrames*'
step "GL tests ($gl_tests)"
"$build/tests/glarelab_tests" --gtest_filter="$gl_tests" > "$build/gl_tests.log" 2>&1
tests_status=$?
tests_passed=$(grep -c '^\[       OK \]' "$build/gl_tests.log")
# Each test's own result line ends in its time; gtest lists the failed and skipped again at the end.
tests_failed=$(grep -c '^\[  FAILED  \] [A-Za-z].* ([0-9]* ms)$' "$build/gl_tests.log")
tests_skipped=$(grep -c '^\[  SKIPPED \] [A-Za-z].* ([0-9]* ms)$' "$build/gl_tests.log")
tested=$(date +%s)

engine=()
if "$build/glarelab" bench --help 2>/dev/null | grep -q -- '--engine'; then engine=(--engine gpu); fi
quick=()
if [ "${GPU_CHECK_QUICK:-0}" = 1 ]; then quick=(--quick); fi
# The GPU's SM clock through the benches, four samples a second: a GPU left mostly idle between
# short submissions stays near its idle clock, and its stage times scale with it (an H200's GL
# transforms took 0.58 ms at 1980 MHz and 2.87 ms near 345 MHz; docs/PERFORMANCE.md).
sampler=
if command -v nvidia-smi >/dev/null; then
  nvidia-smi --query-gpu=clocks.sm,clocks.max.sm,utilization.gpu --format=csv,noheader,nounits -lms 250 \
    > "$build/clocks.csv" 2>/dev/null &
  sampler=$!
fi
step "glarelab bench ${quick[*]} ${engine[*]}"
"$build/glarelab" bench "${quick[@]}" "${engine[@]}" > "$build/bench.log" 2>&1 || fail "bench" "$build/bench.log"
step "glarelab bench --perception-only ${engine[*]}"
"$build/glarelab" bench --perception-only "${engine[@]}" > "$build/bench_perception.log" 2>&1 ||
  fail "bench --perception-only" "$build/bench_perception.log"
finished=$(date +%s)
clocks="not sampled (no nvidia-smi)"
if [ -n "$sampler" ]; then
  kill "$sampler" 2>/dev/null
  wait "$sampler" 2>/dev/null
  clocks=$(grep -E '^[0-9]+, *[0-9]+' "$build/clocks.csv" | sort -t, -k1,1n |
    awk -F', *' '{ n++; s[n] = $1; if ($1 >= 0.9 * $2) high++; max = $2 }
      END { if (n == 0) { print "no samples"; exit }
            printf "%d samples: median %d MHz, %d %% of them at 90 %% of the maximum %d MHz or above", n,
            s[int((n + 1) / 2)], 100 * high / n, max }')
fi
# The GL engine's whole frame (the frame engines' row of --perception-only): fastest ms.
engine_frame=$(awk -F'|' '$2 ~ /^ gl $/ { gsub(/ /, "", $4); print $4; exit }' "$build/bench_perception.log")
# The GPU's targets (hybrid glare at 1920 x 1080 within 2 ms, two headset eyes within 90 Hz).
targets=$(grep -m 1 '^GL engine: 1920 x 1080 with hybrid glare' "$build/bench_perception.log" | sed 's/^GL engine: //; s/\.$//')

gpu=$(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | head -n 1)
renderer=$(grep -m 1 '^OpenGL renderer:' "$build/bench.log" | sed 's/^OpenGL renderer: //; s/\.$//')
cpu=$(grep -m 1 'model name' /proc/cpuinfo | sed 's/.*: //')
{
  echo "## GPU check: $(hostname), $(date -u +%Y-%m-%d)"
  echo
  echo "| what | value |"
  echo "|---|---|"
  echo "| machine | $(hostname): ${cpu:-unknown CPU}, $jobs cores |"
  echo "| GPU | ${gpu:-no nvidia-smi} |"
  echo "| OpenGL renderer | ${renderer:-not reported} |"
  echo "| binaries | $("$build/glarelab" --version 2>/dev/null || echo unknown) |"
  echo "| GL tests | $tests_passed passed, $tests_failed failed, $tests_skipped skipped (exit $tests_status) |"
  echo "| build / tests / bench | $((built - started)) s / $((tested - built)) s / $((finished - tested)) s |"
  echo "| GL engine frame, 1920 x 1080, static Ritschel glare and every perception stage | fastest ${engine_frame:-not reported} ms |"
  echo "| GL engine at the targets | ${targets:-not reported} |"
  echo "| SM clock during the benches | $clocks |"
  echo "| load average at the end | $(cut -d' ' -f1-3 /proc/loadavg) |"
  echo
  echo "### glarelab bench ${quick[*]} ${engine[*]}"
  echo
  cat "$build/bench.log"
  echo
  echo "### glarelab bench --perception-only ${engine[*]}"
  echo
  cat "$build/bench_perception.log"
} > "$report"
step "report: $report"
if [ "$tests_status" -ne 0 ]; then
  step "GL tests failed:"
  grep '^\[  FAILED  \] [A-Za-z].* ([0-9]* ms)$' "$build/gl_tests.log" >&2
  exit 1
fi
exit 0
