// Filtered importance sampling (Krivanek & Colbert), all output levels in one dispatch, mirroring
// core's importance_sampling.cpp: N Hammersley samples of GGX around R (n = v = R), each read from
// the pyramid at level 0.5 log2((1 / (N pdf)) / (4 pi / (6 S_0^2))) + bias, weighted by n.l.
// sin^2(theta) is formed as alpha^2 e1 / (1 + (alpha^2 - 1) e1), which equals the model's
// 1 - cos^2(theta) but does not cancel in float where alpha is small.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "ggx.glsl"
#include "tap_sum.glsl"

layout(local_size_x = 64) in;

layout(push_constant) uniform Params {
    int baseSize;          // S_0
    int pyramidLevels;     // log2(S_0) + 1
    int levelCount;        // M output levels
    float bias;            // added to every sample's level
    float texelSolidAngle; // 4 pi / (6 S_0^2)
    uint copyLevels;       // bit m: output level m is a copy (alpha = 0)
    uint firstTexel;      // the packed output texels [firstTexel, endTexel) of this dispatch
    uint endTexel;
} params;
// table[m].x: alpha^2 of output level m; table[m].y: its sample count N.

float radicalInverse2(uint bits) {
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return float(bits) * 2.3283064365386963e-10; // 2^-32
}

void main() {
    uint index = params.firstTexel + invocationIndex();
    if (index >= params.endTexel) return;
    int level;
    uint texel;
    outputTexelOf(index, params.baseSize, params.levelCount, level, texel);
    vec3 R = geometry[index].xyz;

    vec3 result;
    if ((params.copyLevels & (1u << uint(level))) != 0u) {
        result = copyOfSource(R, params.baseSize);
    } else {
        float alpha2 = table[level].x;
        int samples = int(table[level].y);
        vec3 up = abs(R.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
        vec3 tx = normalize(cross(up, R)), ty = cross(R, tx);
        vec3 sum = vec3(0.0);
        float weightSum = 0.0;
        for (int i = 0; i < samples; ++i) {
            float e1 = float(i) / float(samples), e2 = radicalInverse2(uint(i));
            float denominator = 1.0 + (alpha2 - 1.0) * e1;
            float cosTheta = sqrt((1.0 - e1) / denominator);
            float sinTheta = sqrt(alpha2 * e1 / denominator);
            float phi = 2.0 * kPi * e2;
            vec3 h = tx * (sinTheta * cos(phi)) + ty * (sinTheta * sin(phi)) + R * cosTheta;
            vec3 l = 2.0 * dot(R, h) * h - R;
            float nl = dot(R, l);
            if (nl <= 0.0) continue;
            vec3 d = R - l;
            float pdf = ggxReflectedPdf(nl, dot(d, d), alpha2);
            float sampleSolidAngle = 1.0 / (float(samples) * pdf);
            float sampleLevel = 0.5 * log2(sampleSolidAngle / params.texelSolidAngle) + params.bias;
            sum += nl * sampleTrilinear(params.baseSize, params.pyramidLevels, l, sampleLevel);
            weightSum += nl;
        }
        result = finishTapSum(sum, weightSum);
    }
    outputTexels[index] = vec4(result, 1.0);
}
