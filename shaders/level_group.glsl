// Pass 2 over a group of consecutive output levels in one dispatch (the runtime's
// FilterPlan::levelGroups): up to PROBE_LEVEL_GROUP_WIDTH of them, the storage images the shader
// declares (images.glsl: 4, which every device offers, or PROBE_MAX_GROUP_LEVELS, every level in
// one), so that small levels share a grid instead of each paying a dispatch. The levels' workgroups
// follow one another, level firstLevel + slot ending at groupEnd[slot] (the unused slots repeat the
// last end), and each level writes outputMips[slot].
#ifndef PROBE_LEVEL_GROUP_GLSL
#define PROBE_LEVEL_GROUP_GLSL

// The slot of this workgroup's level (PROBE_LEVEL_GROUP_WIDTH: past the group's end) and its
// workgroup index within that level's, from the flattened workgroup index (dispatches of more than
// 65535 workgroups go over y).
uint levelSlot(uint groupEnd[PROBE_MAX_GROUP_LEVELS], out uint groupInLevel) {
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x, slot = 0u, start = 0u;
    while (slot < uint(PROBE_LEVEL_GROUP_WIDTH) && group >= groupEnd[slot]) {
        start = groupEnd[slot];
        ++slot;
    }
    groupInLevel = group - start;
    return slot;
}

// The invocation's index within its level's invocations.
uint invocationInLevel(uint groupInLevel) { return groupInLevel * uint(PROBE_WORKGROUP_SIZE) + gl_LocalInvocationID.x; }

#endif
