#!/usr/bin/env bash
# The engine example as an engine builds it: install the package to a fresh prefix, build
# examples/engine against it with find_package(probefilter) (the program and the drop-in shaders),
# and run it with each sampling mode: its result equals the CPU model within the tolerance it states.
# A program that links probefilter::runtime alone (no tools component) builds and runs without
# OpenEXR and OpenMP: neither is in its link line, nor among its libraries.
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

# The runtime alone: find_package without the tools component, a program that lists the devices
# and finds the default table, linked with neither OpenEXR nor OpenMP.
mkdir -p "$work/alone"
cat >"$work/alone/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.25)
project(runtime_alone LANGUAGES CXX)
set(CMAKE_CXX_STANDARD 17)
find_package(probefilter REQUIRED)
add_executable(runtime_alone main.cpp)
target_link_libraries(runtime_alone PRIVATE probefilter::runtime)
CMAKE
cat >"$work/alone/main.cpp" <<'CPP'
#include <cstdio>

#include "probe/runtime.h"

int main() {
    const auto devices = probe::gpu::listDevices();
    const auto* table = probe::gpu::findCompiledTable(128, 7, probe::RoughnessMapping::gltf, {});
    std::printf("%zu devices, default table %s\n", devices.size(), table ? table->name.c_str() : "missing");
    return devices.empty() || !table;
}
CPP
cmake -S "$work/alone" -B "$work/alone/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/alone/build" -- -v >"$work/alone/link.txt"
if grep -Eiq 'gomp|openmp|OpenEXR|Imath' "$work/alone/link.txt"; then
    echo "FAIL: the runtime alone links OpenMP or OpenEXR:" \
        "$(grep -Eio '[^ ]*(gomp|openmp|OpenEXR|Imath)[^ ]*' "$work/alone/link.txt" | sort -u | tr '\n' ' ')" >&2
    exit 1
fi
if ldd "$work/alone/build/runtime_alone" | grep -Eiq 'gomp|OpenEXR|Imath'; then
    echo "FAIL: the runtime alone loads OpenMP or OpenEXR: $(ldd "$work/alone/build/runtime_alone" | grep -Ei 'gomp|OpenEXR|Imath')" >&2
    exit 1
fi
"$work/alone/build/runtime_alone"
