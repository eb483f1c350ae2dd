// Cube map addressing in GLSL, mirroring core/src/cube.cpp (probe/cube.h): Vulkan face order
// +X, -X, +Y, -Y, +Z, -Z, face coordinates (u, v) in [-1, 1], texel centres at (i + 0.5) / S.
#ifndef PROBE_CUBE_GLSL
#define PROBE_CUBE_GLSL

// Face coordinates to the unnormalized direction on the unit cube (Vulkan face selection table).
vec3 faceUvToCubePoint(int face, float u, float v) {
    switch (face) {
    case 0: return vec3(1.0, -v, -u);
    case 1: return vec3(-1.0, -v, u);
    case 2: return vec3(u, 1.0, v);
    case 3: return vec3(u, -1.0, -v);
    case 4: return vec3(u, -v, 1.0);
    default: return vec3(-u, -v, -1.0);
    }
}

// Direction (any length, not zero) to (face, u, v); ties go to X, then Y, as in the C++.
void directionToFaceUv(vec3 d, out int face, out vec2 uv) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0.0 ? 0 : 1;
        uv = d.x >= 0.0 ? vec2(-d.z, -d.y) / a.x : vec2(d.z, -d.y) / a.x;
    } else if (a.y >= a.z) {
        face = d.y >= 0.0 ? 2 : 3;
        uv = d.y >= 0.0 ? vec2(d.x, d.z) / a.y : vec2(d.x, -d.z) / a.y;
    } else {
        face = d.z >= 0.0 ? 4 : 5;
        uv = d.z >= 0.0 ? vec2(d.x, -d.y) / a.z : vec2(-d.x, -d.y) / a.z;
    }
}

float texelCentreUv(int index, int size) { return 2.0 * (float(index) + 0.5) / float(size) - 1.0; }

// Continuous texel coordinates (x, y) of a face of size `size` (texel (i, j) spans [i, i + 1] x
// [j, j + 1]) as face coordinates (u, v).
vec2 texelToFaceUv(float x, float y, int size) { return 2.0 * vec2(x, y) / float(size) - 1.0; }

// The centre of texel (i, j) of `face` on the unit cube (probe::texelCubePoint); i or j may step one
// texel beyond the face, onto its extended plane.
vec3 texelCubePoint(int face, int i, int j, int size) { return faceUvToCubePoint(face, texelCentreUv(i, size), texelCentreUv(j, size)); }

// The texel (face, i, j) of a level of `size` whose footprint contains a direction.
ivec3 directionToTexel(vec3 d, int size) {
    int face;
    vec2 uv;
    directionToFaceUv(d, face, uv);
    ivec2 ij = clamp(ivec2(floor((uv + 1.0) * 0.5 * float(size))), ivec2(0), ivec2(size - 1));
    return ivec3(face, ij);
}

// Texel (i, j) of `face` where exactly one of i, j is one step outside the face: the texel centre
// beyond the edge, on the face's extended plane, projected onto the adjacent face
// (probe::texelNeighbour).
ivec3 texelAcrossEdge(int face, int i, int j, int size) { return directionToTexel(texelCubePoint(face, i, j, size), size); }

// Linear index of a texel in a face-major, row-major level (probe::texelIndex).
uint texelIndex(int face, int i, int j, int size) { return (uint(face) * uint(size) + uint(j)) * uint(size) + uint(i); }

#endif
