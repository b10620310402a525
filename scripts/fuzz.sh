#!/usr/bin/env bash
# Runs the libFuzzer targets of fuzz/ (docs/HARDENING.md).
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [RUNS] [TARGET...]
# SECONDS_PER_TARGET: time per target (default 1200, 20 minutes); RUNS: executions per target
# (default 1000000); each target stops at whichever comes first. TARGET: experiment_file,
# csv_table, exr, script_observer, replay_tracker, pupil_labs, condition_json (default: all, one
# after another).
# Configures a clang build with GLARELAB_FUZZ=ON (ASan + UBSan + libFuzzer) in build-fuzz/. The
# corpus each target grows is kept in build-fuzz/fuzz/corpus/TARGET/ (seeds in
# build-fuzz/fuzz/seeds/TARGET/); inputs that crash, leak or time out are written to
# build-fuzz/fuzz/findings/TARGET/. Installs nothing: names the Debian package that is missing.
# Environment: JOBS (build jobs, default 2), FUZZ_FLAGS (extra libFuzzer flags).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-1200}"
runs="${2:-1000000}"
shift $(( $# < 2 ? $# : 2 ))
all_targets=(experiment_file csv_table exr script_observer replay_tracker pupil_labs condition_json)
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=("${all_targets[@]}"); fi
for target in "${targets[@]}"; do
  [[ " ${all_targets[*]} " == *" $target "* ]] || { echo "fuzz: unknown target '$target' (targets: ${all_targets[*]})" >&2; exit 2; }
done

# Tools: clang (Debian package clang) and libFuzzer's runtime, which Debian ships in
# libclang-rt-N-dev for clang N. Checked by compiling a one-line fuzz target.
if ! command -v clang++ >/dev/null || ! command -v clang >/dev/null; then
  echo "fuzz: clang is not installed: apt-get install clang" >&2
  exit 1
fi
clang_major="$(clang++ -dumpversion | cut -d. -f1)"
probe="$(mktemp -d)"
trap 'rm -rf "$probe"' EXIT
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' > "$probe/probe.cpp"
if ! clang++ -fsanitize=fuzzer,address,undefined "$probe/probe.cpp" -o "$probe/probe" 2>"$probe/log"; then
  echo "fuzz: clang++ cannot link a libFuzzer target (libFuzzer and the sanitizer runtimes are missing):" >&2
  echo "fuzz:   apt-get install libclang-rt-${clang_major}-dev" >&2
  sed 's/^/fuzz:   /' "$probe/log" >&2
  exit 1
fi

launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
# Warnings are not errors here: the project's -Werror gate is the gcc build (scripts/test.sh);
# clang's different warning set must not keep the fuzzers from running.
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGLARELAB_FUZZ=ON \
  -DGLARELAB_WERROR=OFF "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j"${JOBS:-2}" --target "${targets[@]/%/_fuzzer}"

summary=()
found_any=0
for target in "${targets[@]}"; do
  work="build-fuzz/fuzz/corpus/$target"
  findings="build-fuzz/fuzz/findings/$target"
  log="build-fuzz/fuzz/$target.log"
  mkdir -p "$work" "$findings"
  echo "fuzz: $target for ${seconds} s or ${runs} runs (log: $log)"
  status=0
  # -rss_limit_mb / -malloc_limit_mb: an input that makes the reader allocate more than 2 GB is a
  # finding (a small corrupt file must not take the machine's memory). -timeout: one input
  # running 25 s is a finding (a hang).
  # shellcheck disable=SC2086
  ASAN_OPTIONS="detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
  UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}" \
    "build-fuzz/fuzz/${target}_fuzzer" -max_total_time="$seconds" -runs="$runs" -rss_limit_mb=2048 -timeout=25 \
      -print_final_stats=1 -artifact_prefix="$findings/" ${FUZZ_FLAGS:-} "$work" "build-fuzz/fuzz/seeds/$target" \
      >"$log" 2>&1 || status=$?
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)"
  coverage="$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1 || true)"
  # crash-, oom-, leak- and timeout- inputs are findings; libFuzzer's slow-unit- files (an input
  # over 10 s of wall time, which a starved process on a loaded machine reaches without any fault
  # of the input) are kept for a look but are not.
  artifacts="$(find "$findings" -type f ! -name 'slow-unit-*' | wc -l)"
  if [ "$status" -ne 0 ] || [ "$artifacts" -ne 0 ]; then
    found_any=1
    result="FOUND (exit $status, $artifacts input(s) in $findings; see $log)"
  else
    result="nothing found"
  fi
  line="$(printf '%-16s executions %-9s exec/s %-6s %-20s %s' "$target" "${execs:-?}" "${rate:-?}" "${coverage:-cov: ?}" "$result")"
  echo "fuzz: $line"
  summary+=("$line")
done

echo
echo "fuzz: summary (${seconds} s or ${runs} runs per target)"
printf '  %s\n' "${summary[@]}"
exit "$found_any"
