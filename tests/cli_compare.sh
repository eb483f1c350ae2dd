#!/usr/bin/env bash
# probebench compare on lavapipe with the validation layer, at 16^2: the sheet has a row of spheres
# per method (reference, table, FIS) with heat maps; the report has the image L1 per level (0 at the
# mirror level), the spheres' L1 and the GPU times.
set -euo pipefail
: "${PROBEFILTER:?}" "${PROBEBENCH:?}"
fixtures="$(cd "$(dirname "$0")" && pwd)/fixtures"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$PROBEFILTER" synth sunsky --size 16 --out sky.exr >/dev/null
"$PROBEBENCH" compare sky.exr --size 16 --table "$fixtures/table_16_quad4_gltf.json" --roughness 0.3,0.6,1 --cell 40 \
    --repeat 1 --validate --out cmp >/dev/null 2>err.txt || fail "compare: $(cat err.txt)"
python3 - cmp <<'PY' || fail "report or sheet"
import json, struct, sys
r = json.load(open(sys.argv[1] + "/report.json"))
assert r["command"] == "compare" and r["report_version"] == 2 and r["date"], r["command"]
assert r["command_line"].startswith("probebench compare sky.exr --size 16 --table "), r["command_line"]
for method in ("table", "fis"):
    e = r[method]["image_l1_per_level"]
    assert len(e) == 4 and e[0] == 0 and all(0 < x < 1 for x in e[1:]), (method, e)
    assert 0 < r[method]["spheres_l1"] < 1 and r[method]["gpu_ms_median"] > 0, r[method]
assert [s["roughness"] for s in r["sheet"]["spheres"]] == [0.3, 0.6, 1.0], r["sheet"]
png = open(sys.argv[1] + "/sheet.png", "rb").read()
width, height = struct.unpack(">II", png[16:24])
assert png[:8] == b"\x89PNG\r\n\x1a\n" and width == 2 * 3 * 40 + 6 and height == 3 * (40 + 26), (width, height)
PY
# --table also takes a compiled-in table's name; a table that does not fit is refused (exit 2, one line,
# nothing written).
"$PROBEBENCH" compare sky.exr --size 16 --table gltf16_quad8 --roughness 0.5 --cell 16 --repeat 1 --out named >/dev/null 2>err.txt ||
    fail "compare --table NAME: $(cat err.txt)"
[[ -f named/sheet.png ]] || fail "compare --table NAME: no sheet"
set +e
"$PROBEBENCH" compare sky.exr --size 16 --table gltf128_quad8 --out wrong >/dev/null 2>err.txt
code=$?
set -e
[[ $code -eq 2 && $(wc -l <err.txt) -eq 1 && ! -e wrong ]] && grep -q "face size 128, not 16" err.txt ||
    fail "compare with a table of another size: exit $code: $(cat err.txt)"
echo "cli_compare: ok"
