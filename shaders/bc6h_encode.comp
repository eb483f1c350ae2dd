// BC6H (unsigned half float) blocks of a filtered cube, one invocation per 4x4 block of every level,
// faces in order, blocks row by row: the layout of VK_FORMAT_BC6H_UFLOAT_BLOCK and of KTX2. A level
// smaller than 4x4 fills one block, its edge texels repeated (a decoder reads only the texels the
// level has).
//
// A BC6H texel interpolates between two endpoints in the half float's bit pattern (nearly its
// logarithm). Each block takes whichever mode decodes closest to its texels: the one-region modes 11
// (two 10-bit endpoints) and 12, 13, 14 (an 11-, 12- or 16-bit endpoint and a 9-, 8- or 4-bit offset
// to the other), which trade range for precision, so that a smooth block (as a filtered level mostly
// is) gets precise endpoints; and where none comes within kTwoRegionError, the two-region modes 1 to
// 10 (four endpoints of 6 to 11 bits, all but mode 10 storing offsets from the first) on each of the
// 32 shapes. Endpoints are fitted along each region's principal axis, refined by least squares for
// the indices chosen, and the best mode's then a step at a time; every candidate is scored by the
// decoder's own integer arithmetic: the squared difference of the half floats' bit patterns.
#version 450

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) writeonly buffer Blocks { uvec4 blocks[]; };
// The levels packed one after another, each face-major and row-major (probe::texelIndex): RGBA32F
// texels, or with kHalfTexels RGBA16F ones (an engine's output cube, copied as it is).
layout(constant_id = 0) const bool kHalfTexels = false;
layout(std430, set = 0, binding = 1) readonly buffer Texels { uint words[]; };

vec3 texel(uint index) {
    if (kHalfTexels) return vec3(unpackHalf2x16(words[2u * index]), unpackHalf2x16(words[2u * index + 1u]).x);
    return uintBitsToFloat(uvec3(words[4u * index], words[4u * index + 1u], words[4u * index + 2u]));
}

layout(push_constant) uniform Params {
    int faceSize; // level 0
    int levelCount;
    uint firstBlock; // the dispatch's blocks: a run of whole faces (whose texels the binding holds)
    uint blockCount;
    uint texelBase; // the first texel bound at binding 1 (a window of the levels where they exceed the storage-buffer range)
} params;

const float kHalfMax = 65504.0;
const float kNone = 3.4e38; // the error of a candidate the format cannot store
// Summed over a block's 48 channels: at or below it (an error of 1 in the last place of a half on
// average) the two-region modes are not tried.
const float kTwoRegionError = 48.0;

// The weights out of 64 of 4-bit (one region) and 3-bit (two regions) indices.
const int kWeights4[16] = int[16](0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64);
const int kWeights3[8] = int[8](0, 9, 18, 27, 37, 46, 55, 64);

// One-region modes 11 to 14: mode bits, endpoint bits, offset bits (0: the second endpoint whole).
const uint kOneModeBits[4] = uint[4](0x03u, 0x07u, 0x0Bu, 0x0Fu);
const int kOneEndpointBits[4] = int[4](10, 11, 12, 16);
const int kOneOffsetBits[4] = int[4](0, 9, 8, 4);

// Two-region modes 1 to 10: mode bits and their count, endpoint bits, and per channel the offset
// bits of the three endpoints after the first (0: stored whole).
const uint kTwoModeBits[10] = uint[10](0x00u, 0x01u, 0x02u, 0x06u, 0x0Au, 0x0Eu, 0x12u, 0x16u, 0x1Au, 0x1Eu);
const int kTwoModeBitCount[10] = int[10](2, 2, 5, 5, 5, 5, 5, 5, 5, 5);
const int kTwoEndpointBits[10] = int[10](10, 7, 11, 11, 11, 9, 8, 8, 8, 6);
const ivec3 kTwoOffsetBits[10] = ivec3[10](ivec3(5), ivec3(6), ivec3(5, 4, 4), ivec3(4, 5, 4), ivec3(4, 4, 5), ivec3(5), ivec3(6, 5, 5),
                                           ivec3(5, 6, 5), ivec3(5, 5, 6), ivec3(0));
// Where each stored bit goes, after the mode bits, as the format's table orders them: field * 16 +
// bit, field = channel * 4 + endpoint (r, g, b; w, x, y, z: region 0's two, region 1's two), or
// 12 for the shape's number; 65535 ends a shorter mode.
//   mode 1: gy4 by4 bz4 rw0-9 gw0-9 bw0-9 rx0-4 gz4 gy0-3 gx0-4 bz0 gz0-3 bx0-4 bz1 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4
//   mode 2: gy5 gz4 gz5 rw0-6 bz0 bz1 by4 gw0-6 by5 bz2 gy4 bw0-6 bz3 bz5 bz4 rx0-5 gy0-3 gx0-5 gz0-3 bx0-5 by0-3 ry0-5
//           rz0-5 d0-4
//   mode 3: rw0-9 gw0-9 bw0-9 rx0-4 rw10 gy0-3 gx0-3 gw10 bz0 gz0-3 bx0-3 bw10 bz1 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4
//   mode 4: rw0-9 gw0-9 bw0-9 rx0-3 rw10 gz4 gy0-3 gx0-4 gw10 gz0-3 bx0-3 bw10 bz1 by0-3 ry0-3 bz0 bz2 rz0-3 gy4 bz3 d0-4
//   mode 5: rw0-9 gw0-9 bw0-9 rx0-3 rw10 by4 gy0-3 gx0-3 gw10 bz0 gz0-3 bx0-4 bw10 by0-3 ry0-3 bz1 bz2 rz0-3 bz4 bz3 d0-4
//   mode 6: rw0-8 by4 gw0-8 gy4 bw0-8 bz4 rx0-4 gz4 gy0-3 gx0-4 bz0 gz0-3 bx0-4 bz1 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4
//   mode 7: rw0-7 gz4 by4 gw0-7 bz2 gy4 bw0-7 bz3 bz4 rx0-5 gy0-3 gx0-4 bz0 gz0-3 bx0-4 bz1 by0-3 ry0-5 rz0-5 d0-4
//   mode 8: rw0-7 bz0 by4 gw0-7 gy5 gy4 bw0-7 gz5 bz4 rx0-4 gz4 gy0-3 gx0-5 gz0-3 bx0-4 bz1 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4
//   mode 9: rw0-7 bz1 by4 gw0-7 by5 gy4 bw0-7 bz5 bz4 rx0-4 gz4 gy0-3 gx0-4 bz0 gz0-3 bx0-5 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4
//   mode 10: rw0-5 gz4 bz0 bz1 by4 gw0-5 gy5 by5 bz2 gy4 bw0-5 gz5 bz3 bz5 bz4 rx0-5 gy0-3 gx0-5 gz0-3 bx0-5 by0-3 ry0-5
//            rz0-5 d0-4
const uint kTwoLayout[10][80] = uint[10][80](
    uint[80](
        100u, 164u, 180u, 0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 64u, 65u, 66u,
        67u, 68u, 69u, 70u, 71u, 72u, 73u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 135u, 136u,
        137u, 16u, 17u, 18u, 19u, 20u, 116u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 84u,
        176u, 112u, 113u, 114u, 115u, 144u, 145u, 146u, 147u, 148u, 177u, 160u, 161u, 162u, 163u, 32u,
        33u, 34u, 35u, 36u, 178u, 48u, 49u, 50u, 51u, 52u, 179u, 192u, 193u, 194u, 195u, 196u),
    uint[80](
        101u, 116u, 117u, 0u, 1u, 2u, 3u, 4u, 5u, 6u, 176u, 177u, 164u, 64u, 65u, 66u,
        67u, 68u, 69u, 70u, 165u, 178u, 100u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 179u, 181u,
        180u, 16u, 17u, 18u, 19u, 20u, 21u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 84u,
        85u, 112u, 113u, 114u, 115u, 144u, 145u, 146u, 147u, 148u, 149u, 160u, 161u, 162u, 163u, 32u,
        33u, 34u, 35u, 36u, 37u, 48u, 49u, 50u, 51u, 52u, 53u, 192u, 193u, 194u, 195u, 196u),
    uint[80](
        0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 64u, 65u, 66u, 67u, 68u, 69u,
        70u, 71u, 72u, 73u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 135u, 136u, 137u, 16u, 17u,
        18u, 19u, 20u, 10u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 74u, 176u, 112u, 113u,
        114u, 115u, 144u, 145u, 146u, 147u, 138u, 177u, 160u, 161u, 162u, 163u, 32u, 33u, 34u, 35u,
        36u, 178u, 48u, 49u, 50u, 51u, 52u, 179u, 192u, 193u, 194u, 195u, 196u, 65535u, 65535u, 65535u),
    uint[80](
        0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 64u, 65u, 66u, 67u, 68u, 69u,
        70u, 71u, 72u, 73u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 135u, 136u, 137u, 16u, 17u,
        18u, 19u, 10u, 116u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 84u, 74u, 112u, 113u,
        114u, 115u, 144u, 145u, 146u, 147u, 138u, 177u, 160u, 161u, 162u, 163u, 32u, 33u, 34u, 35u,
        176u, 178u, 48u, 49u, 50u, 51u, 100u, 179u, 192u, 193u, 194u, 195u, 196u, 65535u, 65535u, 65535u),
    uint[80](
        0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 64u, 65u, 66u, 67u, 68u, 69u,
        70u, 71u, 72u, 73u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 135u, 136u, 137u, 16u, 17u,
        18u, 19u, 10u, 164u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 74u, 176u, 112u, 113u,
        114u, 115u, 144u, 145u, 146u, 147u, 148u, 138u, 160u, 161u, 162u, 163u, 32u, 33u, 34u, 35u,
        177u, 178u, 48u, 49u, 50u, 51u, 180u, 179u, 192u, 193u, 194u, 195u, 196u, 65535u, 65535u, 65535u),
    uint[80](
        0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 164u, 64u, 65u, 66u, 67u, 68u, 69u,
        70u, 71u, 72u, 100u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 135u, 136u, 180u, 16u, 17u,
        18u, 19u, 20u, 116u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 84u, 176u, 112u, 113u,
        114u, 115u, 144u, 145u, 146u, 147u, 148u, 177u, 160u, 161u, 162u, 163u, 32u, 33u, 34u, 35u,
        36u, 178u, 48u, 49u, 50u, 51u, 52u, 179u, 192u, 193u, 194u, 195u, 196u, 65535u, 65535u, 65535u),
    uint[80](
        0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 116u, 164u, 64u, 65u, 66u, 67u, 68u, 69u,
        70u, 71u, 178u, 100u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 135u, 179u, 180u, 16u, 17u,
        18u, 19u, 20u, 21u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 84u, 176u, 112u, 113u,
        114u, 115u, 144u, 145u, 146u, 147u, 148u, 177u, 160u, 161u, 162u, 163u, 32u, 33u, 34u, 35u,
        36u, 37u, 48u, 49u, 50u, 51u, 52u, 53u, 192u, 193u, 194u, 195u, 196u, 65535u, 65535u, 65535u),
    uint[80](
        0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 176u, 164u, 64u, 65u, 66u, 67u, 68u, 69u,
        70u, 71u, 101u, 100u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 135u, 117u, 180u, 16u, 17u,
        18u, 19u, 20u, 116u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 84u, 85u, 112u, 113u,
        114u, 115u, 144u, 145u, 146u, 147u, 148u, 177u, 160u, 161u, 162u, 163u, 32u, 33u, 34u, 35u,
        36u, 178u, 48u, 49u, 50u, 51u, 52u, 179u, 192u, 193u, 194u, 195u, 196u, 65535u, 65535u, 65535u),
    uint[80](
        0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 177u, 164u, 64u, 65u, 66u, 67u, 68u, 69u,
        70u, 71u, 165u, 100u, 128u, 129u, 130u, 131u, 132u, 133u, 134u, 135u, 181u, 180u, 16u, 17u,
        18u, 19u, 20u, 116u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 84u, 176u, 112u, 113u,
        114u, 115u, 144u, 145u, 146u, 147u, 148u, 149u, 160u, 161u, 162u, 163u, 32u, 33u, 34u, 35u,
        36u, 178u, 48u, 49u, 50u, 51u, 52u, 179u, 192u, 193u, 194u, 195u, 196u, 65535u, 65535u, 65535u),
    uint[80](
        0u, 1u, 2u, 3u, 4u, 5u, 116u, 176u, 177u, 164u, 64u, 65u, 66u, 67u, 68u, 69u,
        101u, 165u, 178u, 100u, 128u, 129u, 130u, 131u, 132u, 133u, 117u, 179u, 181u, 180u, 16u, 17u,
        18u, 19u, 20u, 21u, 96u, 97u, 98u, 99u, 80u, 81u, 82u, 83u, 84u, 85u, 112u, 113u,
        114u, 115u, 144u, 145u, 146u, 147u, 148u, 149u, 160u, 161u, 162u, 163u, 32u, 33u, 34u, 35u,
        36u, 37u, 48u, 49u, 50u, 51u, 52u, 53u, 192u, 193u, 194u, 195u, 196u, 65535u, 65535u, 65535u));
// The 32 partitions: bit i is texel i's region. kAnchor1: region 1's anchor texel, whose index
// loses its top bit (region 0's is texel 0).
const uint kPartitions[32] = uint[32](0xCCCCu, 0x8888u, 0xEEEEu, 0xECC8u, 0xC880u, 0xFEECu, 0xFEC8u, 0xEC80u, 0xC800u, 0xFFECu, 0xFE80u,
                                      0xE800u, 0xFFE8u, 0xFF00u, 0xFFF0u, 0xF000u, 0xF710u, 0x008Eu, 0x7100u, 0x08CEu, 0x008Cu, 0x7310u,
                                      0x3100u, 0x8CCEu, 0x088Cu, 0x3110u, 0x6666u, 0x366Cu, 0x17E8u, 0x0FF0u, 0x718Eu, 0x399Cu);
const int kAnchor1[32] = int[32](15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 2, 8, 2, 2, 8, 8, 15, 2, 8, 2, 2, 8, 8,
                                 2, 2);

ivec3 texelHalves[16]; // the texels' half floats, as bit patterns

// Texel i in the interpolation's space (half bits * 64 / 31), where the endpoints are fitted.
vec3 texelValue(int i) { return vec3(texelHalves[i]) * (64.0 / 31.0); }

// The 16 indices, 4 bits each (so that a candidate holds few registers).
int indexAt(uvec2 indices, int i) { return int(((i < 8 ? indices.x : indices.y) >> uint(4 * (i & 7))) & 15u); }
void setIndex(inout uvec2 indices, int i, int value) {
    uint shift = uint(4 * (i & 7)), word = (i < 8 ? indices.x : indices.y) & ~(15u << shift) | (uint(value) << shift);
    if (i < 8) indices.x = word;
    else indices.y = word;
}

int halfBits(float value) { return int(packHalf2x16(vec2(clamp(value, 0.0, kHalfMax), 0.0)) & 0x7FFFu); }

// An endpoint in the interpolation's space (0 to 65535) as `bits` bits, and back, as the decoder
// unquantizes it.
ivec3 quantize(vec3 endpoint, int bits) {
    if (bits >= 15) return clamp(ivec3(round(endpoint)), 0, 65535);
    float step = float(1 << (16 - bits));
    return clamp(ivec3(round((endpoint - 0.5 * step) / step)), 0, (1 << bits) - 1);
}
ivec3 unquantize(ivec3 q, int bits) {
    if (bits >= 15) return q;
    int top = (1 << bits) - 1;
    ivec3 u = ((q << 16) + 0x8000) >> bits;
    return ivec3(q.x == 0 ? 0 : q.x == top ? 0xFFFF : u.x, q.y == 0 ? 0 : q.y == top ? 0xFFFF : u.y,
                 q.z == 0 ? 0 : q.z == top ? 0xFFFF : u.z);
}
// The half float bit patterns that stored endpoints q0, q1 decode to at weight w (of 64).
ivec3 decode(ivec3 u0, ivec3 u1, int w) { return (((u0 * (64 - w) + u1 * w + 32) >> 6) * 31) >> 6; }

// The least-squares line through the region's texels (`members`: bit i for texel i): its ends along
// the principal axis, ordered so that the anchor texel is nearer e0, and the texels' squared
// distance from it.
float fitLine(uint members, int anchor, out vec3 e0, out vec3 e1) {
    vec3 mean = vec3(0.0);
    float count = 0.0;
    for (int i = 0; i < 16; ++i)
        if (((members >> uint(i)) & 1u) != 0u) {
            mean += texelValue(i);
            count += 1.0;
        }
    mean /= max(count, 1.0);
    mat3 covariance = mat3(0.0);
    float spread = 0.0;
    for (int i = 0; i < 16; ++i)
        if (((members >> uint(i)) & 1u) != 0u) {
            vec3 d = texelValue(i) - mean;
            covariance += outerProduct(d, d);
            spread += dot(d, d);
        }
    vec3 axis = vec3(0.577);
    for (int k = 0; k < 8; ++k) {
        vec3 next = covariance * axis;
        float length2 = dot(next, next);
        if (length2 < 1e-12) break;
        axis = next * inversesqrt(length2);
    }
    float low = 3.4e38, high = -3.4e38, along = 0.0;
    for (int i = 0; i < 16; ++i)
        if (((members >> uint(i)) & 1u) != 0u) {
            float t = dot(texelValue(i) - mean, axis);
            low = min(low, t);
            high = max(high, t);
            along += t * t;
        }
    e0 = clamp(mean + low * axis, 0.0, 65535.0);
    e1 = clamp(mean + high * axis, 0.0, 65535.0);
    float t = dot(texelValue(anchor) - mean, axis);
    if (t - low > high - t) {
        vec3 e = e0;
        e0 = e1;
        e1 = e;
    }
    return max(spread - along, 0.0);
}

// Each member texel's nearest index among the palette of stored endpoints q0, q1 (`count` indices,
// 16 or 8); returns their error.
float chooseIndices(uint members, ivec3 q0, ivec3 q1, int bits, int count, inout uvec2 indices) {
    ivec3 u0 = unquantize(q0, bits), u1 = unquantize(q1, bits);
    ivec3 colours[16];
    for (int k = 0; k < count; ++k) colours[k] = decode(u0, u1, count == 16 ? kWeights4[k] : kWeights3[k]);
    float error = 0.0;
    for (int i = 0; i < 16; ++i) {
        if (((members >> uint(i)) & 1u) == 0u) continue;
        int best = 0;
        float bestError = kNone;
        for (int k = 0; k < count; ++k) {
            vec3 d = vec3(texelHalves[i] - colours[k]);
            float e = dot(d, d);
            if (e < bestError) {
                bestError = e;
                best = k;
            }
        }
        setIndex(indices, i, best);
        error += bestError;
    }
    return error;
}

// The region's endpoints that fit its texels best by least squares for their indices, in the
// interpolation's space (unchanged where the indices do not determine them).
void refine(uint members, uvec2 indices, int count, inout vec3 e0, inout vec3 e1) {
    float aa = 0.0, ab = 0.0, bb = 0.0;
    vec3 ax = vec3(0.0), bx = vec3(0.0);
    for (int i = 0; i < 16; ++i) {
        if (((members >> uint(i)) & 1u) == 0u) continue;
        int index = indexAt(indices, i);
        float b = float(count == 16 ? kWeights4[index] : kWeights3[index]) / 64.0, a = 1.0 - b;
        aa += a * a;
        ab += a * b;
        bb += b * b;
        ax += a * texelValue(i);
        bx += b * texelValue(i);
    }
    float det = aa * bb - ab * ab;
    if (det < 1e-6) return;
    e0 = clamp((ax * bb - bx * ab) / det, 0.0, 65535.0);
    e1 = clamp((bx * aa - ax * ab) / det, 0.0, 65535.0);
}

// A mode's endpoints as stored (q[0], q[1]: region 0; q[2], q[3]: region 1), the shape,
// indices and error.
struct Candidate {
    bool twoRegions;
    int mode;      // index into the one- or two-region tables
    int shape; // two regions: 0 to 31
    ivec3 q[4];
    uvec2 indices;
    float error;
};

int endpointBits(Candidate c) { return c.twoRegions ? kTwoEndpointBits[c.mode] : kOneEndpointBits[c.mode]; }
// Per channel: the offset bits of the endpoints after the first (0: stored whole).
ivec3 offsetBits(Candidate c) { return c.twoRegions ? kTwoOffsetBits[c.mode] : ivec3(kOneOffsetBits[c.mode]); }
int regionCount(Candidate c) { return c.twoRegions ? 2 : 1; }
int indexCount(Candidate c) { return c.twoRegions ? 8 : 16; }
// The texels of region r (bit i for texel i), and its anchor texel.
uint members(Candidate c, int r) {
    if (!c.twoRegions) return 0xFFFFu;
    return r == 0 ? ~kPartitions[c.shape] & 0xFFFFu : kPartitions[c.shape];
}
int anchor(Candidate c, int r) { return r == 0 ? 0 : kAnchor1[c.shape]; }

// Whether every endpoint is in range, and within the offsets' reach of the first.
bool storable(Candidate c) {
    int top = (1 << endpointBits(c)) - 1;
    ivec3 bits = offsetBits(c), reach = ivec3(1) << max(bits - 1, 0);
    for (int k = 0; k < 2 * regionCount(c); ++k) {
        if (any(lessThan(c.q[k], ivec3(0))) || any(greaterThan(c.q[k], ivec3(top)))) return false;
        ivec3 d = c.q[k] - c.q[0];
        if (k > 0 && bits.x > 0 && (any(lessThan(d, -reach)) || any(greaterThan(d, reach - 1)))) return false;
    }
    return true;
}

// The indices and error of the stored endpoints; each region's anchor index then loses its top bit
// (swapping the region's endpoints mirrors its indices, and the weights are symmetric, so its texels
// decode alike); kNone where the format cannot store the result.
void score(inout Candidate c) {
    int count = indexCount(c);
    c.error = 0.0;
    for (int r = 0; r < regionCount(c); ++r) {
        c.error += chooseIndices(members(c, r), c.q[2 * r], c.q[2 * r + 1], endpointBits(c), count, c.indices);
        if (indexAt(c.indices, anchor(c, r)) < count / 2) continue;
        ivec3 q = c.q[2 * r];
        c.q[2 * r] = c.q[2 * r + 1];
        c.q[2 * r + 1] = q;
        uint m = members(c, r);
        for (int i = 0; i < 16; ++i)
            if (((m >> uint(i)) & 1u) != 0u) setIndex(c.indices, i, count - 1 - indexAt(c.indices, i));
    }
    if (!storable(c)) c.error = kNone;
}

// The endpoints e (in the interpolation's space) quantized for the candidate's mode, every one after
// the first kept within the offsets' reach of it, and scored.
void quantizeAndScore(inout Candidate c, vec3 e[4]) {
    int bits = endpointBits(c), top = (1 << bits) - 1;
    ivec3 reach = ivec3(1) << max(offsetBits(c) - 1, 0);
    for (int k = 0; k < 2 * regionCount(c); ++k) {
        c.q[k] = quantize(e[k], bits);
        if (k > 0 && offsetBits(c).x > 0) c.q[k] = clamp(c.q[k], max(c.q[0] - reach, 0), min(c.q[0] + reach - 1, top));
    }
    score(c);
}

// The best encoding in the candidate's mode (and shape) from the fitted endpoints: two rounds of
// least squares for the indices chosen.
Candidate fit(Candidate c, vec3 e[4]) {
    Candidate best = c;
    best.error = kNone;
    for (int pass = 0; pass < 2; ++pass) {
        quantizeAndScore(c, e);
        for (int r = 0; r < regionCount(c); ++r) refine(members(c, r), c.indices, indexCount(c), e[2 * r], e[2 * r + 1]);
        if (c.error < best.error) best = c;
    }
    return best;
}

// Then each stored component a step either way, while that lowers the error.
Candidate polish(Candidate best) {
    for (int round = 0; round < 2 && best.error < kNone; ++round)
        for (int k = 0; k < 6 * regionCount(best); ++k)
            for (int step = -1; step <= 1; step += 2) {
                Candidate trial = best;
                trial.q[k / 3][k % 3] += step;
                if (!storable(trial)) continue;
                score(trial);
                if (trial.error < best.error) best = trial;
            }
    return best;
}

uint packed[4];
uint position;

// `count` bits of `value`, lowest first, from the current position.
void put(uint value, int count) {
    for (int b = 0; b < count; ++b) {
        packed[position >> 5] |= ((value >> uint(b)) & 1u) << (position & 31u);
        ++position;
    }
}
// Bits `high` down to `low` of `value`: the order the format stores an endpoint's top bits in, in
// modes 13 and 14.
void putReversed(uint value, int high, int low) {
    for (int b = high; b >= low; --b) put(value >> uint(b), 1);
}

uvec4 encodeOneRegion(Candidate c) {
    put(kOneModeBits[c.mode], 5);
    uvec3 w = uvec3(c.q[0]), x = uvec3(c.q[1] - (c.mode > 0 ? c.q[0] : ivec3(0)));
    for (int k = 0; k < 3; ++k) put(w[k], 10);
    for (int k = 0; k < 3; ++k) {
        switch (c.mode) {
        case 0: put(x[k], 10); break;
        case 1:
            put(x[k], 9);
            put(w[k] >> 10u, 1);
            break;
        case 2:
            put(x[k], 8);
            putReversed(w[k], 11, 10);
            break;
        default:
            put(x[k], 4);
            putReversed(w[k], 15, 10);
            break;
        }
    }
    put(uint(indexAt(c.indices, 0)), 3);
    for (int i = 1; i < 16; ++i) put(uint(indexAt(c.indices, i)), 4);
    return uvec4(packed[0], packed[1], packed[2], packed[3]);
}

uvec4 encodeTwoRegions(Candidate c) {
    put(kTwoModeBits[c.mode], kTwoModeBitCount[c.mode]);
    for (int e = 0; e < 80; ++e) {
        uint entry = kTwoLayout[c.mode][e];
        if (entry == 65535u) break;
        uint field = entry >> 4u, bit = entry & 15u;
        uint value = uint(c.shape);
        if (field < 12u) {
            int channel = int(field / 4u), endpoint = int(field % 4u);
            int stored = c.q[endpoint][channel] - (endpoint > 0 && kTwoOffsetBits[c.mode].x > 0 ? c.q[0][channel] : 0);
            value = uint(stored);
        }
        put(value >> bit, 1);
    }
    for (int i = 0; i < 16; ++i) put(uint(indexAt(c.indices, i)), i == 0 || i == kAnchor1[c.shape] ? 2 : 3);
    return uvec4(packed[0], packed[1], packed[2], packed[3]);
}

void main() {
    if (gl_GlobalInvocationID.x >= params.blockCount) return;
    uint block = params.firstBlock + gl_GlobalInvocationID.x;
    // The block's level, face and position.
    uint first = 0u, texelFirst = 0u;
    int size = params.faceSize;
    for (int level = 0; level < params.levelCount - 1; ++level) {
        uint across = uint((size + 3) / 4), count = 6u * across * across;
        if (block < first + count) break;
        first += count;
        texelFirst += 6u * uint(size * size);
        size = max(size / 2, 1);
    }
    uint across = uint((size + 3) / 4), inLevel = block - first;
    uint face = inLevel / (across * across), row = (inLevel / across) % across, column = inLevel % across;
    for (int i = 0; i < 16; ++i) {
        int x = min(int(column) * 4 + (i & 3), size - 1), y = min(int(row) * 4 + (i >> 2), size - 1);
        vec3 value = texel(texelFirst + face * uint(size * size) + uint(y * size + x) - params.texelBase);
        texelHalves[i] = ivec3(halfBits(value.r), halfBits(value.g), halfBits(value.b));
    }

    vec3 e[4];
    fitLine(0xFFFFu, 0, e[0], e[1]);
    e[2] = e[0];
    e[3] = e[1];
    Candidate best;
    best.error = kNone;
    // The modes compared after their least-squares fit; the best one polished.
    for (int mode = 0; mode < 4; ++mode) {
        Candidate c;
        c.twoRegions = false;
        c.mode = mode;
        c.shape = 0;
        c = fit(c, e);
        if (c.error < best.error) best = c;
    }
    best = polish(best);
    if (best.error > kTwoRegionError) {
        // Every shape, each mode fitted to it; the best one polished.
        Candidate two;
        two.error = kNone;
        for (int shape = 0; shape < 32; ++shape) {
            fitLine(~kPartitions[shape] & 0xFFFFu, 0, e[0], e[1]);
            fitLine(kPartitions[shape], kAnchor1[shape], e[2], e[3]);
            for (int mode = 0; mode < 10; ++mode) {
                Candidate c;
                c.twoRegions = true;
                c.mode = mode;
                c.shape = shape;
                c = fit(c, e);
                if (c.error < two.error) two = c;
            }
        }
        two = polish(two);
        if (two.error < best.error) best = two;
    }
    packed = uint[4](0u, 0u, 0u, 0u);
    position = 0u;
    blocks[block] = best.twoRegions ? encodeTwoRegions(best) : encodeOneRegion(best);
}
