#!/usr/bin/env bash
# The largest face size on a device that offers Vulkan's least maxStorageBufferRange (lavapipe's
# 128 MiB): hardware sampling with the B-spline pyramid has no buffer that grows with the size and
# filters a 2048^2 probe (every level written, finite); exact sampling's bordered pyramid needs 513.5
# MiB and is refused up front (exit 2, the reason on stderr, nothing written). A device with a larger
# range runs both, and the test says so.
set -euo pipefail
: "${PROBEFILTER:?}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$PROBEFILTER" synth sky --size 64 --out "$work/sky.exr" >/dev/null
"$PROBEFILTER" filter "$work/sky.exr" --size 2048 --method fis --sampling hardware --out "$work/hardware" >/dev/null 2>&1 ||
    fail "2048^2 with hardware sampling: exit $?"
for m in $(seq 0 10); do [[ -s $work/hardware/level_$m.exr ]] || fail "2048^2: level_$m.exr missing"; done
python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); assert r["face_size"] == 2048 and r["level_count"] == 11, r' \
    "$work/hardware/report.json" || fail "2048^2: report.json"
status=0
"$PROBEFILTER" filter "$work/sky.exr" --size 2048 --method fis --sampling exact --out "$work/exact" >/dev/null 2>"$work/exact.err" ||
    status=$?
if [[ $status == 0 ]]; then
    echo "cli_largest_size: this device's maxStorageBufferRange holds exact sampling's 2048^2 pyramid too"
else
    [[ $status == 2 ]] || fail "2048^2 with exact sampling: exit $status, not 2"
    grep -q "maxStorageBufferRange" "$work/exact.err" || fail "exact sampling refused without naming the limit: $(cat "$work/exact.err")"
    [[ ! -e $work/exact ]] || fail "a refused run wrote its output folder"
fi
echo "cli_largest_size: ok"
