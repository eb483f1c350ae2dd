// Pass 2's common core, mirroring core's probe/tap_sum.h: an output texel is
// sum_i w_i trilinear(pyramid, d_i, level_i) / sum_i w_i, clamped to >= 0 (black when the weights
// sum to 0); a level with alpha = 0 is a copy of the source texel containing the texel's centre.
// A dispatch covers a range of packed output texels (every level, or one level): the invocation
// finds its level from the packed offsets.
#ifndef PROBE_TAP_SUM_GLSL
#define PROBE_TAP_SUM_GLSL

#include "sampling.glsl"

// The output level of a packed output texel index, and the texel within that level.
void outputTexelOf(uint index, int baseSize, int levelCount, out int level, out uint texel) {
    level = 0;
    while (level + 1 < levelCount && index >= levelOffset(baseSize, level + 1)) ++level;
    texel = index - levelOffset(baseSize, level);
}

vec3 copyOfSource(vec3 direction, int baseSize) {
    ivec3 t = directionToTexel(direction, baseSize);
    return pyramid[texelIndex(t.x, t.y, t.z, baseSize)].rgb;
}

vec3 finishTapSum(vec3 sum, float weightSum) {
    return weightSum == 0.0 ? vec3(0.0) : max(sum / weightSum, vec3(0.0));
}

#endif
