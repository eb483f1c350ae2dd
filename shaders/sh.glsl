// The order-2 real SH basis of core's probe/sh.h (same order and signs, constants from
// probe/shared_constants.h): 0 Y00, 1 Y1-1 (y), 2 Y10 (z), 3 Y11 (x), 4 Y2-2 (xy), 5 Y2-1 (yz),
// 6 Y20 (3z^2 - 1), 7 Y21 (xz), 8 Y22 (x^2 - y^2), for a unit direction.
#ifndef PROBE_SH_GLSL
#define PROBE_SH_GLSL

#include "probe/shared_constants.h"

#define PROBE_SH_COUNT 9

void shBasis(vec3 n, out float y[PROBE_SH_COUNT]) {
    y[0] = float(PROBE_SH_C0);
    y[1] = float(PROBE_SH_C1) * n.y;
    y[2] = float(PROBE_SH_C1) * n.z;
    y[3] = float(PROBE_SH_C1) * n.x;
    y[4] = float(PROBE_SH_C2) * n.x * n.y;
    y[5] = float(PROBE_SH_C2) * n.y * n.z;
    y[6] = float(PROBE_SH_C20) * (3.0 * n.z * n.z - 1.0);
    y[7] = float(PROBE_SH_C2) * n.x * n.z;
    y[8] = float(PROBE_SH_C22) * (n.x * n.x - n.y * n.y);
}

#endif
