// Filtered importance sampling (Krivanek & Colbert), a group of output levels per dispatch
// (level_group.glsl), mirroring core's
// fis.cpp: the level's samples, made once on the host by probe::fisSamples in
// the tangent frame of R (xyz: the reflected direction l, w: its pyramid level; the weight is
// n.l = l.z), are rotated into the frame of each output texel and read from the pyramid: with
// PROBE_HARDWARE_SAMPLING one textureLod through the seamless sampler, with PROBE_PARABOLOID_MAP one
// trilinear read of the dual-paraboloid map at the level its texel solid angle there gives
// (paraboloid.glsl), else footprint.glsl's arithmetic over the bordered buffer.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#define PROBE_LEVEL_GROUP
#include "images.glsl"
#include "footprint.glsl"
#include "level_group.glsl"
#include "tap_sum.glsl"
#ifdef PROBE_PARABOLOID_MAP
#include "paraboloid.glsl"
#endif

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

// 0: the level's sample count from the push constants (the runtime); n > 0: n samples, a constant
// that unrolls the loop, so that bench/shader_stats/shader_stats measures the cost of a sample as the difference
// between two counts.
layout(constant_id = 0) const int kFixedSampleCount = 0;

layout(push_constant) uniform Params {
    int faceSize;      // S_0
    int pyramidLevels; // the levels pass 1 built (log2(S_0) + 1 in a full run): exact reads clamp to them
    int firstLevel;    // the group's first output level
    // Per level of the group, the end of its workgroups (level_group.glsl), and level firstLevel + k's
    // samples: [firstSample[k], firstSample[k + 1]).
    uint groupEnd[PROBE_MAX_GROUP_LEVELS];
    uint firstSample[PROBE_MAX_GROUP_LEVELS + 1];
} params;

vec3 samplePyramid(vec3 direction, float level) {
#if defined(PROBE_HARDWARE_SAMPLING)
    return pyramidRead(direction, level);
#elif defined(PROBE_PARABOLOID_MAP)
    return sampleParaboloid(params.faceSize, direction, paraboloidLevel(direction, level, params.faceSize));
#else
    return sampleTrilinear(params.faceSize, params.pyramidLevels, direction, level);
#endif
}

void main() {
    uint groupInLevel, slot = levelSlot(params.groupEnd, groupInLevel);
    if (slot >= uint(PROBE_LEVEL_GROUP_WIDTH)) return;
    int level = params.firstLevel + int(slot), size = params.faceSize >> level;
    uint inLevel = invocationInLevel(groupInLevel);
    batchCube = int(gl_WorkGroupID.z); // a layer of workgroups per cube of a batch
    if (inLevel >= 6u * uint(size * size)) return;
    ivec3 t = texelCoordinates(inLevel, size);
    // Hardware sampling computes the texel's direction, so that no buffer grows with the texel count;
    // exact sampling reads it from the geometry buffer, as probecore computes it in double.
#ifdef PROBE_HARDWARE_SAMPLING
    vec3 R = normalize(texelCubePoint(t.z, t.x, t.y, size));
#else
    vec3 R = geometryTexel(levelOffset(params.faceSize, level) + inLevel).xyz;
#endif

    // probe::fisFrame
    vec3 up = abs(R.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 tx = normalize(cross(up, R)), ty = cross(R, tx);
    vec3 sum = vec3(0.0);
    float weightSum = 0.0;
    // Tested at the bottom, as table_filter.comp's loops (the host makes at least one sample a level).
    uint firstSample = params.firstSample[slot];
    uint sampleCount = kFixedSampleCount > 0 ? uint(kFixedSampleCount) : params.firstSample[slot + 1u] - firstSample;
    uint k = 0u;
    [[unroll]] do {
        vec4 s = tableEntry(firstSample + k);
        sum += s.z * samplePyramid(tx * s.x + ty * s.y + R * s.z, s.w);
        weightSum += s.z;
    } while (++k < sampleCount);
    storeOutput(slot, t, finishTapSum(sum, weightSum));
}
