// Pass 2's common core, mirroring core's probe/tap_sum.h: an output texel is
// sum_i w_i trilinear(pyramid, d_i, level_i) / sum_i w_i, clamped to >= 0 (black when the weights
// sum to 0). A dispatch covers one output level (copy_level.comp does the levels with alpha = 0).
#ifndef PROBE_TAP_SUM_GLSL
#define PROBE_TAP_SUM_GLSL

vec3 finishTapSum(vec3 sum, float weightSum) {
    return weightSum == 0.0 ? vec3(0.0) : max(sum / weightSum, vec3(0.0));
}

#endif
