// The sphere renderer: one sphere per material, in square cells left to right, each seen by its own
// pinhole camera on +Z looking at -Z (+Y up), over the probe as background, lit by the filtered
// probe with the split-sum approximation:
//   specular = prefiltered(R, level) * (F0 * A + B),  F0 = mix(0.04 specular, base, metallic)
//   diffuse  = base (1 - metallic) E(N),               E = order-2 SH irradiance
// and, where a material has sheen (KHR_materials_sheen), the sheen layer over them:
//   colour = sheenColor charlie(R, sheenLevel) S + (1 - max(sheenColor) E_s) (specular + diffuse)
// with (S, E_s) from the sheen table at (n.v, sheen roughness) (probe/sheen.h; the factor clamped
// at 0, since E_s exceeds 1 at grazing for smooth sheen) and charlie the Charlie levels.
// with (A, B) read bilinearly from the DFG table at (n.v, perceptual roughness), texel centres at
// (i + 0.5) / size (probe/dfg.h), and the prefiltered value read trilinearly from the filtered
// levels at the material's level (probe::roughnessToLevel, computed by the caller).
// The background is the probe itself, read bilinearly (seamless), so that its texels do not show as
// blocks where a cell's pixels are smaller than a texel.
// Buffers: pyramid = the filtered levels (packed from S_0 with borders, in the pyramid's layout),
// then the background cube (one level, with borders), then the Charlie levels (as the filtered ones)
// where some material has sheen; output = the pixels (linear RGB); geometry = the DFG table's
// (A, B, 0, 0) row by row, then the sheen table's (S, E_s, 0, 0); table = the 9 irradiance
// coefficients (rgb), then four vec4 per material.
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
    int sheenFirst;     // the Charlie levels' first texel in the pyramid buffer (0: none)
    int sheenSize;      // the sheen table is sheenSize x sheenSize, after the DFG table
    float tanHalfFov;   // of each cell's camera
    float distance;     // of each cell's camera from its unit sphere
} params;
// tableEntry(k), k < 9: irradiance coefficient k (rgb); then per material m, from 9 + 4m:
// (base colour, metallic), (specular, roughness, level, has specular), (sheen colour, sheen
// roughness), (sheen level, 0, 0, 0).

// A size x size lookup table starting at texel `first` of the geometry buffer, read bilinearly at (n.v, roughness).
vec2 lookup(int first, int size, float nDotV, float roughness) {
    vec2 x = clamp(vec2(nDotV, roughness) * float(size) - 0.5, vec2(0.0), vec2(float(size - 1)));
    ivec2 i0 = min(ivec2(floor(x)), ivec2(size - 2 < 0 ? 0 : size - 2));
    ivec2 i1 = min(i0 + 1, ivec2(size - 1));
    vec2 f = x - vec2(i0);
    vec2 a = mix(geometryTexel(uint(first + i0.y * size + i0.x)).xy, geometryTexel(uint(first + i0.y * size + i1.x)).xy, f.x);
    vec2 b = mix(geometryTexel(uint(first + i1.y * size + i0.x)).xy, geometryTexel(uint(first + i1.y * size + i1.x)).xy, f.x);
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
        uint first = uint(PROBE_SH_COUNT + 4 * material);
        vec4 m0 = tableEntry(first), m1 = tableEntry(first + 1u), m2 = tableEntry(first + 2u), m3 = tableEntry(first + 3u);
        vec3 base = m0.rgb;
        float metallic = m0.a, specularStrength = m1.x, roughness = m1.y, level = m1.z;
        float nDotV = clamp(dot(n, v), 1e-4, 1.0);
        colour = base * (1.0 - metallic) * irradiance(n);
        if (m1.w != 0.0) {
            vec2 ab = lookup(0, params.dfgSize, nDotV, roughness);
            vec3 f0 = mix(vec3(0.04 * specularStrength), base, metallic);
            colour += sampleTrilinear(params.faceSize, params.levelCount, r, level) * (f0 * ab.x + ab.y);
        }
        vec3 sheenColour = m2.rgb;
        if (max(sheenColour.r, max(sheenColour.g, sheenColour.b)) > 0.0) {
            vec2 se = lookup(params.dfgSize * params.dfgSize, params.sheenSize, nDotV, m2.w);
            vec3 charlie = sampleTrilinearAt(uint(params.sheenFirst), params.faceSize, params.levelCount, r, m3.x);
            colour = sheenColour * charlie * se.x + max(1.0 - max(sheenColour.r, max(sheenColour.g, sheenColour.b)) * se.y, 0.0) * colour;
        }
    }
    outputTexels[pixel] = vec4(colour, 1.0);
}
