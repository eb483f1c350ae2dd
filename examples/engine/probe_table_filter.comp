// The drop-in table shader as an engine compiles it into its own pipeline: the generated table
// first, then the shader (see its header for bindings, push constant and dispatch).
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBE_OUTPUT_FORMAT rgba16f
#include "gltf128_quad8.glsl"
#include "engine/probe_table_filter.glsl"
