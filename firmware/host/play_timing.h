/* play_timing.h - how `lmsego play` times and orders a recording's scans
 * (host-only; used by cmd_sim.c, tested by test_recording).
 *
 * A recording holds the time each read returned on the recording host, not
 * the time each telegram left the scanner: a host that was busy for 100 ms
 * reads the scans of those 100 ms at once, late. Played back as recorded,
 * that delay becomes 100 ms of silence on the wire, which a driver rightly
 * takes for a lost link. An LMS 2xx sends at most one scan per mirror
 * rotation (1/75 s), so a scan left no later than one rotation before the
 * next one arrived: the wire times are the read times moved back to that
 * bound. A real outage (no scans read for a while, then the usual one per
 * rotation) stays as long as it was.
 */
#ifndef LMSEGO_PLAY_TIMING_H
#define LMSEGO_PLAY_TIMING_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* One mirror rotation of an LMS 2xx at 75 Hz, in us (rounded down). */
#define PLAY_ROTATION_US 13333u
/* A longer gap is played as this long (a recording paused for minutes). */
#define PLAY_GAP_MAX_US 10000000u

/* Telegrams 0 .. n-1 arrived at time_us[k] (rising). Turns those read
 * times, in place, into the times they left the scanner: the last stays,
 * and time_us[k] = min(time_us[k], time_us[k+1] - PLAY_ROTATION_US) (not
 * below 0). Writes the gaps between them: gap_us[0] = 0, gap_us[k] =
 * time_us[k] - time_us[k-1], at most PLAY_GAP_MAX_US (at least one
 * rotation, but where the clamp at 0 shortened it). */
void play_wire_gaps(uint64_t *time_us, uint32_t *gap_us, size_t n);

/* Which recorded scan is next. The simulator numbers the scans of each
 * stream from 0 (lms_sim_scan_fn's k) and asks for scan k+1 as soon as
 * scan k has left, so when a new stream asks for 0, the last scan asked
 * for never left: a restarted stream resumes there. A scanner's world goes
 * on when its host restarts; a recording played from its start after
 * every restart would replay one outage forever. */
typedef struct {
    uint64_t base;    /* recorded index of the current stream's scan 0 */
    uint32_t last_k;  /* the last k asked for */
    bool asked;       /* any k asked for yet */
} play_cursor_t;

/* The recorded index (counting on past the end when looped: the caller
 * takes it modulo the count) of scan k of the current stream. */
uint64_t play_cursor_index(play_cursor_t *cursor, uint32_t k);

#endif
