#!/usr/bin/env bash
# Runs every example experiment offscreen with the simulated observer, seeded, with two glarelab
# binaries, and compares what each stored and showed: the trials rows (every stored column but the
# wall clock), the frames rows, and the frames each saved with --save-frames (compare_frames, built
# beside the AFTER binary in scripts/: identical, or within 1e-6 relative where only the order of
# floating-point sums changed, each such frame named). For refactors that must not change
# behaviour: build the commit before the change elsewhere (git worktree add /tmp/before HEAD~1;
# cmake there) and pass both binaries.
#   scripts/compare_runs.sh BEFORE_BINARY AFTER_BINARY [SEED]
# Exit 0 when every example stores identical rows and equal frames with both; 1 with the first
# differences shown.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then
  echo "usage: scripts/compare_runs.sh BEFORE_BINARY AFTER_BINARY [SEED]" >&2
  exit 2
fi
before=$(realpath "$1")
after=$(realpath "$2")
seed=${3:-7}
compare_frames=$(dirname "$after")/scripts/compare_frames
if [ ! -x "$compare_frames" ]; then
  echo "compare_runs: $compare_frames is missing (build the compare_frames target beside $after)" >&2
  exit 2
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

dump() {  # DATABASE OUT_PREFIX
  sqlite3 -header -csv "$1" "SELECT trial_index, block, procedure, condition, intensity, response, correct,
    response_time_s, onset_s, staircase, reversal FROM trials ORDER BY trial_index" > "$2.trials.csv"
  sqlite3 -header -csv "$1" "SELECT t.trial_index, f.frame_index, f.scheduled_s, f.flip_s, f.dropped
    FROM frames f JOIN trials t ON t.id = f.trial_id ORDER BY t.trial_index, f.scheduled_s, f.frame_index" > "$2.frames.csv"
}

status=0
for experiment in examples/*.toml; do
  name=$(basename "$experiment" .toml)
  for side in before after; do
    binary=$before
    [ "$side" = after ] && binary=$after
    # An experiment that reads the participant's measured straylight finds it in its database: the
    # measurement (examples/straylight.toml) is run there first, by the same binary.
    if grep -q '^straylight *= *"measured"' "$experiment"; then
      "$binary" run examples/straylight.toml --display offscreen --observer simulated --participant compare \
        --participant-number 1 --seed "$seed" --db "$work/$name.$side.db" > "$work/$name.$side.measure.log" 2>&1 || {
        echo "$name: the $side binary's straylight measurement failed (exit $?):"; tail -n 5 "$work/$name.$side.measure.log"
        status=1; continue 2; }
    fi
    "$binary" run "$experiment" --display offscreen --observer simulated --participant compare \
      --participant-number 1 --seed "$seed" --db "$work/$name.$side.db" \
      --save-frames "$work/$name.$side.saved" > "$work/$name.$side.log" 2>&1 || {
      echo "$name: the $side binary failed (exit $?):"; tail -n 5 "$work/$name.$side.log"; status=1; continue 2; }
    dump "$work/$name.$side.db" "$work/$name.$side"
  done
  trials=$(wc -l < "$work/$name.after.trials.csv")
  frames=$(wc -l < "$work/$name.after.frames.csv")
  if cmp -s "$work/$name.before.trials.csv" "$work/$name.after.trials.csv" &&
     cmp -s "$work/$name.before.frames.csv" "$work/$name.after.frames.csv"; then
    echo "$name: identical rows ($((trials - 1)) trials, $((frames - 1)) frames)"
  else
    echo "$name: DIFFERENT"
    diff "$work/$name.before.trials.csv" "$work/$name.after.trials.csv" | head -n 10 || true
    diff "$work/$name.before.frames.csv" "$work/$name.after.frames.csv" | head -n 10 || true
    status=1
  fi
  if ! "$compare_frames" "$work/$name.before.saved" "$work/$name.after.saved" | sed "s/^/$name: /"; then
    echo "$name: saved frames DIFFERENT"
    status=1
  fi
done
exit $status
