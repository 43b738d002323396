/* play_timing.c - see play_timing.h. */
#include "play_timing.h"

void play_wire_gaps(uint64_t *time_us, uint32_t *gap_us, size_t n)
{
    for (size_t i = n; i-- > 1u;) {
        const uint64_t bound = time_us[i] >= PLAY_ROTATION_US ? time_us[i] - PLAY_ROTATION_US : 0u;
        if (time_us[i - 1u] > bound) {
            time_us[i - 1u] = bound; /* read late: the host was busy */
        }
    }
    for (size_t i = 0u; i < n; i++) {
        const uint64_t gap = i == 0u ? 0u : time_us[i] - time_us[i - 1u];
        gap_us[i] = gap > PLAY_GAP_MAX_US ? PLAY_GAP_MAX_US : (uint32_t)gap;
    }
}

uint64_t play_cursor_index(play_cursor_t *cursor, uint32_t k)
{
    if (k == 0u && cursor->asked) {
        cursor->base += cursor->last_k; /* scan last_k never left */
    }
    cursor->asked = true;
    cursor->last_k = k;
    return cursor->base + k;
}
