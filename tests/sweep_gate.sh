#!/usr/bin/env bash
# A reduced sweep (16^2, synthetic probes, lavapipe) that fails unless the table method is ahead of
# FIS (the Pareto front of every FIS method in the sweep) at equal time on the impulse set: the table
# compared (the most accurate within FIS-32's time, else the fastest) has less error than the front
# interpolated at the table's time.
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$PROBEBENCH" sweep --size 16 --synthetic impulse-centre impulse-edge impulse-corner sunsky room \
    --samples 8 16 32 64 --fis-bias 0 1 --pyramid bspline box --repeat 3 --tables "$TABLES" --out "$work/sweep" 2>/dev/null
python3 - "$work/sweep/report.json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
r = report["impulses"]
if r is None:
    sys.exit("sweep_gate: no table for 16^2 or no FIS-32 in the sweep")
print(f"impulses: table {r['table']} ({r['table_ms']:.2f} ms; FIS-32 {r['fis32_ms']:.2f} ms): "
      f"error / the FIS front's at FIS-32's time = {r['error_at_fis32_time']:.3f}, at the table's time = {r['error_at_table_time']:.3f}")
sys.exit(0 if r["error_at_table_time"] < 1.0 else 1)
PY
