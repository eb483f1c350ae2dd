#!/usr/bin/env bash
# The largest finite inputs give finite outputs: a texel at FLT_MAX, every texel at FLT_MAX and a
# Radiance HDR at its largest value (about 1.7e38), through filter's three methods with either
# mapping, reference, run (levels, SH irradiance, KTX2 in both formats, spheres) and compare: no NaN
# or Inf in any EXR or KTX2 written, none in compare's numbers.
set -euo pipefail
: "${PROBEFILTER:?}" "${PROBEBENCH:?}" "${EXTREME_PROBES:?}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$EXTREME_PROBES" make in

failures=0
check() { # folder, what
    if ! "$EXTREME_PROBES" check "$1"/*.exr "$1"/*.ktx2 "$1"/*/*.exr "$1"/*/*.ktx2 | grep -v ': 0 non-finite'; then
        return
    fi
    echo "FAIL: $2"
    failures=$((failures + 1))
}
shopt -s nullglob
for input in in/one_max.exr in/all_max.exr in/rgbe_max.hdr; do
    for method in reference table fis; do
        for mapping in gltf authors; do
            [[ $method == table && $mapping == authors ]] && continue # no compiled-in authors table at 16^2
            out=$method-$mapping-$(basename "$input")
            "$PROBEFILTER" filter "$input" --method $method --mapping $mapping --size 16 --ktx2 rgba32f --out "$out" >/dev/null 2>&1 ||
                { echo "FAIL: filter $input $method $mapping"; failures=$((failures + 1)); continue; }
            check "$out" "filter $input --method $method --mapping $mapping"
        done
    done
    "$PROBEFILTER" reference "$input" --size 16 --ktx2 rgba16f --out "reference-$(basename "$input")" >/dev/null 2>&1 ||
        { echo "FAIL: reference $input"; failures=$((failures + 1)); }
    check "reference-$(basename "$input")" "reference $input"
    # compare: the spheres rendered from those levels, their errors and the sheet (no NaN: JSON null).
    name=compare-$(basename "$input")
    if ! "$PROBEBENCH" compare "$input" --size 16 --out "$name" >/dev/null 2>&1 || grep -q null "$name/report.json"; then
        echo "FAIL: compare $input"
        failures=$((failures + 1))
    fi
    for ktx2 in rgba16f rgba32f; do
        name=run-$ktx2-$(basename "$input")
        cat >"$name.json" <<JSON
{"probes": [{"name": "p", "image": "$input", "face_size": 16, "method": "fis"}],
 "materials": [{"name": "metal", "roughness": 0.4, "metallic": 0.5}, {"name": "chalk", "roughness": 1, "specular": 0}],
 "outputs": {"exr": true, "ktx2": "$ktx2", "spheres": true}}
JSON
        "$PROBEFILTER" run "$name.json" --out "$name" >/dev/null 2>&1 || { echo "FAIL: run $input"; failures=$((failures + 1)); continue; }
        if [[ ! -f $name/p/irradiance_sh.exr || ! -f $name/p/probe.ktx2 ]]; then
            echo "FAIL: run $input: outputs missing"
            failures=$((failures + 1))
        fi
        check "$name" "run $input with $ktx2"
    done
done
echo "cli_extreme_values: $failures failure(s)"
[[ $failures -eq 0 ]]
