#!/usr/bin/env bash
# The engine example as an engine builds it: install the package to a fresh prefix, build
# examples/engine against it with find_package(probefilter) (the program and the drop-in shaders),
# and run it with each sampling mode: its result equals the CPU model within the tolerance it states.
# Usage: engine_example.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$source/examples/engine" -B "$work/example" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/example" >/dev/null
test -s "$work/example/probe_pyramid.spv"
test -s "$work/example/probe_table_filter.spv"
for sampling in hardware exact; do
    "$work/example/engine_example" "$sampling"
done
