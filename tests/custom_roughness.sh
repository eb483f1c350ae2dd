#!/usr/bin/env bash
# A user's own roughness per level (--roughness) end to end: probefit fits a table for the list and
# records it; probefilter filters with that table, FIS and the reference at the list's roughness
# (the table within 0.2 image L1 of the reference, which uses the list too); a scene takes the list;
# a table for another mapping and lists that are not a roughness per level are refused (exit 2, one
# line naming --roughness, nothing written).
set -euo pipefail
: "${PROBEFIT:?}" "${PROBEFILTER:?}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

fail() { echo "FAIL: $*" >&2; exit 1; }
list=0,0.2,0.45,1

"$PROBEFILTER" synth sky --size 16 --out sky.exr >/dev/null
"$PROBEFIT" fit --size 16 --taps 4 --form quad --roughness $list --iterations 30 --out custom >fit.log || fail "fit: $(tail -3 fit.log)"
python3 - custom.json <<'PY' || fail "the fitted table does not record the list"
import json, sys
t = json.load(open(sys.argv[1]))
assert t["mapping"] == "custom" and t["roughness"] == [0, 0.2, 0.45, 1] and t["levelCount"] == 4, (t["mapping"], t.get("roughness"))
assert [round(l["alpha"], 12) for l in t["levels"]] == [0, 0.04, 0.2025, 1], [l["alpha"] for l in t["levels"]]
assert all(l["all"]["mean"] < 0.2 for l in t["levels"][1:]), [l["all"]["mean"] for l in t["levels"]]
PY
grep -q 'kLevelRoughness\[4\] = {0, 0.2, 0.45, 1}' custom.h || fail "the header lacks the list: $(grep kLevel custom.h)"
"$PROBEFIT" eval custom.json --texels all --check 1e-3 >eval.log || fail "eval does not reproduce the records: $(cat eval.log)"

"$PROBEFILTER" filter sky.exr --method table --table custom.json --size 16 --roughness $list --against-reference --out table \
    >/dev/null 2>err.txt || fail "filter with the custom table: $(cat err.txt)"
"$PROBEFILTER" filter sky.exr --method fis --size 16 --roughness $list --against-reference --out fis >/dev/null 2>err.txt ||
    fail "fis: $(cat err.txt)"
"$PROBEFILTER" reference sky.exr --size 16 --roughness 0,0.5,1 --out reference >/dev/null 2>err.txt || fail "reference: $(cat err.txt)"
python3 - <<'PY' || fail "reports"
import json
for name in ["table", "fis"]:
    r = json.load(open(f"{name}/report.json"))
    assert r["mapping"] == "custom 0,0.2,0.45,1" and r["level_count"] == 4, (name, r["mapping"])
    assert [l["roughness"] for l in r["levels"]] == [0, 0.2, 0.45, 1], (name, r["levels"])
    errors = [e["image_l1"] for e in r["errors_against_reference"]]
    assert errors[0] == 0 and all(0 < e < 0.2 for e in errors[1:]), (name, errors)
r = json.load(open("reference/report.json"))
assert [l["roughness"] for l in r["levels"]] == [0, 0.5, 1] and len(r["levels"]) == 3, r["levels"]
PY

cat >scene.json <<'JSON'
{"probes": [{"name": "sky", "image": "sky.exr", "face_size": 16, "method": "fis", "roughness": [0, 0.3, 1]}],
 "materials": [{"name": "satin", "roughness": 0.3, "metallic": 1}]}
JSON
"$PROBEFILTER" run scene.json --out run >/dev/null 2>err.txt || fail "scene with a roughness list: $(cat err.txt)"
[[ -f run/sky/level_1.exr && ! -f run/sky/level_2.exr ]] || fail "the scene's run did not compute exactly level 1: $(ls run/sky)"

refused() { # program, expected text, args...
    local program=$1 text=$2
    shift 2
    "$program" "$@" >/dev/null 2>err.txt && fail "accepted: $*"
    local code=$?
    [[ $code -eq 2 ]] || fail "exit $code for: $*"
    [[ $(wc -l <err.txt) -eq 1 ]] && grep -qF -- "$text" err.txt || fail "message for $*: $(cat err.txt)"
    [[ ! -e out && ! -e out.json ]] || fail "output written for: $*"
}
refused "$PROBEFILTER" "roughness mapping" filter sky.exr --method table --table custom.json --size 16 --out out
refused "$PROBEFILTER" "roughness mapping" filter sky.exr --method table --table custom.json --size 16 --roughness 0,0.2,0.5,1 --out out
refused "$PROBEFILTER" "--roughness" filter sky.exr --method fis --size 16 --roughness 0,0.5,1 --levels 4 --out out
refused "$PROBEFILTER" "--roughness" filter sky.exr --method fis --size 16 --roughness 0,1.5 --out out
refused "$PROBEFILTER" "--roughness" filter sky.exr --method fis --size 16 --roughness 0,0.5,0.4 --out out
refused "$PROBEFILTER" "--roughness" reference sky.exr --size 16 --roughness 0,,1 --out out
refused "$PROBEFILTER" "--roughness" reference sky.exr --size 4 --roughness 0,0.2,0.5,1 --out out
refused "$PROBEFILTER" "--mapping or --roughness" filter sky.exr --method fis --size 16 --mapping gltf --roughness 0,1 --out out
refused "$PROBEFIT" "--roughness" fit --size 16 --taps 4 --form quad --roughness 0,0.5,1 --levels 4 --out out
refused "$PROBEFIT" "--roughness" fit --size 16 --taps 4 --form quad --roughness 0,nan --out out
refused "$PROBEFIT" "--roughness" fit --size 4 --taps 4 --form quad --roughness 0,0.2,0.5,1 --out out
refused "$PROBEFIT" "--roughness" fit --size 16 --taps 4 --form quad --mapping unity --roughness 0,1 --out out
echo "custom roughness: ok"
