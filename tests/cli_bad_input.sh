#!/usr/bin/env bash
# Bad input to `probefilter reference` and bad scenes for `probefilter run`: exit code 2, a one-line
# error naming the file or option (and the scene's field), and no output (neither the folder nor a
# staging folder beside it).
set -u
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$MAKE_BAD_PROBES" "$work/in" || exit 1
touch "$work/a-file"
failures=0

# The bench's commands are probebench's, the rest probefilter's.
tool_for() { case $1 in compare | sweep) echo "$PROBEBENCH" ;; *) echo "$PROBEFILTER" ;; esac; }
expect_refused() { # name, expected text in the message, args...
    local name=$1 text=$2
    shift 2
    local out="$work/out"
    "$(tool_for "$1")" "$@" 2>"$work/stderr" >/dev/null
    local code=$?
    local lines
    lines=$(wc -l <"$work/stderr")
    if [[ $code -ne 2 ]]; then echo "FAIL $name: exit code $code, expected 2"; failures=$((failures + 1)); fi
    if [[ $lines -ne 1 ]]; then echo "FAIL $name: $lines lines on stderr, expected 1"; cat "$work/stderr"; failures=$((failures + 1)); fi
    if ! grep -qF -- "$text" "$work/stderr"; then
        echo "FAIL $name: message lacks '$text': $(cat "$work/stderr")"
        failures=$((failures + 1))
    fi
    if [[ -e $out ]] || compgen -G "$work/.probefilter-*" >/dev/null; then echo "FAIL $name: output written"; failures=$((failures + 1)); fi
    rm -rf "$out"
    echo "ok $name: $(cat "$work/stderr")"
}

in=$work/in
ref() { echo reference "$@" --size 8 --out "$work/out"; }
expect_refused missing-file   "$in/nope.exr"      $(ref "$in/nope.exr")
expect_refused empty-file     "$in/empty.exr"     $(ref "$in/empty.exr")
expect_refused not-an-image   "$in/garbage.exr"   $(ref "$in/garbage.exr")
expect_refused truncated-exr  "$in/truncated.exr" $(ref "$in/truncated.exr")
expect_refused aspect-ratio   "$in/aspect.exr"    $(ref "$in/aspect.exr")
expect_refused nan-pixel      "x=17 y=3"          $(ref "$in/nan.exr")
expect_refused inf-pixel      "$in/inf.exr"       $(ref "$in/inf.exr")
expect_refused unknown-mapping "bogus"            reference "$in/good.exr" --size 8 --mapping bogus --out "$work/out"
expect_refused size-not-pow2  "face size 12"      reference "$in/good.exr" --size 12 --out "$work/out"
expect_refused size-zero      "face size 0"       reference "$in/good.exr" --size 0 --out "$work/out"
expect_refused too-many-levels "level count 5"    reference "$in/good.exr" --size 8 --levels 5 --out "$work/out"
expect_refused zero-levels    "level count 0"     reference "$in/good.exr" --size 8 --levels 0 --out "$work/out"
expect_refused unwritable-out "$work/a-file/out"  reference "$in/good.exr" --size 8 --out "$work/a-file/out"
# Empty values are refused, not taken as the defaults.
expect_refused empty-levels   "--levels"          reference "$in/good.exr" --size 8 --levels '' --out "$work/out"
expect_refused empty-input    "input"             reference '' --size 8 --out "$work/out"
expect_refused empty-out      "--out"             reference "$in/good.exr" --size 8 --out ''
expect_refused filter-zero-levels "level count 0" filter "$in/good.exr" --method fis --size 8 --levels 0 --out "$work/out"
expect_refused filter-empty-bias "--fis-bias"     filter "$in/good.exr" --method fis --size 8 --fis-bias '' --out "$work/out"
expect_refused filter-empty-roughness "--roughness" filter "$in/good.exr" --method fis --size 8 --roughness '' --out "$work/out"

# Bad scenes for `run`: the message names the scene file and the field.
bad_scene() { # name, probe fields, materials
    printf '{"probes": [{"name": "sky", %s}], "materials": [%s]}' "$2" "$3" >"$work/$1.json"
}
bad_scene missing-image '"image": "in/nope.exr"' ''
bad_scene unknown-field '"image": "in/good.exr"' '{"name": "a", "roughness": 0.5, "shininess": 3}'
bad_scene roughness-range '"image": "in/good.exr"' '{"name": "a", "roughness": 1.5}'
bad_scene duplicate-material '"image": "in/good.exr"' '{"name": "a", "roughness": 0.5}, {"name": "a", "roughness": 0.2}'
run() { echo run "$work/$1.json" --out "$work/out"; }
expect_refused scene-missing-image      "$work/missing-image.json: probes[0].image"              $(run missing-image)
expect_refused scene-unknown-field      "$work/unknown-field.json: materials[0].shininess"       $(run unknown-field)
expect_refused scene-roughness-range    "$work/roughness-range.json: materials[0].roughness"     $(run roughness-range)
expect_refused scene-duplicate-material "$work/duplicate-material.json: materials[1].name"       $(run duplicate-material)
expect_refused scene-missing-file       "$work/nope.json"                                        $(run nope)
# The format's version and the outputs' irradiance are checked like any field.
printf '{"version": 2, "probes": [{"name": "sky", "image": "in/good.exr"}], "materials": []}' >"$work/scene-version.json"
printf '{"probes": [{"name": "sky", "image": "in/good.exr"}], "materials": [], "outputs": {"irradiance": "lambert"}}' \
    >"$work/scene-irradiance.json"
expect_refused scene-version            "$work/scene-version.json: version"                      $(run scene-version)
expect_refused scene-irradiance         "$work/scene-irradiance.json: outputs.irradiance"        $(run scene-irradiance)
# A table file of a format version this build does not read.
sed 's/"version": 2/"version": 3/' "$(dirname "$0")/fixtures/table_16_quad4_gltf.json" >"$work/table-version3.json"
expect_refused table-version "$work/table-version3.json: table format version 3" \
    filter "$in/good.exr" --method table --table "$work/table-version3.json" --size 16 --out "$work/out"
expect_refused filter-irradiance "--irradiance lambert" filter "$in/good.exr" --size 8 --irradiance lambert --out "$work/out"
expect_refused filter-slices "--slices 0" filter "$in/good.exr" --size 8 --slices 0 --out "$work/out"
expect_refused ktx2-format "--ktx2: unknown format 'bc7'" reference "$in/good.exr" --size 8 --ktx2 bc7 --out "$work/out"
expect_refused ktx2-zstd-alone "--ktx2-zstd" reference "$in/good.exr" --size 8 --ktx2-zstd --out "$work/out"

expect_refused sweep-size     "face size 12"      sweep --size 12 --out "$work/out"
expect_refused sweep-hdri-dir "$in/nope"          sweep --size 4 --hdri-dir "$in/nope" --out "$work/out"
expect_refused sweep-repeat   "--repeat 0"        sweep --size 4 --repeat 0 --out "$work/out"
expect_refused sweep-texels   "--texels"          sweep --size 4 --texels 0 --out "$work/out"
expect_refused sweep-summarize-missing "$in/nope/sweep.csv" sweep --summarize "$in/nope" --out "$work/out"
mkdir -p "$work/bad-sweep"
{
    printf '%s%s\n' method,family,count,bias,pyramid,form,reads_per_texel,shader_taps_per_texel,probe,level, \
        image_l1,impulse_l1_mean,impulse_l1_max,gpu_ms,level_gpu_ms
    echo fis8,fis,8,0,bspline,,8,sky,1,0.1,0.1
} >"$work/bad-sweep/sweep.csv"
expect_refused sweep-summarize-short-row "sweep.csv: line 2" sweep --summarize "$work/bad-sweep" --out "$work/out"
expect_refused plan-missing   "$in/nope.json"     plan "$in/nope.json"

# The explicit flag repairs instead of refusing, and then the output is complete.
if "$PROBEFILTER" reference "$in/nan.exr" --size 8 --repair-pixels --out "$work/repaired" >/dev/null 2>&1 &&
   [[ -f $work/repaired/level_2.exr && -f $work/repaired/report.json ]]; then
    echo "ok repair-pixels"
else
    echo "FAIL repair-pixels"; failures=$((failures + 1))
fi

# Negative pixels (what lossy EXR compression leaves around bright sources) are clamped to 0 with a
# warning that names the file and counts them, and the count is in the report.
if "$PROBEFILTER" reference "$in/negative.exr" --size 8 --out "$work/clamped" >/dev/null 2>"$work/stderr" &&
   grep -qF "$in/negative.exr: 1 pixel(s) with negative values clamped to 0" "$work/stderr" &&
   grep -q '"clamped_negative_pixels": 1' "$work/clamped/report.json"; then
    echo "ok negative-pixels-clamped: $(cat "$work/stderr")"
else
    echo "FAIL negative-pixels-clamped: $(cat "$work/stderr")"; failures=$((failures + 1))
fi

echo "cli_bad_input: $failures failure(s)"
[[ $failures -eq 0 ]]
