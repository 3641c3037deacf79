#!/usr/bin/env bash
# The sweep contract (issue: thermally cycled bed): the summary of a sweep is the same
# bit for bit whether it runs locally, under mpirun with 2 ranks, or is stopped and
# started again (the finished runs are skipped).
#   check_sweep_contract.sh RATCHET_BIN WORK_DIR
set -euo pipefail
bin="$1"; work="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
rm -rf "$work"; mkdir -p "$work"
cat > "$work/sweep.json" <<JSON
{"scene": "$here/bed_quick.json",
 "set": {"particles.generate.count": 12, "thermal.start_time": 4.0, "thermal.cycles": 1, "time.dt": 0.005},
 "grid": {"container.opening_angle_deg": [0, 6]}, "realizations": 2}
JSON
fail() { echo "check_sweep_contract: FAILED: $*" >&2; exit 1; }
"$bin" sweep "$work/sweep.json" --out "$work/local" --jobs 2
mpirun --allow-run-as-root --oversubscribe -n 2 "$bin" sweep "$work/sweep.json" --out "$work/mpi"
cmp "$work/local/summary.csv" "$work/mpi/summary.csv" || fail "summary under mpirun -n 2 differs from the local one"
[[ $(grep -c ',completed$' "$work/local/summary.csv") -eq 4 ]] || fail "not all 4 runs completed"
# Interrupted sweep: one run removed, one left half-written (no run.json): both rerun.
rm -rf "$work/mpi/runs/1"
rm -f "$work/mpi/runs/2/run.json"
out="$("$bin" sweep "$work/sweep.json" --out "$work/mpi" 2>&1)"
grep -q "2 of 4 runs already completed; running 2" <<<"$out" || fail "resume did not skip exactly the 2 finished runs: $out"
cmp "$work/local/summary.csv" "$work/mpi/summary.csv" || fail "summary after resume differs"
# A bad grid value stops the sweep before any run.
echo '{"scene": "'"$here"'/bed_quick.json", "grid": {"solver.p_gap": [0.1, -1]}}' > "$work/bad.json"
if "$bin" sweep "$work/bad.json" --out "$work/bad" 2> "$work/bad.err"; then fail "a bad grid value was accepted"; fi
grep -q "solver.p_gap" "$work/bad.err" || fail "the error does not name the field: $(cat "$work/bad.err")"
[[ ! -e "$work/bad/runs" ]] || fail "a rejected sweep left run folders"
echo "check_sweep_contract: 1 passed, 0 failed"
