// The per-tap math of Pass 2, mirroring core's probe/frame.h line by line: the three frames of an
// output texel, their weights, the polynomial domain (theta, phi) and the evaluation of four taps
// at once from the published table layout (docs/design.md "Tap tables").
#ifndef PROBE_FRAME_GLSL
#define PROBE_FRAME_GLSL

#include "probe/shared_constants.h"

struct FrameSetup {
    float weight; // (max(|d_b|, |d_c|) - 0.75) / 0.25; the frame is skipped where <= 0
    vec3 x, y, z; // z = R, x = normalize(axis x R), y = R x x
    float theta2, phi2;
};

// The weight of frame `axis` at cube vector d: (max(|d_b|, |d_c|) - 0.75) / 0.25.
float frameWeight(vec3 d, int axis) {
    int b = axis == 0 ? 1 : 0, c = axis == 2 ? 1 : 2;
    return (max(abs(d[b]), abs(d[c])) - PROBE_FRAME_BAND_START) / PROBE_FRAME_BAND_WIDTH;
}

// Frame `axis` of the output texel with cube vector d (major component exactly 1 in magnitude).
FrameSetup frameSetup(vec3 d, int axis) {
    int b = axis == 0 ? 1 : 0, c = axis == 2 ? 1 : 2;
    FrameSetup f;
    f.weight = frameWeight(d, axis);
    f.x = vec3(0.0);
    f.y = vec3(0.0);
    f.z = vec3(0.0);
    f.theta2 = 0.0;
    f.phi2 = 0.0;
    if (f.weight <= 0.0) return f;

    vec3 up = vec3(0.0);
    up[axis] = 1.0;
    f.z = normalize(d);
    f.x = normalize(cross(up, f.z));
    f.y = cross(f.z, f.x);

    float z = abs(d[axis]);
    float m = max(abs(d[b]), abs(d[c]));
    float xs = d[b] / m, ys = d[c] / m;
    float theta;
    if (ys < xs)
        theta = ys <= -PROBE_THETA_EDGE ? xs : ys;
    else
        theta = ys >= PROBE_THETA_EDGE ? -xs : -ys;
    float phi = z >= 1.0 - PROBE_POLE_EPSILON ? m : z;
    f.theta2 = theta * theta;
    f.phi2 = phi * phi;
    return f;
}

// A tap as the pyramid sees it: direction with major component 1, absolute level (before the
// clamp), weight (frame weight included).
struct TapSample {
    vec3 direction;
    float level;
    float weight;
};

// One tap from its five parameters (direction in the frame basis, level, weight).
TapSample evaluateTap(FrameSetup f, float px, float py, float pz, float level, float weight) {
    TapSample s;
    s.direction = f.x * px + f.y * py + f.z * pz;
    vec3 a = abs(s.direction);
    s.direction = s.direction / max(max(a.x, a.y), a.z); // |major component|, as the C++ finds it
    s.level = level + PROBE_LEVEL_JACOBIAN_SCALE * log2(dot(s.direction, s.direction));
    s.weight = weight * f.weight;
    return s;
}

#endif
