// The engine drop-in (shaders/engine/probe_table_filter.glsl) with the default table, its pyramid and
// output bindings moved to the Filter's pyramid cube (6) and output mip (8), so that shader_stats
// compiles it with the runtime's pipeline layout.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBE_PYRAMID_BINDING 6
#define PROBE_OUTPUT_BINDING 8
#include "gltf128_quad8.glsl"
#include "engine/probe_table_filter.glsl"
