#!/usr/bin/env bash
# probefilter filter on lavapipe with the validation layer: the three methods write every level and a
# report naming the device, the dispatches, GPU times (per level with --level-times) and errors; a table
# file and the same table in the published text layout give the same output; the mappings' compiled-in
# tables at 128^2 filter; a pyramid format asked for is used; a table that does not fit, a missing
# table, an unknown device and a format that does not apply are refused (exit 2, reason on stderr,
# nothing written).
set -euo pipefail
: "${PROBEFILTER:?}"
fixtures="$(cd "$(dirname "$0")" && pwd)/fixtures"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

fail() { echo "FAIL: $*" >&2; exit 1; }

"$PROBEFILTER" synth sky --size 16 --out sky.exr >/dev/null

"$PROBEFILTER" filter sky.exr --method table --table "$fixtures/table_16_quad4_gltf.json" --size 16 --repeat 3 --level-times \
    --against-reference --validate --out table >/dev/null 2>&1 || fail "table method"
for m in 0 1 2 3; do [[ -f table/level_$m.exr ]] || fail "table: level_$m.exr missing"; done
python3 - table/report.json <<'PY' || fail "table: report.json"
import json, re, sys
r = json.load(open(sys.argv[1]))
assert r["command"] == "filter" and r["report_version"] == 2, r["command"]
assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", r["date"]), r["date"]
assert r["command_line"].startswith("probefilter filter sky.exr --method table --table ") and "--level-times" in r["command_line"], r
assert r["method"] == "table" and r["device"]["name"] and r["device"]["driver"], r["device"]
assert [p["name"] for p in r["passes"]] == ["pyramid", "table", "total"], r["passes"]
assert all(len(p["gpu_ms_runs"]) == 3 and p["gpu_ms_median"] > 0 for p in r["passes"]), r["passes"]
assert all(l["gpu_ms_median"] >= 0 for l in r["levels"]) and len(r["levels"]) == 4, r["levels"]
# Exact sampling at 16^2: level 0 with its corners, then levels 1 to 4 (8^2 and smaller) in one dispatch.
expected = [("pyramid", 0), ("pyramid", 1)] + [("table", m) for m in range(4)]
assert [(d["pass"], d["level"]) for d in r["dispatches"]] == expected, r["dispatches"]
# A barrier before the run, one before each pyramid dispatch that reads the one before it, one
# between the passes; pass 2's levels run with none between them.
assert r["barriers"] == 1 + (len([d for d in r["dispatches"] if d["pass"] == "pyramid"]) - 1) + 1, r["barriers"]
errors = r["errors_against_reference"]
assert len(errors) == 4 and errors[0]["image_l1"] == 0 and all(0 < e["image_l1"] < 0.2 for e in errors[1:]), errors
PY

"$PROBEFILTER" filter sky.exr --method table --table "$fixtures/table_16_quad4_gltf.txt" --table-taps 4 --table-form quad \
    --size 16 --validate --out published >/dev/null 2>&1 || fail "published layout"
for m in 0 1 2 3; do cmp -s table/level_$m.exr published/level_$m.exr || fail "published layout differs at level $m"; done
# A table file of format version 1 (the face size named "baseSize") filters alike, with one note.
sed -e 's/"faceSize":/"baseSize":/' -e 's/"version": 2/"version": 1/' "$fixtures/table_16_quad4_gltf.json" > version1.json
"$PROBEFILTER" filter sky.exr --method table --table version1.json --size 16 --out version1 >/dev/null 2>version1.err \
    || fail "version 1 table"
for m in 0 1 2 3; do cmp -s table/level_$m.exr version1/level_$m.exr || fail "version 1 table differs at level $m"; done
[[ $(grep -c 'version1.json: table format version 1; version 2 names "baseSize" "faceSize"' version1.err) == 1 ]] \
    || fail "version 1 table: no note naming the new field: $(cat version1.err)"
# Without --level-times: pass times only.
python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); assert not any("gpu_ms_median" in l for l in r["levels"]), r["levels"]' \
    published/report.json || fail "levels timed without --level-times"

# Without --table, the compiled-in table for the settings (tables/*.json), quad 8 taps preferred.
if [[ -f "$fixtures/../../tables/gltf16_quad8.json" ]]; then
    "$PROBEFILTER" filter sky.exr --method table --size 16 --validate --out compiled >/dev/null 2>&1 || fail "compiled-in table"
    python3 -c "import json,sys; t=json.load(open('compiled/report.json'))['table']
sys.exit(not (t['taps_per_frame'] == 8 and t['form'] == 'quad'))" \
        || fail "compiled-in table: not the quad 8 table"
fi

# The compiled-in table of each mapping at 128^2 (tables/*_quad8.h) filters.
"$PROBEFILTER" synth sky --size 128 --out sky128.exr >/dev/null
for mapping in gltf authors filament unity; do
    "$PROBEFILTER" filter sky128.exr --method table --size 128 --mapping $mapping --out table128_$mapping >/dev/null 2>&1 ||
        fail "compiled-in table for the $mapping mapping at 128^2"
    python3 -c "import json,sys; t=json.load(open('table128_$mapping/report.json'))['table']
sys.exit(not (t['mapping'] == '$mapping' and t['face_size'] == 128 and t['taps_per_frame'] == 8 and t['form'] == 'quad'))" ||
        fail "compiled-in table for the $mapping mapping: not the quad 8 table at 128^2"
    [[ -f table128_$mapping/level_6.exr ]] || fail "$mapping: level_6.exr missing"
done

for method in fis reference; do
    "$PROBEFILTER" filter sky.exr --method $method --samples 64 --size 16 --validate --out $method >/dev/null 2>&1 || fail "$method"
    [[ -f $method/level_3.exr && -f $method/report.json ]] || fail "$method: output missing"
done

refused() { # expected stderr fragment, then the arguments
    local expect="$1"; shift
    local rc=0
    "$PROBEFILTER" filter sky.exr "$@" --out refused 2>err.txt >/dev/null || rc=$?
    [[ $rc == 2 ]] || fail "$* exited $rc, expected 2"
    grep -q -- "$expect" err.txt || fail "$*: stderr lacks '$expect': $(cat err.txt)"
    [[ ! -e refused ]] || fail "$*: wrote output"
}
refused "it is for face size 16, not 32" --method table --table "$fixtures/table_16_quad4_gltf.json" --size 32
refused "for the gltf roughness mapping, not authors" \
    --method table --table "$fixtures/table_16_quad4_gltf.json" --size 16 --mapping authors
refused "fitted over the bspline solid-angle pyramid, not box" \
    --method table --table "$fixtures/table_16_quad4_gltf.json" --size 16 --pyramid box
refused "make one with \`probefit fit --size 16 --levels 3" --method table --size 16 --levels 3
refused "needs --table-taps" --method table --table "$fixtures/table_16_quad4_gltf.txt" --size 16
refused "no Vulkan device of that name" --method fis --device no-such-device --size 16
refused "--samples 0" --method fis --samples 0 --size 16
refused "--format rgb8" --method fis --format rgb8 --size 16
refused "--sampling fast" --method fis --sampling fast --size 16
refused "one count, or one per output level (4)" --method fis --samples 8 16 --size 16
refused "--fis-map sphere" --method fis --fis-map sphere --size 16
refused "reads it exactly" --method fis --fis-map paraboloid --sampling hardware --size 16
refused "--pyramid-format b10g11r11" --method fis --sampling hardware --pyramid-format b10g11r11 --size 16
refused "--pyramid-format rgba16f: only hardware sampling" --method fis --sampling exact --pyramid-format rgba16f --size 16
refused "--pyramid-format rgb9e5: only hardware sampling" --method fis --sampling exact --pyramid-format rgb9e5 --size 16
refused "--irradiance lambert: expected none, sh, cube or both" --irradiance lambert --size 16

# --slices 3: the update as pass 1 and two groups of levels, one submission each; the same levels
# as one run, and each slice's dispatches, texel-taps and GPU time in the report.
"$PROBEFILTER" filter sky.exr --method table --table "$fixtures/table_16_quad4_gltf.json" --size 16 --slices 3 --out sliced \
    >/dev/null 2>&1 || fail "--slices 3"
for m in 0 1 2 3; do cmp -s table/level_$m.exr sliced/level_$m.exr || fail "--slices 3: level $m differs from one run"; done
python3 - sliced/report.json <<'PY' || fail "--slices 3: report"
import json, sys
r = json.load(open(sys.argv[1]))
slices = r["slices"]
assert len(slices) == 3 and slices[0]["pyramid"] and not slices[0]["levels"], slices
assert sum((s["levels"] for s in slices), []) == [0, 1, 2, 3], slices
assert all(s["dispatches"] > 0 and s["texel_taps"] > 0 and s["gpu_ms"] > 0 for s in slices), slices
assert "passes" not in r, r.keys()
PY
refused "--slices runs each slice once" --slices 2 --repeat 3 --size 16
refused "--slices 0: must be 1 to 64" --slices 0 --size 16

# --irradiance both: the SH projection and the exact irradiance cube, and SH measured against it (on
# the smooth sky, within a few percent).
"$PROBEFILTER" filter sky.exr --size 16 --irradiance both --out irradiance >/dev/null 2>&1 || fail "--irradiance both"
python3 - irradiance <<'PY' || fail "--irradiance both: report"
import json, os, sys
folder = sys.argv[1]
r = json.load(open(os.path.join(folder, "report.json")))["irradiance"]
assert len(r["sh"]["irradiance"]) == 9 and r["sh"]["file"] == "irradiance_sh.exr", r["sh"]
assert r["cube"] == {**r["cube"], "file": "irradiance.exr", "face_size": 32, "source_face_size": 16}, r["cube"]
assert all(os.path.getsize(os.path.join(folder, f)) > 0 for f in ("irradiance.exr", "irradiance_sh.exr"))
d = r["sh_against_cube"]
assert 0 < d["relative_l1"] < 0.05 and d["relative_l1"] <= d["max_relative"], d
PY

# The pyramid format, by default and as asked for: the report names it.
for format in auto rgba32f rgb9e5; do
    "$PROBEFILTER" filter sky.exr --method table --table "$fixtures/table_16_quad4_gltf.json" --size 16 --sampling hardware \
        --pyramid-format $format --validate --out pyramid-$format >/dev/null 2>&1 || fail "--pyramid-format $format"
    expected=$format; [[ $format == auto ]] && expected=rgba16f
    python3 -c "import json,sys; sys.exit(json.load(open('pyramid-$format/report.json'))['pyramid']['format'] != '$expected')" ||
        fail "--pyramid-format $format: the report does not name $expected"
done

# Any committed table by its name, compiled in or not (tables/authors128_const4.json is not).
"$PROBEFILTER" filter sky128.exr --size 128 --mapping authors --table authors128_const4 --out named-table >/dev/null 2>err.txt ||
    fail "--table authors128_const4: $(cat err.txt)"
python3 -c "import json,sys; t=json.load(open('named-table/report.json'))['table']
sys.exit(not (t['form'] == 'const' and t['taps_per_frame'] == 4))" || fail "--table authors128_const4: another table was used"

# FIS with a count per level: the report lists them.
"$PROBEFILTER" filter sky.exr --method fis --samples 8 8 32 128 --size 16 --out fis-levels >/dev/null 2>&1 || fail "fis per level"
python3 -c "import json,sys; sys.exit(json.load(open('fis-levels/report.json'))['fis']['samples'] != [8, 8, 32, 128])" ||
    fail "fis per level: the report does not list the counts"

# FIS on a dual-paraboloid map: the report names the map.
"$PROBEFILTER" filter sky.exr --method fis --fis-map paraboloid --samples 32 --size 16 --validate --out fis-paraboloid >/dev/null 2>&1 ||
    fail "fis paraboloid"
python3 -c "import json,sys; sys.exit(json.load(open('fis-paraboloid/report.json'))['fis']['map'] != 'paraboloid')" ||
    fail "fis paraboloid: the report does not name the map"
# The Charlie lobe with a Charlie table (probefit --lobe charlie): every level filtered, the report names
# the lobe; a table of the other lobe is refused with the reason, and so is the GGX table picked by default.
charlie=$fixtures/table_16_quad4_gltf_charlie.json
"$PROBEFILTER" filter sky.exr --method table --lobe charlie --table "$charlie" --size 16 --validate --out charlie >/dev/null 2>&1 ||
    fail "charlie table"
python3 -c "import json,sys; r=json.load(open('charlie/report.json'))
sys.exit(not (r['lobe'] == 'charlie' and r['table']['lobe'] == 'charlie' and r['levels'][0]['alpha'] > 0))" ||
    fail "charlie table: the report does not name the Charlie table and lobe"
"$PROBEFILTER" filter sky.exr --method table --table "$charlie" --size 16 --out wrong-lobe >/dev/null 2>err.txt &&
    fail "a Charlie table for the GGX lobe was accepted"
grep -q "fitted for the charlie lobe" err.txt || fail "a Charlie table for the GGX lobe: $(cat err.txt)"
"$PROBEFILTER" filter sky.exr --method table --lobe charlie --size 16 --out no-table >/dev/null 2>err.txt &&
    fail "the GGX table picked for the Charlie lobe"
grep -q "no compiled-in charlie tap table" err.txt || fail "no Charlie table: $(cat err.txt)"
echo "cli_filter: ok"
