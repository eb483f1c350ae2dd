// The engine drop-in pyramid pass (shaders/engine/probe_pyramid.glsl) for the default table, its fine
// and coarse bindings moved to the Filter's pyramid cube (6) and pyramid mip (7), so that shader_stats
// compiles it with the runtime's pipeline layout.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBE_FINE_BINDING 6
#define PROBE_COARSE_BINDING 7
#define PROBE_PYRAMID_FORMAT rgba32f
#define PROBE_PYRAMID_MAX vec3(3.40282347e38)
#define PROBE_TABLE_PYRAMID_ONLY
#include "gltf128_quad8.glsl"
#include "engine/probe_pyramid.glsl"
