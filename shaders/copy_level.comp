// Pass 2 at an output level with alpha = 0, for every method: each texel is a copy of the source
// texel that contains its centre (docs/design.md: alpha = 0 means a copy), mirroring core's tap_sum.h.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "cube.glsl"
#include "images.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

layout(push_constant) uniform Params {
    int faceSize;    // S_0
    int level;       // the output level of this dispatch
    uint firstTexel; // the packed output texels [firstTexel, endTexel) of the level
    uint endTexel;
} params;

void main() {
    uint index = params.firstTexel + invocationIndex();
    batchCube = int(gl_WorkGroupID.z); // a layer of workgroups per cube of a batch
    if (index >= params.endTexel) return;
    // The source texel that holds the texel's centre (computed: the nearest read needs no more).
    int size = params.faceSize >> params.level;
    ivec3 t = texelCoordinates(index - params.firstTexel, size);
    storeOutput(t, sourceTexel(texelCubePoint(t.z, t.x, t.y, size)));
}
