#!/usr/bin/env bash
# A reduced sweep (16^2, synthetic probes, lavapipe) that fails unless the table method is ahead of
# FIS-32 (at its best setting) at equal time on the impulse set.
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$PROBEFILTER" sweep --size 16 --synthetic impulse-centre impulse-edge impulse-corner sunsky room \
    --samples 8 16 32 64 --bias 0 1 --pyramid bspline box --repeat 3 --out "$work/sweep" 2>/dev/null
python3 - "$work/sweep/report.json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
r = report["impulses_best_fis"]
if r is None:
    sys.exit("sweep_gate: no table for 16^2 or no FIS-32 in the sweep")
print(f"impulses: table {r['table']} error / FIS-32 ({r['fis_setting']}) error at FIS-32's time = {r['error_at_fis32_time']:.3f}")
sys.exit(0 if r["error_at_fis32_time"] < 1.0 else 1)
PY
