#!/usr/bin/env bash
# probebench sweep --lobe charlie at 16^2: every method against the exact Charlie reference at every
# level (none is a copy); the Charlie table beside FIS for Charlie and the stand-in engines use (a GGX
# table's levels), which misses the ring: its impulse L1 is above the Charlie table's. Another lobe
# name is refused with exit 2 and one line, before anything is written.
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/tables"
cp "$FIXTURES/table_16_quad4_gltf_charlie.json" "$TABLES/gltf16_quad8.json" "$work/tables/"
"$PROBEBENCH" sweep --size 16 --lobe charlie --synthetic impulse-centre impulse-edge sunsky room \
    --samples 8 32 --fis-mix 8 --fis-bias 0 --pyramid bspline --repeat 1 --tables "$work/tables" --out "$work/sweep" 2>/dev/null
python3 - "$work/sweep/report.json" "$work/sweep/sweep.csv" "$work/sweep/sweep.md" <<'PY'
import csv, json, sys
report = json.load(open(sys.argv[1]))
assert report["lobe"] == "charlie" and report["first_level"] == 0, (report["lobe"], report["first_level"])
methods = {m["method"]: m for m in report["methods"]}
families = sorted({m["family"] for m in methods.values()})
assert families == ["fis", "fis-mix", "ggx-levels", "table"], families
table, stand_in = methods["table_16_quad4_gltf_charlie"], methods["ggx-levels-gltf16_quad8"]
assert stand_in["impulse_l1"] > 1.5 * table["impulse_l1"], (stand_in["impulse_l1"], table["impulse_l1"])
# The FIS front holds FIS alone.
assert all(methods[p["method"]]["family"].startswith("fis") for p in report["fis_front_impulses"])
levels = {int(r["level"]) for r in csv.DictReader(open(sys.argv[2]))}
assert levels == {0, 1, 2, 3}, levels
assert "charlie lobe" in open(sys.argv[3]).read()
print(f"charlie sweep: impulse L1 table {table['impulse_l1']:.4f}, ggx levels {stand_in['impulse_l1']:.4f}")
PY
set +e
message=$(timeout 60 "$PROBEBENCH" sweep --size 16 --lobe sheen --tables "$work/tables" --out "$work/refused" 2>&1)
status=$?
set -e
[[ $status == 2 ]] || { echo "sweep --lobe sheen: exit $status, expected 2"; exit 1; }
[[ $(wc -l <<<"$message") == 1 && $message == *"--lobe sheen"* ]] || { echo "sweep --lobe sheen: message '$message'"; exit 1; }
[[ ! -e $work/refused ]] || { echo "sweep --lobe sheen wrote $work/refused"; exit 1; }
