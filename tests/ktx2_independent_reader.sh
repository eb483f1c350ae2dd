#!/usr/bin/env bash
# KTX2 written by probefilter, read by the independent parser ktx-parse (installed here with npm).
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source "$(dirname "$0")/ktx_parse.sh"
"$PROBEFILTER" synth sunsky --size 16 --out "$work/sunsky.exr" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 16 --ktx2 rgba16f --out "$work/half" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 16 --ktx2 rgba32f --out "$work/float" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 16 --ktx2 rgb9e5 --out "$work/e5" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 16 --ktx2 rgba16f --ktx2-zstd --out "$work/zstd" >/dev/null
KTX_PARSE_DIR="$node_dir" node "$(dirname "$0")/ktx2_check.mjs" "$work/half/probe.ktx2" "$work/float/probe.ktx2" "$work/e5/probe.ktx2" \
    "$work/zstd/probe.ktx2" "$work/half/report.json"
