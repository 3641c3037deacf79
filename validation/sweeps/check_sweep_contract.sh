#!/usr/bin/env bash
# The sweep contract (issue: thermally cycled bed): the summary of a sweep is the same
# bit for bit whether it runs locally, under mpirun with 2 ranks, or is stopped and
# started again (the finished runs are skipped); and runs that differ only in what
# cannot act before the settle stage ends start from one shared settled packing.
#   check_sweep_contract.sh RATCHET_BIN WORK_DIR
set -euo pipefail
bin="$1"; work="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
rm -rf "$work"; mkdir -p "$work"
cat > "$work/sweep.json" <<JSON
{"scene": "$here/bed_quick.json",
 "set": {"particles.generate.count": 12, "settle.ke_ratio": 1e-3, "thermal.cycles": 1, "time.dt": 0.005},
 "grid": {"container.opening_angle_deg": [0, 6]}, "realizations": 2}
JSON
fail() { echo "check_sweep_contract: FAILED: $*" >&2; exit 1; }
"$bin" sweep "$work/sweep.json" --out "$work/local" --jobs 2
mpirun --allow-run-as-root --oversubscribe -n 2 "$bin" sweep "$work/sweep.json" --out "$work/mpi"
cmp "$work/local/summary.csv" "$work/mpi/summary.csv" || fail "summary under mpirun -n 2 differs from the local one"
[[ $(grep -c ',completed$' "$work/local/summary.csv") -eq 4 ]] || fail "not all 4 runs completed"
# Two angles x two seeds: four containers-and-seeds, four packings, locally and under MPI.
for d in local mpi; do
  [[ $(ls "$work/$d/packings" | grep -c '\.state$') -eq 4 ]] || fail "$d: expected 4 packings: $(ls "$work/$d/packings")"
done
# Column of the packing key in summary.csv, and the key of run K.
packing_col="$(head -1 "$work/local/summary.csv" | tr ',' '\n' | grep -nx packing | cut -d: -f1)"
[[ -n "$packing_col" ]] || fail "summary.csv has no packing column"
key_of() { awk -F, -v c="$packing_col" -v r="$2" 'NR > 1 && $1 == r { print $c }' "$1/summary.csv"; }
# Interrupted sweep: one run removed, one left half-written (no run.json): both rerun;
# the packing of the removed run is cut short (half-written) and is made again.
rm -rf "$work/mpi/runs/1"
rm -f "$work/mpi/runs/2/run.json"
key1="$(key_of "$work/local" 1)"
[[ -f "$work/mpi/packings/$key1.state" ]] || fail "no packing $key1 for run 1"
truncate -s 100 "$work/mpi/packings/$key1.state"
out="$("$bin" sweep "$work/sweep.json" --out "$work/mpi" 2>&1)"
grep -q "2 of 4 runs already completed; running 2" <<<"$out" || fail "resume did not skip exactly the 2 finished runs: $out"
grep -q "packing unusable, making it again: .*$key1" <<<"$out" || fail "resume did not notice the cut packing: $out"
grep -q "1 of 2 packings already made; making 1" <<<"$out" || fail "resume did not reuse the whole packing: $out"
cmp "$work/local/summary.csv" "$work/mpi/summary.csv" || fail "summary after resume differs"
# Ratio grid (2 points) x 2 seeds: alpha_c cannot act before the settle stage ends, so
# exactly 2 packings, and both grid points of a seed start from the same state.
cat > "$work/ratio.json" <<JSON
{"scene": "$here/bed_quick.json",
 "set": {"particles.generate.count": 12, "settle.ke_ratio": 1e-3, "thermal.cycles": 1, "time.dt": 0.005,
         "outputs.bodies_every": 100},
 "grid": {"thermal.alpha_c": [2.5e-4, 1e-3]}, "realizations": 2}
JSON
"$bin" sweep "$work/ratio.json" --out "$work/ratio" --jobs 2
[[ $(ls "$work/ratio/packings" | grep -c '\.state$') -eq 2 ]] || fail "ratio sweep: expected 2 packings: $(ls "$work/ratio/packings")"
# Seeds are innermost: runs 0 and 2 have seed 1, runs 1 and 3 seed 2. 12 bodies per step.
first_rows() { sed -n '2,13p' "$work/ratio/runs/$1/bodies.csv"; }
# The step where the bed reached settle.ke_ratio, as run 0's run.json records it.
packing_step="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["packing"]["step"])' \
  "$work/ratio/runs/0/run.json")"
[[ "$packing_step" -gt 0 ]] || fail "run 0's run.json names no packing step"
[[ "$(first_rows 0 | cut -d, -f1 | sort -u)" == "$packing_step" ]] ||
  fail "run 0 does not start at the packing (step $packing_step): $(first_rows 0 | head -1)"
cmp <(first_rows 0) <(first_rows 2) || fail "the two ratios of seed 1 start from different states"
cmp <(first_rows 1) <(first_rows 3) || fail "the two ratios of seed 2 start from different states"
if cmp -s <(first_rows 0) <(first_rows 1); then fail "seeds 1 and 2 start from the same state"; fi
[[ "$(key_of "$work/ratio" 0)" == "$(key_of "$work/ratio" 2)" && "$(key_of "$work/ratio" 1)" == "$(key_of "$work/ratio" 3)" &&
   "$(key_of "$work/ratio" 0)" != "$(key_of "$work/ratio" 1)" ]] || fail "summary.csv packing keys: $(cat "$work/ratio/summary.csv")"
# A bad grid value stops the sweep before any run.
echo '{"scene": "'"$here"'/bed_quick.json", "grid": {"solver.p_gap": [0.1, -1]}}' > "$work/bad.json"
if "$bin" sweep "$work/bad.json" --out "$work/bad" 2> "$work/bad.err"; then fail "a bad grid value was accepted"; fi
grep -q "solver.p_gap" "$work/bad.err" || fail "the error does not name the field: $(cat "$work/bad.err")"
[[ ! -e "$work/bad/runs" && ! -e "$work/bad/packings" ]] || fail "a rejected sweep left run or packing folders"
echo "check_sweep_contract: 1 passed, 0 failed"
