// The exact reference of docs/design.md on the GPU, mirroring core/src/reference.cpp: for each output
// texel centre R, F(R) = sum_t L(t) K(R, l_t) dOmega_t / sum_t K(R, l_t) dOmega_t over every source
// texel t, K the GGX or Charlie lobe's, at the levels that are not copies (copy_level.comp does those).
// The source is summed in chunks of rows, one dispatch each (reference_pass.cpp): a chunk's rows
// are summed in float and added with Kahan compensation; the chunk's sum (sum L K dOmega, sum K
// dOmega) is added to the texel's running sum (the accumulator, binding 1), which the last chunk
// divides and stores.
// Chunks bound the work of one invocation: GPUs reset a device whose dispatch runs too long, and
// Mesa's lavapipe ends every loop of an invocation after 65535 iterations in all (its
// LP_MAX_TGSI_LOOP_ITERATIONS), which a whole 128^2 source exceeds. A chunk wholly behind R (all
// four corners of its face with R.l <= 0) adds nothing.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "cube.glsl"
#include "lobe.glsl"
#include "images.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

layout(push_constant) uniform Params {
    int sourceSize; // S_0: pyramid level 0
    int outLevel;   // output level m, face size S_0 >> m
    float alpha2;   // GGX: alpha^2 of the level
    float exponent; // Charlie: its kernel's exponent (lobe.glsl)
    int lobe;       // 0: GGX, 1: Charlie
    int firstRow;   // the chunk: rows [firstRow, firstRow + rowCount) of the source, counted over
    int rowCount;   // all faces (face * S_0 + row), within one face
    int stage;      // bit 0: the first chunk (the sum starts at 0); bit 1: the last (divide)
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
    vec3 R = geometryTexel(outIndex).xyz;

    int s = params.sourceSize;
    int face = params.firstRow / s;
    precise vec4 total = (params.stage & 1) != 0 ? vec4(0.0) : outputTexels[outIndex]; // (sum L K dOmega, sum K dOmega)
    if (!faceBehind(R, face)) {
        precise vec4 chunk = vec4(0.0);
        precise vec4 compensation = vec4(0.0); // Kahan
        for (int row = params.firstRow; row < params.firstRow + params.rowCount; ++row) {
            uint begin = uint(row * s);
            uint source = pyramidTexelIndex(face, 0, row - face * s, s); // the same texel in the bordered pyramid
            vec4 rowSum = vec4(0.0);
            for (uint t = begin; t < begin + uint(s); ++t, ++source) {
                vec4 l = geometryTexel(t); // level 0 of the geometry is the source's
                vec3 d = R - l.xyz;
                float k = params.lobe == 0 ? ggxKernel(dot(R, l.xyz), dot(d, d), params.alpha2)
                                           : charlieKernel(dot(R, l.xyz), dot(d, d), params.exponent);
                rowSum += k * vec4(pyramidTexel(source) * l.w, l.w);
            }
            precise vec4 y = rowSum - compensation;
            precise vec4 sum = chunk + y;
            compensation = (sum - chunk) - y;
            chunk = sum;
        }
        total += chunk;
    }
    if ((params.stage & 2) != 0) storeOutput(texelCoordinates(texel, outSize), total.rgb / total.w);
    else outputTexels[outIndex] = total;
}
