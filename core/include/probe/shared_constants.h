// Numeric constants of the sampling model that the C++ model and the GLSL shaders share.
// Valid as both C++ and GLSL: only #defines of plain numbers, no includes, no code.
#ifndef PROBE_SHARED_CONSTANTS_H
#define PROBE_SHARED_CONSTANTS_H

#define PROBE_PI 3.14159265358979323846

// Frames: a frame's weight is (max(|d_b|, |d_c|) - START) / WIDTH, d scaled to major component 1.
#define PROBE_FRAME_BAND_START 0.75
#define PROBE_FRAME_BAND_WIDTH 0.25

// Polynomial domain: theta switches to the other coordinate where y' is within this of -1 or 1.
#define PROBE_THETA_EDGE 0.999
// phi = m instead of z on the frame's own pole faces, where z is within this of 1.
#define PROBE_POLE_EPSILON 0.001

// Tap level bias from the cube's distortion: level += SCALE * log2(|d'|^2), d' major component 1.
#define PROBE_LEVEL_JACOBIAN_SCALE 0.75

// Pass 1 B-spline: the four bilinear taps sit at +-OFFSET fine texels around the coarse texel
// centre; tap i weighs SHARE * J_i / sum(J) + BASE (4 * BASE + SHARE = 1).
#define PROBE_PYRAMID_TAP_OFFSET 0.75
#define PROBE_PYRAMID_JACOBIAN_SHARE 0.5
#define PROBE_PYRAMID_BASE_WEIGHT 0.125
// The GPU runtime's pass 1 builds the mips of this face size and smaller in one workgroup
// (shaders/pyramid_tail.comp), keeping two of them in shared memory.
#define PROBE_PYRAMID_TAIL_SIZE 8

// The most output levels one dispatch of the runtime's pass 2 writes (a level group): every level of
// the largest face size, 2048^2 (probe::kMaxFaceSize), from level 0. The push constants hold this
// many per group; a device whose storage images per stage are fewer gets groups of 4 (images.glsl).
#define PROBE_MAX_GROUP_LEVELS 12

// The workgroup size (local_size_x) of the runtime's per-texel shaders, which invocationIndex()
// (shaders/buffers.glsl) and the runtime's group counts share. A constant, since a shader's
// gl_WorkGroupSize before its own local_size declaration reads as 1.
#define PROBE_WORKGROUP_SIZE 64

// Dual-paraboloid FIS (probe/paraboloid.h): the image square holds the mapping's (u, v) times this,
// so the unit disc of a hemisphere ends inside it.
#define PROBE_PARABOLOID_SCALE 0.9

// The largest magnitude a probe's values are filtered at, 2^64 (probe/range_scale.h): the filters'
// float sums stay finite below it.
#define PROBE_FILTER_RANGE_LIMIT 18446744073709551616.0

// The largest finite values of the 16-bit formats: a half float (RGBA16F), and B10G11R11's 11-bit
// (R, G) and 10-bit (B) floats.
#define PROBE_HALF_MAX 65504.0
#define PROBE_FLOAT11_MAX 65024.0
#define PROBE_FLOAT10_MAX 64512.0
// The largest finite value of E5B9G9R9 (a 9-bit mantissa per channel, one 5-bit exponent shared):
// 511 / 512 * 2^16.
#define PROBE_RGB9E5_MAX 65408.0

// Order-2 real SH basis (probe/sh.h): sqrt(1/4pi), sqrt(3/4pi), sqrt(15/4pi), sqrt(5/16pi),
// sqrt(15/16pi).
#define PROBE_SH_C0 0.28209479177387814
#define PROBE_SH_C1 0.4886025119029199
#define PROBE_SH_C2 1.0925484305920792
#define PROBE_SH_C20 0.31539156525252005
#define PROBE_SH_C22 0.5462742152960396

#endif
