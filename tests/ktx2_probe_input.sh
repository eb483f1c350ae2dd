#!/usr/bin/env bash
# KTX2 probes in: files written by the independent writer ktx-parse in every float format probefilter
# reads (tests/ktx2_write_probes.mjs) filter as the RGBA32F files of their decoded values; a 2D image
# stored bottom to top as the same image top to bottom; a cube as its faces in a 2D 1:6 column; and
# probefilter's own RGBA32F KTX2 (Zstandard supercompressed), read back, as the probe it holds.
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source "$(dirname "$0")/ktx_parse.sh"
KTX_PARSE_DIR="$node_dir" node "$(dirname "$0")/ktx2_write_probes.mjs" "$work"

reference() { "$PROBEFILTER" reference "$1" --size 8 --out "$2" >/dev/null; }
# The same levels, file for file.
same_levels() {
    local count=0
    for level in "$1"/level_*.exr; do
        cmp -s "$level" "$2/$(basename "$level")" || { echo "FAIL $3: $(basename "$level") differs" >&2; exit 1; }
        count=$((count + 1))
    done
    (( count > 1 )) || { echo "FAIL $3: $count level files" >&2; exit 1; }
}

for format in rgba16f rgb16f rgb32f b10g11r11 e5b9g9r9; do
    reference "$work/cube_$format.ktx2" "$work/out_$format"
    reference "$work/cube_${format}_expected.ktx2" "$work/out_${format}_expected"
    same_levels "$work/out_$format" "$work/out_${format}_expected" "$format cube"
done
reference "$work/column.ktx2" "$work/out_column"
same_levels "$work/out_column" "$work/out_rgba16f" "2D 1:6 column against the cube"
reference "$work/equirect_up.ktx2" "$work/out_up"
reference "$work/equirect_up_expected.ktx2" "$work/out_up_expected"
same_levels "$work/out_up" "$work/out_up_expected" "KTXorientation ru"

# The level-0 probe of probefilter's own KTX2, filtered again, gives the same levels.
"$PROBEFILTER" synth sunsky --size 8 --out "$work/sunsky.exr" >/dev/null
"$PROBEFILTER" reference "$work/sunsky.exr" --size 8 --ktx2 rgba32f --ktx2-zstd --out "$work/first" >/dev/null
reference "$work/first/probe.ktx2" "$work/again"
same_levels "$work/again" "$work/first" "probefilter's KTX2 read back"
grep -q '"layout": "face column"' "$work/again/report.json" || { echo "FAIL the report does not name the face column" >&2; exit 1; }
echo "ktx2_probe_input: 5 formats, the 1:6 column, KTXorientation and probefilter's own KTX2 read as their probes"
