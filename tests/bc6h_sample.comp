// Every texel of a BC6H cube as the device's texture unit decodes it: level after level, the faces,
// each row-major, as RGBA32F (tests/bc6h_sample.cpp).
#version 450

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) writeonly buffer Texels { vec4 texels[]; };
layout(set = 0, binding = 1) uniform sampler2DArray blocks; // the faces as layers, every mip

layout(push_constant) uniform Params {
    int faceSize;
    int levelCount;
    uint texelCount; // of every level
} params;

void main() {
    uint t = gl_GlobalInvocationID.x;
    if (t >= params.texelCount) return;
    uint first = 0u;
    int size = params.faceSize, level = 0;
    for (; level < params.levelCount - 1; ++level) {
        uint count = 6u * uint(size * size);
        if (t < first + count) break;
        first += count;
        size = max(size / 2, 1);
    }
    uint k = t - first, faceTexels = uint(size * size), r = k % faceTexels;
    ivec3 at = ivec3(int(r % uint(size)), int(r / uint(size)), int(k / faceTexels));
    texels[t] = vec4(texelFetch(blocks, at, level).rgb, 1.0);
}
