// The box step of pass 1, mirroring core/src/pyramid.cpp: a coarse texel from its 2x2 children on
// the same face, each weighing its exact solid angle (or its inverse), normalized. Shared by
// pyramid.comp, pyramid_image.comp and pyramid_tail.comp; the includer includes buffers.glsl (the
// solid angles) and cube.glsl, and defines first:
//   vec3 probeFineTexel(int face, int i, int j, int fineSize)  texel (i, j) of `face` of the finer
//     level (face size fineSize)
#ifndef PROBE_PYRAMID_BOX_GLSL
#define PROBE_PYRAMID_BOX_GLSL

// Texel (i, j) of `face` of the coarse level, from the finer level of face size fineSize whose
// solid angles start at `firstGeometry` in the geometry buffer.
vec3 pyramidBox(int face, int i, int j, int fineSize, uint firstGeometry, bool inverseSolidAngle) {
    vec3 sum = vec3(0.0);
    float weightSum = 0.0;
    for (int k = 0; k < 4; ++k) {
        int fi = 2 * i + (k & 1), fj = 2 * j + (k >> 1);
        float area = geometryTexel(firstGeometry + texelIndex(face, fi, fj, fineSize)).w;
        float w = inverseSolidAngle ? 1.0 / area : area;
        sum += w * probeFineTexel(face, fi, fj, fineSize);
        weightSum += w;
    }
    return sum / weightSum;
}

#endif
