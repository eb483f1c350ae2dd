// The drop-in pyramid shader as an engine compiles it: the table the pyramid is for first, its pyramid
// pass alone, then the shader (see its header for bindings and dispatch). It builds the mips that
// probe_table_filter.comp reads.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBE_PYRAMID_FORMAT rgba16f
#define PROBE_TABLE_PYRAMID_ONLY
#include "gltf128_quad8.glsl"
#include "engine/probe_pyramid.glsl"
