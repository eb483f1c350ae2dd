// The exact reference of DESIGN.md on the GPU, mirroring core/src/reference.cpp: for each output
// texel centre R, F(R) = sum_t L(t) K(R, l_t) dOmega_t / sum_t K(R, l_t) dOmega_t over every source
// texel t, at the levels with alpha > 0 (copy_level.comp does the others). Rows are summed in float,
// rows into a compensated float sum (the C++ sums rows in double). Faces wholly behind R (all four
// corners with R.l <= 0) are skipped.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "ggx.glsl"
#include "buffers.glsl"
#include "cube.glsl"

layout(local_size_x = 64) in;

layout(push_constant) uniform Params {
    int sourceSize; // S_0: pyramid level 0
    int outLevel;   // output level m, face size S_0 >> m
    float alpha2;   // GGX alpha^2 of the level
} params;

bool faceBehind(vec3 R, int face) {
    for (int c = 0; c < 4; ++c) {
        vec3 corner = faceUvToCubePoint(face, (c & 1) == 0 ? -1.0 : 1.0, (c & 2) == 0 ? -1.0 : 1.0);
        if (dot(R, corner) > 0.0) return false;
    }
    return true;
}

void main() {
    int outSize = params.sourceSize >> params.outLevel;
    uint texel = invocationIndex();
    if (texel >= 6u * uint(outSize * outSize)) return;
    uint outIndex = levelOffset(params.sourceSize, params.outLevel) + texel;
    vec3 R = geometry[outIndex].xyz;

    int s = params.sourceSize;
    precise vec4 total = vec4(0.0);        // (sum L K dOmega, sum K dOmega)
    precise vec4 compensation = vec4(0.0); // Kahan
    for (int face = 0; face < 6; ++face) {
        if (faceBehind(R, face)) continue;
        for (int row = 0; row < s; ++row) {
            uint begin = uint((face * s + row) * s);
            uint source = pyramidTexelIndex(face, 0, row, s); // the same texel in the bordered pyramid
            vec4 rowSum = vec4(0.0);
            for (uint t = begin; t < begin + uint(s); ++t, ++source) {
                vec4 l = geometry[t]; // level 0 of the geometry is the source's
                vec3 d = R - l.xyz;
                float k = ggxKernel(dot(R, l.xyz), dot(d, d), params.alpha2);
                rowSum += k * vec4(pyramidTexel(source) * l.w, l.w);
            }
            precise vec4 y = rowSum - compensation;
            precise vec4 sum = total + y;
            compensation = (sum - total) - y;
            total = sum;
        }
    }
    outputTexels[outIndex] = vec4(total.rgb / total.w, 1.0);
}
