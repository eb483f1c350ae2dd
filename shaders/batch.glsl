// A batch (FilterSettings::batchSize): the probes one recording filters, kept as the cubes of
// cube-map arrays, cube c in layers 6c to 6c + 5. Each invocation works on one cube, batchCube, which
// main() sets from its workgroup (or its layer) before it reads or writes anything.
#ifndef PROBE_BATCH_GLSL
#define PROBE_BATCH_GLSL

// The cubes of the batch (the runtime's kBatchSizeConstant): 1 outside a batch.
layout(constant_id = 15) const int kBatchSize = 1;

int batchCube = 0;

// A texel (i, j, face) of the invocation's cube as image coordinates (i, j, layer) of the array.
ivec3 batchLayer(ivec3 texel) { return ivec3(texel.xy, texel.z + 6 * batchCube); }

#endif
