#!/usr/bin/env bash
# scripts/bundle-runtime: the bundle holds the loader and the glvnd libraries NVIDIA's driver needs,
# and its launcher runs probefilter from them alone (no build folder on the library path) on the
# default device; a missing build is refused with exit 2 before anything is written.
# Usage: bundle_runtime.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$source/scripts/bundle-runtime" "$work/bundle" "$build" >/dev/null
for name in libvulkan.so.1 libGLdispatch.so.0 libGLX.so.0 libEGL.so.1; do
    test -f "$work/bundle/lib/$name" || { echo "bundle_runtime: $name missing from the bundle" >&2; exit 1; }
done
"$work/bundle/probefilter" synth sky --size 16 --out "$work/sky.exr" >/dev/null
"$work/bundle/probefilter" filter "$work/sky.exr" --size 16 --out "$work/out" >/dev/null
test -s "$work/out/level_3.exr"

set +e
"$source/scripts/bundle-runtime" "$work/other" "$work/no-build" 2>"$work/err"
status=$?
set -e
[[ $status -eq 2 && ! -e "$work/other" ]] || { echo "bundle_runtime: a missing build gave exit $status" >&2; exit 1; }
grep -q "not built" "$work/err"
