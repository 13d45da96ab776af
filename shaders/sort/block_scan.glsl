// Workgroup-wide exclusive sum of one uint per invocation, in shared memory only (no subgroup
// operations, so it is the same on any subgroup size). Raking: PG_SORT_RAKE invocations each
// scan a row of PG_SORT_RAKE values, one scans the row sums, everybody adds its row's offset.
// Three barriers (each costs about a microsecond per workgroup on lavapipe, more than the
// serial work). Must be called in uniform control flow by all PG_SORT_THREADS invocations;
// s_scan must not be written again before the caller's next barrier.
#ifndef PG_SORT_BLOCK_SCAN_GLSL
#define PG_SORT_BLOCK_SCAN_GLSL
#include "sort/sort_config.h"

#define PG_SORT_RAKE 16  // PG_SORT_RAKE^2 == PG_SORT_THREADS

shared uint s_scan[PG_SORT_THREADS];
shared uint s_rake[PG_SORT_RAKE + 1];

uint pg_block_exclusive_scan(uint value, out uint total) {
    uint t = gl_LocalInvocationIndex;
    s_scan[t] = value;
    barrier();
    if (t < PG_SORT_RAKE) {
        uint sum = 0u;
        for (uint i = 0u; i < PG_SORT_RAKE; ++i) {
            uint x = s_scan[t * PG_SORT_RAKE + i];
            s_scan[t * PG_SORT_RAKE + i] = sum;
            sum += x;
        }
        s_rake[t] = sum;
    }
    barrier();
    if (t == 0u) {
        uint sum = 0u;
        for (uint i = 0u; i < PG_SORT_RAKE; ++i) {
            uint x = s_rake[i];
            s_rake[i] = sum;
            sum += x;
        }
        s_rake[PG_SORT_RAKE] = sum;
    }
    barrier();
    total = s_rake[PG_SORT_RAKE];
    return s_scan[t] + s_rake[t / PG_SORT_RAKE];
}
#endif
