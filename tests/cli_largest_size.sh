#!/usr/bin/env bash
# The largest face size on a device that offers Vulkan's least maxStorageBufferRange (lavapipe's
# 128 MiB): both sampling modes filter a 2048^2 probe (every level written). Hardware sampling with
# the B-spline pyramid has no buffer that grows with the size; exact sampling reads its 513.5 MiB
# bordered pyramid as a texel buffer and writes it through storage-buffer windows of whole faces,
# level 0 in six of them where the range is 128 MiB (its report's dispatches). FIS on the
# dual-paraboloid map writes its 682.7 MiB map after the bordered source, level 0 (two 4096^2
# images, 512 MiB) in windows of the range too: four on lavapipe.
set -euo pipefail
: "${PROBEFILTER:?}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$PROBEFILTER" synth sky --size 64 --out "$work/sky.exr" >/dev/null
for run in hardware exact paraboloid; do
    options=(--sampling "$run")
    [[ $run == paraboloid ]] && options=(--fis-map paraboloid)
    "$PROBEFILTER" filter "$work/sky.exr" --size 2048 --method fis --samples 8 "${options[@]}" --out "$work/$run" \
        >/dev/null 2>"$work/$run.err" || fail "2048^2, $run: exit $?: $(cat "$work/$run.err")"
    for m in $(seq 0 10); do [[ -s $work/$run/level_$m.exr ]] || fail "2048^2, $run: level_$m.exr missing"; done
done
python3 - "$work" <<'PY' || fail "2048^2: report.json"
import json, sys
for run in ("hardware", "exact", "paraboloid"):
    r = json.load(open(f"{sys.argv[1]}/{run}/report.json"))
    sampling = "exact" if run == "paraboloid" else run
    assert r["face_size"] == 2048 and r["level_count"] == 11 and r["sampling"] == sampling, r
    if sampling == "exact" and r["device"]["name"].startswith("llvmpipe"):
        # The bordered source's level 0 in six windows, then the map's level 0 in four.
        windows = [d for d in r["dispatches"] if d["pass"] == "pyramid" and d["level"] == 0 and d["workgroups"] > 1]
        expected = 6 + (4 if run == "paraboloid" else 0)
        assert len(windows) == expected, f"{run}: level 0 in {len(windows)} windows, not {expected}"
PY
echo "cli_largest_size: ok"
