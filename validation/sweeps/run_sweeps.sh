#!/usr/bin/env bash
# Runs the canonical angle and ratio sweeps of one tier and checks the paper's trends
# on them (scripts/trends). Used by CTest (quick tier) and by scripts/validate --tier.
#   run_sweeps.sh RATCHET_BIN TIER SWEEP_OUT_DIR REPORT_DIR [mpirun args...]
# Trend checks go to $RATCHET_CHECKS_DIR when set (the validation report), figures to
# REPORT_DIR/figures. Exit status: non-zero if a sweep or a trend check failed.
set -euo pipefail
bin="$1"; tier="$2"; sweep_out="$3"; report_dir="$4"; shift 4
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
launcher=()
[[ $# -gt 0 ]] && launcher=("$@")
for kind in angle ratio; do
  "${launcher[@]}" "$bin" sweep "$here/${kind}_${tier}.json" --out "$sweep_out/$kind"
done
exec /usr/bin/python3 "$root/scripts/trends" "$sweep_out/angle" "$sweep_out/ratio" --tier "$tier" --out "$report_dir"
