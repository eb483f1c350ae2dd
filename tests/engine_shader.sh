#!/usr/bin/env bash
# The drop-in engine shaders (shaders/engine/probe_table_filter.glsl, probe_pyramid.glsl) compile to
# SPIR-V against a generated table include, for each image format an engine would write, with the
# include paths an installed package gives (the shaders folder with probe/shared_constants.h, the
# tables folder). The pyramid, given the table's pyramid pass alone (PROBE_TABLE_PYRAMID_ONLY), carries
# none of its coefficients; the filter refuses a table included so.
# Usage: engine_shader.sh GLSLANG SHADERS_DIR CORE_INCLUDE_DIR TABLES_DIR TABLE_NAME
set -euo pipefail
glslang=$1 shaders=$2 include=$3 tables=$4 table=$5
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for format in rgba16f rgba32f r11f_g11f_b10f; do
    printf '%s\n' '#version 450' '#extension GL_GOOGLE_include_directive : require' "#define PROBE_OUTPUT_FORMAT $format" \
        "#include \"$table.glsl\"" '#include "engine/probe_table_filter.glsl"' >"$work/filter.comp"
    "$glslang" -V --target-env vulkan1.1 --quiet -I"$shaders" -I"$include" -I"$tables" "$work/filter.comp" -o "$work/filter.spv" ||
        { echo "FAIL: $table with $format"; exit 1; }
    printf '%s\n' '#version 450' '#extension GL_GOOGLE_include_directive : require' "#define PROBE_PYRAMID_FORMAT $format" \
        '#define PROBE_TABLE_PYRAMID_ONLY' "#include \"$table.glsl\"" '#include "engine/probe_pyramid.glsl"' >"$work/pyramid.comp"
    "$glslang" -V --target-env vulkan1.1 --quiet -I"$shaders" -I"$include" -I"$tables" "$work/pyramid.comp" -o "$work/pyramid.spv" ||
        { echo "FAIL: $table with a $format pyramid"; exit 1; }
    # The pyramid pass alone: its module names none of the table's arrays.
    if grep -qa -e probeTableCoeffs -e probeTableTapGroups "$work/pyramid.spv"; then
        echo "FAIL: the $format pyramid with $table carries the table's coefficients"; exit 1
    fi
done
# The filter needs the coefficients: a table included for its pyramid pass alone is refused by name.
printf '%s\n' '#version 450' '#extension GL_GOOGLE_include_directive : require' '#define PROBE_TABLE_PYRAMID_ONLY' \
    "#include \"$table.glsl\"" '#include "engine/probe_table_filter.glsl"' >"$work/refused.comp"
if "$glslang" -V --target-env vulkan1.1 -I"$shaders" -I"$include" -I"$tables" "$work/refused.comp" \
    -o "$work/refused.spv" >"$work/log" 2>&1; then
    echo "FAIL: the filter compiled with $table's pyramid pass alone"; exit 1
fi
grep -q PROBE_TABLE_PYRAMID_ONLY "$work/log" ||
    { echo "FAIL: the filter's refusal does not name PROBE_TABLE_PYRAMID_ONLY"; cat "$work/log"; exit 1; }
filter=$(wc -c <"$work/filter.spv") pyramid=$(wc -c <"$work/pyramid.spv")
echo "engine shaders compile with $table (SPIR-V with $format images: filter $filter bytes, pyramid $pyramid)"
