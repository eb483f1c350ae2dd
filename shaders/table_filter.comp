// Pass 2 with a tap table (Manson & Sloan), a group of output levels per dispatch, mirroring core's
// table_filter.cpp: per output texel, every frame with weight > 0 contributes its N taps, four at a
// time from the published layout (vec4 coeffs[5][3][3N/4] per quad level, vec4 coeffs[5][3N/4]
// per constant level), each one trilinear read of the pyramid: with PROBE_HARDWARE_SAMPLING one
// textureLod through the seamless sampler, else footprint.glsl's arithmetic over the bordered buffer.
// After the coefficients, tableEntry(usageFirst + m).x is the tap groups of four that level m uses
// (probe::tapsInUse; the rest are zero-weight padding). With hardware sampling the dispatch is
// (groups, rows, 6 P): a workgroup covers texels of one face of one level, face gl_WorkGroupID.z % 6
// of cube gl_WorkGroupID.z / 6 of a batch of P (batch.glsl), so that the frames' axes and with them
// every table index are the same across it (a GPU reads them once per wave). Exact sampling, whose
// frame loop takes each invocation's axes, runs (groups, rows, P) over the six faces one after
// another, so that the smallest levels fill a workgroup instead of six. The group's levels follow one
// another in the grid (level_group.glsl). Within a face the invocations take its interior first, then
// its edge ring (texelOfInvocation).
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#ifndef PROBE_HARDWARE_SAMPLING
#extension GL_KHR_shader_subgroup_vote : require
#endif
#define PROBE_LEVEL_GROUP
#include "images.glsl"
#include "footprint.glsl"
#include "level_group.glsl"
#include "tap_sum.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

// The table's form and taps per frame N (a multiple of 4), fixed per pipeline: the other form's
// reads are compiled out, and every table index is a base plus a constant offset.
layout(constant_id = 0) const int kCoefficientCount = 3; // 3: quadratic, 1: constant
layout(constant_id = 2) const int kTaps = 8;
// 0: each level's tap groups in use, from the table (the runtime); n > 0: n groups of four taps per
// frame at every level, a constant that unrolls the loops, so that bench/shader_stats/shader_stats measures the
// cost of a tap as the difference between two counts.
layout(constant_id = 1) const int kFixedTapGroups = 0;

layout(push_constant) uniform Params {
    int faceSize;      // S_0
    int pyramidLevels; // the levels pass 1 built (log2(S_0) + 1 in a full run): exact reads clamp to them
    int firstLevel;    // the group's first output level
    uint usageFirst;   // index of level 0's tap group count in `table`
    // Per level of the group, the end of its workgroups (level_group.glsl).
    uint groupEnd[PROBE_MAX_GROUP_LEVELS];
} params;

uint levelFirst; // the level's first vec4 in `table`

#define PROBE_TAPS kTaps
#define PROBE_COEFFICIENTS kCoefficientCount
vec4 probeTableEntry(uint index) { return tableEntry(levelFirst + index); }
vec3 probeSamplePyramid(vec3 direction, float level) {
#ifdef PROBE_HARDWARE_SAMPLING
    return pyramidRead(direction, level);
#else
    return sampleTrilinear(params.faceSize, params.pyramidLevels, direction, level);
#endif
}
#include "table_taps.glsl"

// The texel (its index within the face) that invocation k of a face computes, in a level of face
// size `size`. The interior comes first and the ring where the face's own frame counts
// (max(|u|, |v|) > PROBE_FRAME_BAND_START: size / 8 texels wide) last, so that a subgroup seldom
// holds both and only the ring's subgroups take the third frame. In row order, every subgroup of a
// face at most two subgroups wide would reach the ring (16^2 on lavapipe's 8 invocations, 64^2 for a
// 32-wide warp), and many of a wider face's would. Outputs do not depend on the order.
uint texelOfInvocation(uint k, int size) {
    uint s = uint(size);
    uint w = uint(float(s) * 0.5 * (1.0 - PROBE_FRAME_BAND_START)), n = s - 2u * w;
    uint r = k, i, j;
    if (r < n * n) {
        i = w + r % n;
        j = w + r / n;
    } else if (r - n * n < 2u * w * s) { // the w rows at the top, then the w at the bottom
        r -= n * n;
        j = r / s;
        j = j < w ? j : j + n;
        i = r % s;
    } else { // the rows between: w texels on each side
        r -= n * n + 2u * w * s;
        uint side = max(2u * w, 1u);
        j = w + r / side;
        i = r % side;
        i = i < w ? i : i + n;
    }
    return j * s + i;
}

void main() {
    uint groupInLevel, slot = levelSlot(params.groupEnd, groupInLevel);
    if (slot >= uint(PROBE_LEVEL_GROUP_WIDTH)) return;
    int level = params.firstLevel + int(slot), size = params.faceSize >> level;
    uint faceTexels = uint(size * size), inLevel = invocationInLevel(groupInLevel);
#ifdef PROBE_HARDWARE_SAMPLING
    uint invocation = inLevel, face = gl_WorkGroupID.z % 6u;
    batchCube = int(gl_WorkGroupID.z / 6u);
    if (invocation >= faceTexels) return;
#else
    uint invocation = inLevel % faceTexels, face = inLevel / faceTexels;
    batchCube = int(gl_WorkGroupID.z);
    if (face >= 6u) return;
#endif
    uint inFace = texelOfInvocation(invocation, size), texel = face * faceTexels + inFace;
    // The two frames about the other axes weigh 1 everywhere on the face (one of their axes is the
    // face's); the frame about the face's own axis only near its edges, so it comes last. Faces are
    // +X, -X, +Y, -Y, +Z, -Z.
    int major = int(face) / 2;
    // The texel centre on the cube (major component +-1). Hardware sampling computes it, so that no
    // buffer grows with the texel count; exact sampling takes it from its unit direction in the
    // geometry buffer, as probecore computes it in double.
#ifdef PROBE_HARDWARE_SAMPLING
    vec3 d = texelCubePoint(int(face), int(inFace % uint(size)), int(inFace / uint(size)), size);
#else
    vec3 R = geometryTexel(levelOffset(params.faceSize, level) + texel).xyz;
    vec3 d = R / abs(R[major]);
#endif
    levelFirst = uint(level) * uint(5 * kCoefficientCount * 3 * kTaps / 4);
    int groupsInUse = kFixedTapGroups > 0 ? kFixedTapGroups : int(tableEntry(params.usageFirst + uint(level)).x);
    vec3 sum = vec3(0.0);
    float weightSum = 0.0;
#ifdef PROBE_HARDWARE_SAMPLING
    addTableFrame(d, (major + 1) % 3, groupsInUse, false, sum, weightSum);
    addTableFrame(d, (major + 2) % 3, groupsInUse, false, sum, weightSum);
    if (frameWeight(d, major) > 0.0) addTableFrame(d, major, groupsInUse, false, sum, weightSum);
#else
    // Exact sampling is the mode for Mesa's lavapipe, a SIMD back end that runs a branch's body even
    // where no invocation takes it and a loop until every invocation has left it: the third frame is
    // a third pass of a loop that the subgroups where some invocation needs it take (the others
    // weigh it 0). Every invocation of a subgroup leaves the loop together: Mesa 22.3's lavapipe
    // miscompiles some loops whose exit diverges (GpuTest.TableFilterEqualsCpuModel catches it).
    int frames = subgroupAny(frameWeight(d, major) > 0.0) ? 3 : 2;
    int k = 0;
    do {
        addTableFrame(d, (major + 1 + k) % 3, groupsInUse, true, sum, weightSum);
    } while (++k < frames);
#endif
    storeOutput(slot, texelCoordinates(texel, size), finishTapSum(sum, weightSum));
}
