#!/usr/bin/env bash
# The random-CSG stress harness (tests/stress/stress_csg.cpp, docs/benchmarks.md "Random-CSG
# stress harness") over COUNT seeds from FIRST_SEED: each scene evaluated, cut into cells at
# N = 2, 3, 5, 8 and decomposed, every output checked by Cover's exact validity test and by CGAL.
# Prints the summary table and the failing seeds per stage and kind. Failing cases land in
# FAILURES/<stage>-<kind>/seed-<s>.json (the scene: `cover evaluate seed-<s>.json -o out.off`
# reproduces it) and seed-<s>.txt (what failed), with FAILURES/SUMMARY.txt and every outcome in
# FAILURES/results.tsv; the folder is replaced as a whole when the run ends.
# Usage: scripts/stress.sh [COUNT] [FIRST_SEED]      (defaults 1000 and 1)
# Environment: JOBS (parallel processes, default 1), THREADS (per process, default 1),
#   BUILD (build folder, default build), FAILURES (default $BUILD/stress/failures),
#   STRESS_ARGS (more stress_csg options, e.g. "--catalogue small --timeout 120").
set -euo pipefail
cd "$(dirname "$0")/.."
count=${1:-1000}
first=${2:-1}
jobs=${JOBS:-1}
build=${BUILD:-build}
failures=${FAILURES:-$build/stress/failures}
if [ ! -f "$build/build.ninja" ] && [ ! -f "$build/Makefile" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" --target stress_csg >/dev/null
meshes=$build/cgal-data/data/meshes
work=$failures.new-$$
rm -rf "$work"
mkdir -p "$work"
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' INT TERM
chunk=$(( (count + jobs - 1) / jobs ))
pids=()
for ((j = 0; j < jobs; j++)); do
  start=$((first + j * chunk))
  n=$(( count - j * chunk < chunk ? count - j * chunk : chunk ))
  [ "$n" -le 0 ] && break
  # shellcheck disable=SC2086
  "$build/bin/stress_csg" --meshes "$meshes" --first "$start" --count "$n" \
    --threads "${THREADS:-1}" --failures "$work" --results "$work/results-$j.tsv" \
    ${STRESS_ARGS:-} >"$work/log-$j.txt" 2>&1 &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p" || true; done
cat "$work"/results-*.tsv >"$work/results.tsv"
rm -f "$work"/results-*.tsv
label="commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
status=0
"$build/bin/stress_csg" --summarize --failures "$work" --label "$label" "$work/results.tsv" || status=$?
rm -rf "$failures"
mv "$work" "$failures"
trap - INT TERM
exit "$status"
