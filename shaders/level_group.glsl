// Pass 2 over a group of up to four consecutive output levels in one dispatch (the runtime's
// FilterPlan::levelGroups), so that small levels share a grid instead of each paying a dispatch: the
// levels' workgroups follow one another, level firstLevel + slot ending at groupEnd[slot] (the
// unused slots repeat the last end), and each level writes outputMips[slot] (images.glsl).
#ifndef PROBE_LEVEL_GROUP_GLSL
#define PROBE_LEVEL_GROUP_GLSL

// The slot of this workgroup's level (4: past the group's end) and its workgroup index within that
// level's, from the flattened workgroup index (dispatches of more than 65535 workgroups go over y).
uint levelSlot(uint groupEnd[4], out uint groupInLevel) {
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x, slot = 0u, start = 0u;
    while (slot < 4u && group >= groupEnd[slot]) {
        start = groupEnd[slot];
        ++slot;
    }
    groupInLevel = group - start;
    return slot;
}

// The invocation's index within its level's invocations.
uint invocationInLevel(uint groupInLevel) { return groupInLevel * uint(PROBE_WORKGROUP_SIZE) + gl_LocalInvocationID.x; }

#endif
