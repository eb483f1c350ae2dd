// Pass 1's dispatches whose last workgroup finishes what the others wrote (pyramid.comp's border
// corners): the workgroups count themselves in a counter of binding 9
// (probe runtime's kPyramidCounters, 0 between dispatches), in the manner of AMD's single-pass
// downsampler.
#ifndef PROBE_WORKGROUP_COUNT_GLSL
#define PROBE_WORKGROUP_COUNT_GLSL

layout(std430, set = 0, binding = 9) coherent buffer PyramidCounters { uint pyramidCounters[]; };

shared uint workgroupsBefore;

// Called by every invocation once its stores are made visible (the caller's memoryBarrier*): true in
// the last of the dispatch's workgroups to count itself in pyramidCounters[counter], when every other
// one's stores are visible; that workgroup sets the counter back to 0 for the next dispatch.
bool lastWorkgroup(uint counter) {
    barrier();
    if (gl_LocalInvocationIndex == 0u) workgroupsBefore = atomicAdd(pyramidCounters[counter], 1u);
    barrier();
    bool last = workgroupsBefore + 1u == gl_NumWorkGroups.x * gl_NumWorkGroups.y;
    if (last && gl_LocalInvocationIndex == 0u) pyramidCounters[counter] = 0u;
    return last;
}

#endif
