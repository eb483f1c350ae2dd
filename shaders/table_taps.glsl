// The taps of one frame of pass 2 with a tap table (Manson & Sloan), four at a time from the
// published layout, mirroring core's table_filter.cpp. Shared by table_filter.comp and the engine
// drop-in engine/probe_table_filter.glsl; the includer defines first:
//   PROBE_TAPS                the taps per frame N (a multiple of 4)
//   PROBE_COEFFICIENTS        3 (quadratic table) or 1 (constant)
//   vec4 probeTableEntry(uint index)                 the published layout of the level, vec4 `index`
//   vec3 probeSamplePyramid(vec3 direction, float level)  one trilinear read of the pyramid
#ifndef PROBE_TABLE_TAPS_GLSL
#define PROBE_TABLE_TAPS_GLSL

#include "frame.glsl"

// P for four taps: c0 + c1 theta^2 + c2 phi^2 (or c0).
vec4 tablePolynomial(int parameter, uint group, FrameSetup f) {
    uint groups = uint(3 * PROBE_TAPS / 4);
    uint first = uint(parameter * PROBE_COEFFICIENTS) * groups + group;
    if (PROBE_COEFFICIENTS == 1) return probeTableEntry(first);
    return probeTableEntry(first) + probeTableEntry(first + groups) * f.theta2 + probeTableEntry(first + 2u * groups) * f.phi2;
}

// Adds the taps of frame `axis` at cube vector d (major component 1), the first `groupsInUse`
// groups of four (at least one: the level's count from probe::tapsInUse). With `mayWeighZero` the
// frame may not count at d (a loop over frames that some texels of a subgroup need): there its taps
// weigh 0 at a direction that can be read. A caller that only adds frames that count passes a
// constant false, and the compiler drops those selects. The loop unrolls where groupsInUse is a
// constant (the fixed counts that bench/shader_stats/shader_stats compiles to measure the cost of a tap).
void addTableFrame(vec3 d, int axis, int groupsInUse, bool mayWeighZero, inout vec3 sum, inout float weightSum) {
    FrameSetup f = frameSetup(d, axis);
    bool counts = !mayWeighZero || f.weight > 0.0;
    int g = 0;
    [[unroll]] do {
        uint group = uint(axis * PROBE_TAPS / 4 + g);
        vec4 px = tablePolynomial(0, group, f);
        vec4 py = tablePolynomial(1, group, f);
        vec4 pz = tablePolynomial(2, group, f);
        vec4 pl = tablePolynomial(3, group, f);
        vec4 pw = tablePolynomial(4, group, f);
        [[unroll]] for (int lane = 0; lane < 4; ++lane) {
            TapSample s = evaluateTap(f, px[lane], py[lane], pz[lane], pl[lane], pw[lane]);
            float weight = counts ? s.weight : 0.0;
            sum += weight * probeSamplePyramid(counts ? s.direction : d, counts ? s.level : 0.0);
            weightSum += weight;
        }
    } while (++g < groupsInUse);
}

#endif
