#!/usr/bin/env bash
# The mixed tables that scripts/regenerate-tables says lie on the greedy path of scripts/mix-path do:
# each recipe's tap counts at the filtered levels (from its source tables' names) are a step of the
# path that the script prints from the committed tables.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
path=$("$root/scripts/mix-path" gltf128_quad)
for mix in gltf128_quadmix8lean gltf128_quadmix8; do
    recipe=$(sed -n "s/^ *\[$mix\]=\"\(.*\)\"$/\1/p" "$root/scripts/regenerate-tables")
    [[ -n $recipe ]] || { echo "mix_path: no recipe for $mix in scripts/regenerate-tables" >&2; exit 1; }
    read -r -a sources <<< "$recipe"
    taps=""
    for source in "${sources[@]:1}"; do taps+=$(printf ' %2d' "${source##*_quad}"); done # level 0 is a copy
    grep -q "^taps$taps  mean" <<< "$path" || { echo "mix_path: $mix (taps$taps) is not on the path:" >&2; echo "$path" >&2; exit 1; }
    echo "mix_path: $mix (taps$taps) is on the greedy path"
done
