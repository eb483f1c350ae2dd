#!/usr/bin/env bash
# KTX2 written by probefilter, read by the independent parser ktx-parse (installed here with npm).
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
node_dir="$KTX_PARSE_PREFIX/node_modules"
if [[ ! -d $node_dir/ktx-parse ]]; then
    npm install --silent --no-audit --no-fund --prefix "$KTX_PARSE_PREFIX" ktx-parse@2.0.0 >/dev/null ||
        { echo "ktx2_independent_reader: npm install ktx-parse@2.0.0 failed (is the npm registry reachable?)" >&2; exit 1; }
fi
"$PROBEFILTER" synth sunsky --size 16 --out "$work/sunsky.exr" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 16 --ktx2 rgba16f --out "$work/half" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 16 --ktx2 rgba32f --out "$work/float" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 16 --ktx2 rgb9e5 --out "$work/e5" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 16 --ktx2 rgba16f --ktx2-zstd --out "$work/zstd" >/dev/null
KTX_PARSE_DIR="$node_dir" node "$(dirname "$0")/ktx2_check.mjs" "$work/half/probe.ktx2" "$work/float/probe.ktx2" "$work/e5/probe.ktx2" \
    "$work/zstd/probe.ktx2" "$work/half/report.json"
