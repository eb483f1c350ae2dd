#!/usr/bin/env bash
# probefilter run on lavapipe with the validation layer: scenes that call for the mirror level only,
# diffuse only, both, sheen, and nothing run end to end; report.json lists exactly the passes that
# `probefilter plan` prints; only the planned files are written; the levels a run computes equal,
# byte for byte, the same levels of a full `filter` run (fis, table, and Charlie fis for sheen); the
# compiled-in 128^2 Charlie table hands its level 0 to FIS, and the plan and the run say so; probes of
# the same filters run as one batch.
set -euo pipefail
: "${PROBEFILTER:?}"
fixtures="$(cd "$(dirname "$0")" && pwd)/fixtures"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

fail() { echo "FAIL: $*" >&2; exit 1; }

"$PROBEFILTER" synth sky --size 16 --out sky.exr >/dev/null

scene() { # name, method extra, materials, outputs
    cat >"$1.json" <<JSON
{"probes": [{"name": "sky", "image": "sky.exr", "face_size": 16, $2}],
 "materials": [$3], "outputs": {$4}}
JSON
}
scene mirror '"method": "fis"' '{"name": "chrome", "roughness": 0, "metallic": 1}' '"spheres": true'
scene diffuse '"method": "fis"' '{"name": "chalk", "roughness": 1, "specular": 0}' '"spheres": true'
scene mixed '"method": "fis", "samples": 32' \
    '{"name": "plastic", "roughness": 0.5}, {"name": "chrome", "roughness": 0, "metallic": 1}' '"ktx2": "rgba32f", "spheres": true'
scene table "\"method\": \"table\", \"table\": \"$fixtures/table_16_quad4_gltf.json\"" \
    '{"name": "satin", "roughness": 0.5, "metallic": 1}' ''
scene empty '"method": "fis"' '' ''
# The Lambertian cube only where asked: beside SH, or alone (no spheres, so no SH either).
scene lambert '"method": "fis"' '{"name": "chalk", "roughness": 1, "specular": 0}' '"irradiance": "both"'
scene cube '"method": "fis"' '{"name": "chalk", "roughness": 1, "specular": 0}' '"irradiance": "cube"'
# Sheen alone (no specular, black base): the Charlie levels its sheen roughness reads and the sheen table.
scene sheen '"method": "table", "table": "'"$fixtures"'/table_16_quad4_gltf.json", "samples": 16' \
    '{"name": "velvet", "roughness": 1, "specular": 0, "base_color": [0, 0, 0], "sheen_color": [1, 0.5, 0.5], "sheen_roughness": 0.5}' \
    '"ktx2": "rgba16f", "spheres": true'
# Sheen on a 128^2 table probe: gltf128_quad8_charlie filters level 1, FIS with 24 samples its level 0.
"$PROBEFILTER" synth sky --size 128 --out sky128.exr >/dev/null
cat >handoff.json <<JSON
{"probes": [{"name": "sky", "image": "sky128.exr", "face_size": 128, "method": "table"}],
 "materials": [{"name": "satin", "roughness": 1, "specular": 0, "base_color": [0, 0, 0], "sheen_color": [1, 1, 1],
                "sheen_roughness": 0.1}], "outputs": {}}
JSON

# The passes `plan` prints (the text before " because "), as JSON.
planned() {
    "$PROBEFILTER" plan "$1.json" |
        python3 -c 'import json, sys; print(json.dumps([l.split(" because ")[0].strip() for l in sys.stdin if " because " in l]))'
}

check_run() { # scene name, expected passes as a JSON list
    "$PROBEFILTER" run "$1.json" --validate --out "out-$1" >/dev/null 2>err.txt || fail "$1: run failed: $(cat err.txt)"
    planned "$1" >"plan-$1.json"
    python3 - "$1" "out-$1/report.json" "plan-$1.json" "$2" <<'PY' || fail "$1: report"
import json, os, sys
name, report, plan, expected = sys.argv[1], json.load(open(sys.argv[2])), json.load(open(sys.argv[3])), json.loads(sys.argv[4])
ran = [d["pass"] for d in report["dispatches"]]
assert ran == plan, f"{name}: ran {ran}, planned {plan}"
assert ran == expected, f"{name}: ran {ran}, expected {expected}"
for d in report["dispatches"]:
    assert (d["on"] == "gpu") == (len(d["gpu_dispatches"]) > 0), d
out = os.path.dirname(sys.argv[2])
files = sorted(os.path.relpath(os.path.join(r, f), out) for r, _, fs in os.walk(out) for f in fs)
levels = sorted(int(p.split(" ")[2]) for p in ran if ": level " in p)
sheen = sorted(int(p.split(" ")[3]) for p in ran if ": sheen level " in p)
want = ["report.json"] + [f"sky/level_{m}.exr" for m in levels] + [f"sky/sheen_level_{m}.exr" for m in sheen]
if "sky: sh-irradiance" in ran: want.append("sky/irradiance_sh.exr")
if "sky: irradiance-cube" in ran: want.append("sky/irradiance.exr")
if "dfg-table" in ran: want.append("dfg.exr")
if "sheen-table" in ran: want.append("sheen.exr")
if report.get("probes") and name in ("mirror", "diffuse", "mixed", "sheen"): want.append("sky/spheres.png")
if name == "mixed": want.append("sky/probe.ktx2")
if name == "sheen": want.append("sky/sheen.ktx2")
assert files == sorted(want), f"{name}: wrote {files}, expected {sorted(want)}"
for p in report["probes"]:
    irradiance = p.get("irradiance", {})
    assert ("sh" in irradiance) == ("sky: sh-irradiance" in ran) and ("cube" in irradiance) == ("sky: irradiance-cube" in ran), p
    assert ("sh_against_cube" in irradiance) == ("sh" in irradiance and "cube" in irradiance), irradiance
    if "sh" in irradiance:
        assert "Y2-2 = 1.092548 x y" in irradiance["sh"]["convention"] and len(irradiance["sh"]["irradiance"]) == 9, irradiance
    if "cube" in irradiance:
        assert irradiance["cube"]["face_size"] == 32 and irradiance["cube"]["file"] == "sky/irradiance.exr", irradiance
if "dfg" in report: assert "red = A, green = B" in report["dfg"]["convention"]
if "sheen_table" in report: assert "Estevez-Kulla" in report["sheen_table"]["convention"]
for p in report["probes"]:
    if "sheen" in p:
        assert [l["level"] for l in p["sheen"]["levels"]] == sheen, p["sheen"]
        if name == "handoff":
            assert p["sheen"]["method"] == "table", p["sheen"]
            assert [l["method"] for l in p["sheen"]["levels"]] == ["fis", "table"], p["sheen"]
        else:
            assert p["sheen"]["method"] == "fis" and p["sheen"]["fis_samples"] == 16, p["sheen"]
PY
}

check_run mirror '["sky: load", "sky: level 0 (fis)", "dfg-table"]'
check_run diffuse '["sky: load", "sky: sh-irradiance"]'
check_run empty '[]'
check_run lambert '["sky: load", "sky: sh-irradiance", "sky: irradiance-cube"]'
check_run cube '["sky: load", "sky: irradiance-cube"]'
# Mixed: r = 0.5 reads levels 1 and 2 (lod = 3 r at 16^2); the pyramid depth is whatever their taps read.
"$PROBEFILTER" plan mixed.json | grep -q "^sky: pyramid 0\.\." || fail "mixed: no pyramid in the plan"
mixed_pyramid=$("$PROBEFILTER" plan mixed.json | grep -o "^sky: pyramid 0\.\.[0-9]*")
check_run mixed "[\"sky: load\", \"$mixed_pyramid\", \"sky: level 0 (fis)\", \"sky: level 1 (fis)\", \"sky: level 2 (fis)\", \
\"sky: sh-irradiance\", \"dfg-table\"]"
sheen_pyramid=$("$PROBEFILTER" plan sheen.json | grep -o "^sky: sheen pyramid 0\.\.[0-9]*")
check_run sheen "[\"sky: load\", \"$sheen_pyramid\", \"sky: sheen level 1 (fis)\", \"sky: sheen level 2 (fis)\", \"sheen-table\"]"
handoff_pyramid=$("$PROBEFILTER" plan handoff.json | grep -o "^sky: sheen pyramid 0\.\.[0-9]*")
"$PROBEFILTER" plan handoff.json | grep -q "^sky: sheen level 0 (fis) .*the table hands it to FIS" ||
    fail "handoff: the plan names no hand-off"
check_run handoff "[\"sky: load\", \"$handoff_pyramid\", \"sky: sheen level 0 (fis)\", \"sky: sheen level 1 (table)\", \"sheen-table\"]"
table_pyramid=$("$PROBEFILTER" plan table.json | grep -o "^sky: pyramid 0\.\.[0-9]*")
check_run table "[\"sky: load\", \"$table_pyramid\", \"sky: level 1 (table)\", \"sky: level 2 (table)\", \"dfg-table\"]"

# The computed levels equal a full filter run's, byte for byte.
"$PROBEFILTER" filter sky.exr --method fis --samples 32 --size 16 --out full-fis >/dev/null 2>&1 || fail "filter fis"
for m in 0 1 2; do cmp -s out-mixed/sky/level_$m.exr full-fis/level_$m.exr || fail "mixed: level $m differs from the full fis run"; done
"$PROBEFILTER" filter sky.exr --method table --table "$fixtures/table_16_quad4_gltf.json" --size 16 --out full-table >/dev/null 2>&1 ||
    fail "filter table"
for m in 1 2; do cmp -s out-table/sky/level_$m.exr full-table/level_$m.exr || fail "table: level $m differs from the full table run"; done
"$PROBEFILTER" filter sky.exr --method fis --lobe charlie --samples 16 --size 16 --out full-charlie >/dev/null 2>&1 || fail "filter charlie"
for m in 1 2; do
    cmp -s out-sheen/sky/sheen_level_$m.exr full-charlie/level_$m.exr || fail "sheen: level $m differs from the full Charlie fis run"
done
# The hand-off is the table method's own: a full Charlie table run has the same levels and names them.
"$PROBEFILTER" filter sky128.exr --method table --lobe charlie --size 128 --out full-handoff >/dev/null 2>&1 || fail "filter charlie table"
for m in 0 1; do
    cmp -s out-handoff/sky/sheen_level_$m.exr full-handoff/level_$m.exr || fail "handoff: level $m differs from the full table run"
done
python3 - full-handoff/report.json <<'PY' || fail "handoff: the filter report"
import json, sys
levels = json.load(open(sys.argv[1]))["levels"]
assert [l["method"] for l in levels] == ["fis"] + ["table"] * 6 and levels[0]["fis_samples"] == 24, levels
PY
# Probes of the same filters run as one batch (one Filter, one submission): a and b here, c alone. The
# report lists every probe and pass in the scene's order, as the plan does; the batch's levels equal
# each probe's alone, byte for byte.
"$PROBEFILTER" synth sunsky --size 16 --out sunsky.exr >/dev/null
cat >batch.json <<JSON
{"probes": [{"name": "a", "image": "sky.exr", "face_size": 16, "method": "fis", "samples": 32},
            {"name": "c", "image": "sky.exr", "face_size": 16, "method": "table", "table": "$fixtures/table_16_quad4_gltf.json"},
            {"name": "b", "image": "sunsky.exr", "face_size": 16, "method": "fis", "samples": 32}],
 "materials": [{"name": "a1", "probe": "a", "roughness": 0.5}, {"name": "a2", "probe": "a", "roughness": 0, "metallic": 1},
               {"name": "b1", "probe": "b", "roughness": 0.5}, {"name": "b2", "probe": "b", "roughness": 0, "metallic": 1},
               {"name": "c1", "probe": "c", "roughness": 0.5, "metallic": 1}], "outputs": {}}
JSON
"$PROBEFILTER" run batch.json --validate --out out-batch >/dev/null 2>err.txt || fail "batch: run failed: $(cat err.txt)"
planned batch >plan-batch.json
python3 - out-batch/report.json plan-batch.json <<'PY' || fail "batch: report"
import json, sys
report, plan = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
ran = [d["pass"] for d in report["dispatches"]]
assert ran == plan, f"ran {ran}, planned {plan}"
probes = {p["name"]: p for p in report["probes"]}
assert [p["name"] for p in report["probes"]] == ["a", "c", "b"], report["probes"]
assert "batch" not in probes["c"] and probes["c"]["barriers"] > 0, probes["c"]
# The filter's dispatches (not the irradiance's); one that writes several levels is listed under each:
# counted once, under its first level.
def counted(p, d):
    return ": pyramid " in p or (" level " in p and d["level"] == int(p.split(" level ")[1].split(" ")[0]))
own = {n: sum(counted(p["pass"], d) for p in report["dispatches"] if p["pass"].startswith(n + ": ") for d in p["gpu_dispatches"])
       for n in "abc"}
# A batch's dispatches filter both of its probes: each lists them all.
for n in "ab":
    assert probes[n]["batch"]["probes"] == ["a", "b"], probes[n]
    assert probes[n]["batch"]["dispatches"] == own["a"] == own["b"] > 0, (own, probes[n]["batch"])
PY
"$PROBEFILTER" filter sunsky.exr --method fis --samples 32 --size 16 --out full-sunsky >/dev/null 2>&1 || fail "filter sunsky"
for m in 0 1 2; do
    cmp -s out-batch/a/level_$m.exr full-fis/level_$m.exr || fail "batch: a's level $m differs from the full fis run"
    cmp -s out-batch/b/level_$m.exr full-sunsky/level_$m.exr || fail "batch: b's level $m differs from the full fis run"
done
cmp -s out-batch/c/level_1.exr full-table/level_1.exr || fail "batch: c's level 1 differs from the full table run"
echo "cli_run: ok"
