// The sphere renderer: one sphere per material, in square cells left to right, each seen by its own
// pinhole camera on +Z looking at -Z (+Y up), over the probe as background, lit by the filtered
// probe with the split-sum approximation:
//   specular = prefiltered(R, level) * (F0 * A + B),  F0 = mix(0.04 specular, base, metallic)
//   diffuse  = base (1 - metallic) E(N),               E = order-2 SH irradiance
// with (A, B) read bilinearly from the DFG table at (n.v, perceptual roughness), texel centres at
// (i + 0.5) / size (probe/dfg.h), and the prefiltered value read trilinearly from the filtered
// levels at the material's level (probe::roughnessToLevel, computed by the caller).
// The background is the probe itself, read bilinearly (seamless), so that its texels do not show as
// blocks where a cell's pixels are smaller than a texel.
// Buffers: pyramid = the filtered levels (packed from S_0 with borders, in the pyramid's layout),
// then the background cube (one level, with borders); output = the pixels (linear RGB); geometry =
// the DFG table's (A, B, 0, 0) row by row; table = the 9 irradiance coefficients (rgb), then two vec4
// per material.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "footprint.glsl"
#include "sh.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

layout(push_constant) uniform Params {
    int cellSize;       // pixels per sphere cell (square)
    int materialCount;  // cells, left to right
    int faceSize;       // S_0 of the filtered levels
    int levelCount;     // M
    int backgroundSize; // face size of the background cube
    int dfgSize;        // the DFG table is dfgSize x dfgSize
    float tanHalfFov;   // of each cell's camera
    float distance;     // of each cell's camera from its unit sphere
} params;
// tableEntry(k), k < 9: irradiance coefficient k (rgb); then per material m:
// tableEntry(9 + 2m) = (base colour, metallic), tableEntry(10 + 2m) = (specular, roughness, level, has specular).

vec2 dfgLookup(float nDotV, float roughness) {
    int size = params.dfgSize;
    vec2 x = clamp(vec2(nDotV, roughness) * float(size) - 0.5, vec2(0.0), vec2(float(size - 1)));
    ivec2 i0 = min(ivec2(floor(x)), ivec2(size - 2 < 0 ? 0 : size - 2));
    ivec2 i1 = min(i0 + 1, ivec2(size - 1));
    vec2 f = x - vec2(i0);
    vec2 a = mix(geometry[i0.y * size + i0.x].xy, geometry[i0.y * size + i1.x].xy, f.x);
    vec2 b = mix(geometry[i1.y * size + i0.x].xy, geometry[i1.y * size + i1.x].xy, f.x);
    return mix(a, b, f.y);
}

vec3 irradiance(vec3 n) {
    float y[PROBE_SH_COUNT];
    shBasis(n, y);
    vec3 e = vec3(0.0);
    for (int k = 0; k < PROBE_SH_COUNT; ++k) e += tableEntry(uint(k)).rgb * y[k];
    return max(e, vec3(0.0));
}

// The background cube sits right after the M filtered levels in the pyramid buffer.
vec3 background(vec3 direction) {
    int face;
    vec2 uv;
    directionToFaceUv(direction, face, uv);
    float half0 = 0.5 * float(params.backgroundSize);
    return sampleBilinearAt(pyramidLevelOffset(params.faceSize, params.levelCount), params.backgroundSize, face, (uv.x + 1.0) * half0,
                            (uv.y + 1.0) * half0);
}

void main() {
    uint pixel = invocationIndex();
    int width = params.cellSize * params.materialCount;
    if (pixel >= uint(width * params.cellSize)) return;
    int x = int(pixel % uint(width)), y = int(pixel / uint(width));
    int material = x / params.cellSize;
    // Cell coordinates in [-1, 1], +y up.
    vec2 c = (vec2(float(x % params.cellSize), float(y)) + 0.5) / float(params.cellSize) * 2.0 - 1.0;
    vec3 direction = normalize(vec3(c.x * params.tanHalfFov, -c.y * params.tanHalfFov, -1.0));
    vec3 origin = vec3(0.0, 0.0, params.distance);

    // |origin + t direction| = 1.
    float b = dot(origin, direction);
    float discriminant = b * b - (dot(origin, origin) - 1.0);
    vec3 colour;
    if (discriminant < 0.0) {
        colour = background(direction);
    } else {
        vec3 n = normalize(origin + (-b - sqrt(discriminant)) * direction);
        vec3 v = -direction;
        vec3 r = reflect(direction, n);
        vec4 m0 = tableEntry(uint(PROBE_SH_COUNT + 2 * material)), m1 = tableEntry(uint(PROBE_SH_COUNT + 2 * material + 1));
        vec3 base = m0.rgb;
        float metallic = m0.a, specularStrength = m1.x, roughness = m1.y, level = m1.z;
        float nDotV = clamp(dot(n, v), 1e-4, 1.0);
        colour = base * (1.0 - metallic) * irradiance(n);
        if (m1.w != 0.0) {
            vec2 ab = dfgLookup(nDotV, roughness);
            vec3 f0 = mix(vec3(0.04 * specularStrength), base, metallic);
            colour += sampleTrilinear(params.faceSize, params.levelCount, r, level) * (f0 * ab.x + ab.y);
        }
    }
    outputTexels[pixel] = vec4(colour, 1.0);
}
