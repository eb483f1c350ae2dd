#!/usr/bin/env bash
# The largest face size on a device that offers Vulkan's least maxStorageBufferRange (lavapipe's
# 128 MiB): both sampling modes filter a 2048^2 probe (every level written). Hardware sampling with
# the B-spline pyramid has no buffer that grows with the size; exact sampling reads its 513.5 MiB
# bordered pyramid as a texel buffer and writes it through storage-buffer windows of whole faces,
# level 0 in six of them where the range is 128 MiB (its report's dispatches).
set -euo pipefail
: "${PROBEFILTER:?}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$PROBEFILTER" synth sky --size 64 --out "$work/sky.exr" >/dev/null
for sampling in hardware exact; do
    "$PROBEFILTER" filter "$work/sky.exr" --size 2048 --method fis --samples 8 --sampling $sampling --out "$work/$sampling" \
        >/dev/null 2>"$work/$sampling.err" || fail "2048^2 with $sampling sampling: exit $?: $(cat "$work/$sampling.err")"
    for m in $(seq 0 10); do [[ -s $work/$sampling/level_$m.exr ]] || fail "2048^2, $sampling: level_$m.exr missing"; done
done
python3 - "$work" <<'PY' || fail "2048^2: report.json"
import json, sys
for sampling in ("hardware", "exact"):
    r = json.load(open(f"{sys.argv[1]}/{sampling}/report.json"))
    assert r["face_size"] == 2048 and r["level_count"] == 11 and r["sampling"] == sampling, r
    if sampling == "exact" and r["device"]["name"].startswith("llvmpipe"):
        windows = [d for d in r["dispatches"] if d["pass"] == "pyramid" and d["level"] == 0 and d["workgroups"] > 1]
        assert len(windows) == 6, f"level 0 in {len(windows)} windows, not 6"
PY
echo "cli_largest_size: ok"
