#!/usr/bin/env bash
# probefilter filter with several inputs: one batch (the probes as cube-map arrays, one recording), on
# lavapipe with the validation layer, in both sampling modes. Each input's levels, KTX2 and irradiance
# go into a folder named after it, equal file for file to that input filtered alone; one report.json
# lists the probes, and the batch takes the dispatches and barriers of one probe. Two inputs of one
# name, slices or level times with several inputs, the reference or FIS on a paraboloid map with
# several, and a bad input among good ones are refused (exit 2, the reason on stderr, nothing
# written).
set -euo pipefail
: "${PROBEFILTER:?}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

fail() { echo "FAIL: $*" >&2; exit 1; }

for name in sky room checker; do "$PROBEFILTER" synth $name --size 16 --out $name.exr >/dev/null; done
options=(--size 16 --method fis --ktx2 rgba16f --irradiance sh --validate)

for sampling in exact hardware; do
    "$PROBEFILTER" filter sky.exr room.exr checker.exr "${options[@]}" --sampling $sampling --out batch_$sampling >/dev/null 2>&1 ||
        fail "a batch of three, $sampling sampling"
    for name in sky room checker; do
        "$PROBEFILTER" filter $name.exr "${options[@]}" --sampling $sampling --out alone_${sampling}_$name >/dev/null 2>&1 ||
            fail "$name alone, $sampling sampling"
        for file in level_0.exr level_1.exr level_2.exr level_3.exr probe.ktx2 irradiance_sh.exr preview.png; do
            cmp -s batch_$sampling/$name/$file alone_${sampling}_$name/$file ||
                fail "$name/$file differs from $name filtered alone, $sampling sampling"
        done
    done
done
[[ ! -e batch_exact/level_0.exr ]] || fail "a batch wrote levels outside the probes' folders"
for sampling in exact hardware; do
python3 - batch_$sampling/report.json alone_${sampling}_sky/report.json <<'PY' || fail "batch report.json, $sampling sampling"
import json, sys
batch, alone = (json.load(open(p)) for p in sys.argv[1:])
assert batch["command"] == "filter", batch["command"]
assert [(p["input"], p["folder"]) for p in batch["probes"]] == [("sky.exr", "sky/"), ("room.exr", "room/"), ("checker.exr", "checker/")]
assert all(p["ktx2"]["file"] == p["folder"] + "probe.ktx2" for p in batch["probes"]), batch["probes"]
assert all(p["irradiance"]["sh"]["file"] == p["folder"] + "irradiance_sh.exr" for p in batch["probes"]), batch["probes"]
b = batch["batch"]
assert b["probes"] == 3 and b["dispatches"] == len(batch["dispatches"]) == len(alone["dispatches"]), (b, len(alone["dispatches"]))
assert b["barriers"] == alone["barriers"], (b, alone["barriers"])
assert [(d["pass"], d["level"]) for d in batch["dispatches"]] == [(d["pass"], d["level"]) for d in alone["dispatches"]], batch["dispatches"]
assert [p["name"] for p in batch["passes"]] == [p["name"] for p in alone["passes"]], batch["passes"]
assert all(p["gpu_ms_median"] > 0 for p in batch["passes"]), batch["passes"]
PY
done

refused() { # refused NAME EXPECTED-STDERR ARGS...: exit 2, the reason on stderr, no output folder
    local name="$1" expected="$2"
    shift 2
    local status=0
    "$PROBEFILTER" filter "$@" --out refused_$name >/dev/null 2>$name.err || status=$?
    [[ $status == 2 ]] || fail "$name: exit $status, not 2"
    grep -q -- "$expected" $name.err || fail "$name: stderr does not say '$expected': $(cat $name.err)"
    [[ ! -e refused_$name ]] || fail "$name: wrote refused_$name"
}
mkdir other && cp sky.exr other/sky.exr
refused same_name "same name" sky.exr other/sky.exr --size 16
refused slices "take one input" sky.exr room.exr --size 16 --slices 2
refused level_times "take one input" sky.exr room.exr --size 16 --level-times
refused reference "one probe at a time: give one input" sky.exr room.exr --size 16 --method reference
refused paraboloid "one probe at a time: give one input" sky.exr room.exr --size 16 --method fis --fis-map paraboloid
head -c 100 sky.exr > broken.exr
refused bad_input "broken.exr" sky.exr broken.exr --size 16
echo "cli_batch: ok"
