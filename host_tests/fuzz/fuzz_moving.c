/* fuzz_moving.c - libFuzzer target over the moving clusters of a range
 * scan (estimator/ego_moving.h) through their one input, ego_moving_scan:
 * sequences of range scans that pass ego_range_check (the estimator
 * refuses the others, so ego_moving never sees them), each with the line
 * the estimator gave out for it (pose, flags, covariance: any values, a
 * variance at least 0), at any time step, with any capacity of objects.
 *
 * Input: byte 0 is the setup: bit 0 a bearing table (else uniform
 * bearings), bits 1-2 the sensor's origin (none; +-4 m, +-128 m or any
 * int32, from two values in the input), bits 3-4 the range unit (10000,
 * 1000, 250 um, or 1 + u32 % 500000 from the input), bit 5 the poses'
 * translations any int32 (else cut to +-4 m). Then up to 12 scans, each:
 *   u8   count: 1 + c % 181 beams, or c == 255: EGO_MAX_BEAMS (the
 *        capacity; the ranges given repeat), c == 254: 0 beams
 *   u8   options: bit 0 the ranges given are the last scan's (none read:
 *        a scene that stays put), bits 1-2 patches (0..3), bit 3 flags
 *        from the input (else 0), bit 4 a covariance from the input (else
 *        0)
 *   u8   cap: EGO_MOVING_MAX_OBJECTS - v % (EGO_MOVING_MAX_OBJECTS + 1)
 *   u8   sweep: 1 + v 256ths of a turn, spread over the beams
 *   u32  time step in us (any: 0, jumps, wrap-around)
 *   u32  first bearing (a binary angle)
 *   with a table: u8 warp (the steps between beams weigh 1..4 by the
 *        beam's index times warp; 0: uniform)
 *   u16  per beam up to 181 (unless bit 0): the range in units (0: none)
 *   per patch: u16 first beam (% count), u8 beams, u16 range: those
 *        beams of this scan only (a body in front of the scene)
 *   with bit 3: u16 flags (any EGO_FLAG_* bits)
 *   u32  theta, i32 x, i32 y: the pose (x, y cut to +-4 m unless setup
 *        bit 5)
 *   with bit 4: i32 xx, xy, xt, yy, yt, tt: the covariance, the variances
 *        xx, yy, tt with the sign bit cleared (>= 0, EGO_COV_SATURATED
 *        reachable; the estimator gives no negative variance)
 * A missing byte reads as 0. A scan that fails ego_range_check (a step
 * of half a turn or more, more than a turn in all) is skipped; its time
 * step still counts. At most 181 values are read a scan, so that an input
 * stays short (12 scans of a kept scene take about 300 bytes; the runs
 * cap inputs at 4 kB).
 *
 * Checks (abort on violation), for every scan fed:
 *  - the return is at most cap (and at most EGO_MOVING_MAX_OBJECTS);
 *    nothing is written past cap (the objects are a heap array of cap + 1
 *    whose last element must stay as it was, and ASan sees past it);
 *  - a line without a measured motion (FIRST, PREDICTED, RECOVERING,
 *    RECOVERED), an interval of 0 or over EGO_MOVING_MAX_DT_US, and the
 *    first scan fed start everything over: no object; and no object
 *    until the third scan after such a restart and 0.2 s
 *    (EGO_MOVING_REF_MIN_US) after it (a track is reported from its third
 *    sighting; a sighting needs a reference that old);
 *  - every object: id in 1 .. EGO_MOVING_CLUSTERS times the scans since
 *    the restart (ids count from 1 after a reset, a scan starts at most
 *    EGO_MOVING_CLUSTERS tracks), the ids of one scan distinct;
 *    EGO_MOVING_MIN_POINTS <= points <= the scan's count; vx_cms and
 *    vy_cms both EGO_MOVING_UNKNOWN or neither; length_cm and width_cm at
 *    most 70 m (the points lie within EGO_MOVING_MAX_RANGE of the
 *    origin); the box centre within 35 sqrt(2) m of the origin (when the
 *    origin is within 250 m, so that centimetres do not saturate);
 *  - the work (units, public): at most EGO_MOVING_UNITS_PER_BEAM a beam
 *    for the evidence tests, plus the last test's (at most
 *    EGO_MOVING_UNITS_TEST_MAX),
 *    plus a unit per point of each box: the moving clusters' (disjoint
 *    segments: at most the count) and the hold's (at most two segments
 *    for each of EGO_MOVING_TRACKS tracks); so at most
 *    (EGO_MOVING_UNITS_PER_BEAM + 1 + 2 EGO_MOVING_TRACKS) count +
 *    EGO_MOVING_UNITS_TEST_MAX;
 *  - the scan's arrays and the line are not written (const);
 *  - determinism and cap: a second state fed the same scans with cap
 *    EGO_MOVING_MAX_OBJECTS returns n2 objects; the first returns
 *    min(cap, n2), byte for byte the first of them (cap bounds what is
 *    written, never what is tracked);
 *  - no crash, no undefined behaviour (ASan, UBSan).
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ego.h"
#include "ego_moving.h"
#include "ego_range.h"
#include "fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Enough for a track to be dropped: a restart, a sighting 0.2 s later,
 * then EGO_MOVING_MAX_MISSES + 1 misses. */
#define MAX_SCANS 12u
#define MAX_GIVEN 181u
#define MAX_PATCHES 3u
/* Pose translations are cut to +-4 m (Q16.16). */
#define POSE_LIMIT (4 * 65536)
/* ego_moving.h: the lines that start everything over. */
#define UNMEASURED (EGO_FLAG_FIRST | EGO_FLAG_PREDICTED | EGO_FLAG_RECOVERING | EGO_FLAG_RECOVERED)
/* ego_moving.h: the most one evidence test costs (the last test of a
 * scan may cross the scan's limit by this). */
#define LAST_TEST_UNITS EGO_MOVING_UNITS_TEST_MAX
/* Points within EGO_MOVING_MAX_RANGE (35 m) of the origin: lengths at
 * most 70 m, a box centre within 35 sqrt(2) = 49.50 m of it; a few cm to
 * spare for the sines' and the roundings' last places. */
#define MAX_SIZE_CM 7005
#define MAX_CENTRE_CM 4955
#define CENTRE_ORIGIN_LIMIT (250 * 65536)

static int64_t abs64(int64_t v)
{
    return (v < 0) ? -v : v;
}

/* The count byte: 1 + c % 181 beams, 255 the capacity (the ranges given
 * repeat), 254 none. */
static uint16_t beams_of(uint8_t c)
{
    if (c == 255u) {
        return (uint16_t)EGO_MAX_BEAMS;
    }
    return (c == 254u) ? 0u : (uint16_t)(1u + c % MAX_GIVEN);
}

/* The ranges a scan of count beams reads (the rest repeat them). */
static uint16_t given_of(uint16_t count)
{
    return (count < MAX_GIVEN) ? count : (uint16_t)MAX_GIVEN;
}

/* The checks of one scan's objects (the header's list). */
static void check_objects(const ego_moving_object_t *o, uint8_t n, const ego_range_scan_t *scan,
                          uint32_t since_restart, bool centre_check)
{
    for (uint8_t i = 0u; i < n; i++) {
        FUZZ_CHECK(o[i].id != 0u && o[i].id <= EGO_MOVING_CLUSTERS * since_restart);
        for (uint8_t k = 0u; k < i; k++) {
            FUZZ_CHECK(o[k].id != o[i].id);
        }
        FUZZ_CHECK(o[i].points >= EGO_MOVING_MIN_POINTS && o[i].points <= scan->count);
        FUZZ_CHECK((o[i].vx_cms == EGO_MOVING_UNKNOWN) == (o[i].vy_cms == EGO_MOVING_UNKNOWN));
        FUZZ_CHECK(o[i].length_cm <= MAX_SIZE_CM && o[i].width_cm <= MAX_SIZE_CM);
        if (centre_check) {
            /* The origin in cm, rounded as cm_of rounds. */
            const int64_t ox = (abs64(scan->origin_x) * 100 + 32768) / 65536 * ((scan->origin_x < 0) ? -1 : 1);
            const int64_t oy = (abs64(scan->origin_y) * 100 + 32768) / 65536 * ((scan->origin_y < 0) ? -1 : 1);
            const int64_t dx = o[i].cx_cm - ox;
            const int64_t dy = o[i].cy_cm - oy;
            FUZZ_CHECK(dx * dx + dy * dy <= (int64_t)MAX_CENTRE_CM * MAX_CENTRE_CM);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static ego_moving_t state;
    static ego_moving_t twin; /* fed the same scans, cap EGO_MOVING_MAX_OBJECTS */
    static const uint32_t units[3] = {10000u, 1000u, 250u};
    static uint16_t given_ranges[MAX_GIVEN]; /* the scene, kept from scan to scan */
    if (size < 1u) {
        return 0;
    }
    fuzz_input_t in = {data, size, 1u};
    const uint8_t setup = data[0];
    const bool with_table = (setup & 1u) != 0u;
    const unsigned origin_pick = (setup >> 1) & 3u;
    const unsigned unit_pick = (setup >> 3) & 3u;
    const bool raw_pose = (setup & 32u) != 0u;
    /* Every input starts from states that never ran, so that an input
     * gives the same outputs whatever ran before it. */
    memset(&state, 0, sizeof state);
    memset(&twin, 0, sizeof twin);
    ego_moving_reset(&state);
    ego_moving_reset(&twin);
    memset(given_ranges, 0, sizeof given_ranges);
    const uint32_t unit_um = (unit_pick < 3u) ? units[unit_pick] : 1u + fuzz_take(&in, 4u) % 500000u;
    fx_q16_16_t ox = 0;
    fx_q16_16_t oy = 0;
    if (origin_pick == 1u || origin_pick == 2u) {
        const int32_t scale = (origin_pick == 1u) ? 8 : 256; /* +-4 m, +-128 m */
        ox = (fx_q16_16_t)(((int32_t)fuzz_take(&in, 2u) - 32768) * scale);
        oy = (fx_q16_16_t)(((int32_t)fuzz_take(&in, 2u) - 32768) * scale);
    } else if (origin_pick == 3u) {
        ox = (fx_q16_16_t)fuzz_take(&in, 4u);
        oy = (fx_q16_16_t)fuzz_take(&in, 4u);
    }
    const bool centre_check = abs64(ox) <= CENTRE_ORIGIN_LIMIT && abs64(oy) <= CENTRE_ORIGIN_LIMIT;
    uint32_t time_us = 0u;
    uint32_t last_fed_us = 0u; /* ego_moving_reset: time 0 */
    bool fed = false;
    uint32_t since_restart = 0u;  /* scans fed since the last restart */
    uint64_t restart_age_us = 0u; /* time since it (each interval <= 1 s) */
    uint16_t given = 0u;
    for (unsigned s = 0u; s < MAX_SCANS && in.pos < in.size; s++) {
        const uint8_t c = (uint8_t)fuzz_take(&in, 1u);
        const uint8_t options = (uint8_t)fuzz_take(&in, 1u);
        const uint8_t cap = (uint8_t)(EGO_MOVING_MAX_OBJECTS - fuzz_take(&in, 1u) % (EGO_MOVING_MAX_OBJECTS + 1u));
        const uint8_t sweep_v = (uint8_t)fuzz_take(&in, 1u);
        time_us += fuzz_take(&in, 4u);
        const uint32_t first = fuzz_take(&in, 4u);
        const uint8_t warp = with_table ? (uint8_t)fuzz_take(&in, 1u) : 0u;
        const uint16_t count = beams_of(c);
        const uint16_t want = given_of(count);
        if ((options & 1u) == 0u) {
            for (uint16_t k = 0u; k < want; k++) {
                given_ranges[k] = (uint16_t)fuzz_take(&in, 2u);
            }
            given = want;
        } else if (given < want) {
            given = want; /* the scene's values beyond the last scan's: as left (0 at first) */
        }
        /* Arrays of exactly count elements on the heap: ASan reports a read
         * past the scan's last beam. */
        uint16_t *range = malloc(((count > 0u) ? count : 1u) * sizeof *range);
        fx_bam32_t *table = malloc(((count > 0u) ? count : 1u) * sizeof *table);
        FUZZ_CHECK(range != NULL && table != NULL);
        for (uint16_t k = 0u; k < count; k++) {
            range[k] = given_ranges[k % given];
        }
        const unsigned patches = (options >> 1) & 3u;
        for (unsigned p = 0u; p < patches; p++) {
            const uint32_t at = fuzz_take(&in, 2u);
            const uint32_t beams = fuzz_take(&in, 1u);
            const uint16_t value = (uint16_t)fuzz_take(&in, 2u);
            for (uint32_t k = 0u; count > 0u && k < beams; k++) {
                const uint32_t b = (at % count) + k;
                if (b < count) {
                    range[b] = value;
                }
            }
        }
        ego_range_scan_t scan;
        memset(&scan, 0, sizeof scan);
        scan.count = count;
        scan.range = range;
        scan.range_unit_um = unit_um;
        scan.origin_x = ox;
        scan.origin_y = oy;
        scan.first_bearing = EGO_BEARING_Q32(first);
        /* The sweep, 1..256 256ths of a turn less a unit of the last place
         * (Q32.32: (1 + v) << 56, a whole turn wrapping to 0, minus 1),
         * spread over count - 1 steps. */
        const uint64_t steps = (count > 1u) ? (uint64_t)(count - 1u) : 1u;
        scan.bearing_step = ((((uint64_t)sweep_v + 1u) << 56) - 1u) / steps;
        if (with_table) {
            /* Beam k at first + sweep * (the weights up to it) / (all of
             * them): increasing, the steps in proportion 1..4. */
            const uint64_t turn = ((uint64_t)sweep_v + 1u) << 24; /* binary angle, up to 2^32 */
            uint64_t total = 0u;
            for (uint16_t k = 1u; k < count; k++) {
                total += 1u + (((uint32_t)k * warp >> 4) & 3u);
            }
            uint64_t sum = 0u;
            table[0] = first;
            for (uint16_t k = 1u; k < count; k++) {
                sum += 1u + (((uint32_t)k * warp >> 4) & 3u);
                table[k] = first + (fx_bam32_t)((turn - 1u) * sum / total);
            }
            scan.bearing = table;
        }
        const uint16_t flags = ((options & 8u) != 0u) ? (uint16_t)fuzz_take(&in, 2u) : 0u;
        ego_output_t out;
        memset(&out, 0, sizeof out);
        out.flags = flags;
        out.pose.theta = fuzz_take(&in, 4u);
        out.pose.x = (fx_q16_16_t)fuzz_take(&in, 4u);
        out.pose.y = (fx_q16_16_t)fuzz_take(&in, 4u);
        if (!raw_pose) {
            out.pose.x %= POSE_LIMIT;
            out.pose.y %= POSE_LIMIT;
        }
        if ((options & 16u) != 0u) {
            out.cov.xx = (fx_q2_30_t)(fuzz_take(&in, 4u) & 0x7FFFFFFFu);
            out.cov.xy = (fx_q2_30_t)fuzz_take(&in, 4u);
            out.cov.xt = (fx_q2_30_t)fuzz_take(&in, 4u);
            out.cov.yy = (fx_q2_30_t)(fuzz_take(&in, 4u) & 0x7FFFFFFFu);
            out.cov.yt = (fx_q2_30_t)fuzz_take(&in, 4u);
            out.cov.tt = (fx_q2_30_t)(fuzz_take(&in, 4u) & 0x7FFFFFFFu);
        }
        out.dt_us = time_us - last_fed_us;
        if (!ego_range_check(&scan)) {
            free(range);
            free(table);
            continue;
        }
        /* What the call must not write, and the objects: cap + 1 of them,
         * the last one a canary. */
        uint16_t range_copy[EGO_MAX_BEAMS];
        fx_bam32_t table_copy[EGO_MAX_BEAMS];
        memcpy(range_copy, range, count * sizeof *range);
        memcpy(table_copy, table, count * sizeof *table);
        const ego_output_t out_copy = out;
        ego_moving_object_t *objects = malloc(((size_t)cap + 1u) * sizeof *objects);
        FUZZ_CHECK(objects != NULL);
        memset(objects, 0xA5, ((size_t)cap + 1u) * sizeof *objects);
        ego_moving_object_t canary;
        memset(&canary, 0xA5, sizeof canary);
        ego_moving_object_t all[EGO_MOVING_MAX_OBJECTS];

        const uint32_t dt = time_us - last_fed_us;
        const bool restart = !fed || (flags & UNMEASURED) != 0u || dt == 0u || dt > EGO_MOVING_MAX_DT_US;
        if (restart) {
            since_restart = 0u;
            restart_age_us = 0u;
        } else {
            since_restart++;
            restart_age_us += dt;
        }
        fed = true;
        last_fed_us = time_us;

        const uint8_t n = ego_moving_scan(&state, &scan, time_us, &out, objects, cap);
        const uint8_t n2 = ego_moving_scan(&twin, &scan, time_us, &out, all, (uint8_t)EGO_MOVING_MAX_OBJECTS);

        FUZZ_CHECK(n <= cap && n2 <= EGO_MOVING_MAX_OBJECTS);
        FUZZ_CHECK(state.units == twin.units &&
                   state.units <= (EGO_MOVING_UNITS_PER_BEAM + 1u + 2u * EGO_MOVING_TRACKS) * count +
                                      LAST_TEST_UNITS);
        FUZZ_CHECK(memcmp(&objects[cap], &canary, sizeof canary) == 0);
        FUZZ_CHECK(memcmp(range_copy, range, count * sizeof *range) == 0);
        FUZZ_CHECK(memcmp(table_copy, table, count * sizeof *table) == 0);
        FUZZ_CHECK(memcmp(&out_copy, &out, sizeof out) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): a byte copy of itself
        if (since_restart < EGO_MOVING_CONFIRM || restart_age_us < EGO_MOVING_REF_MIN_US) {
            FUZZ_CHECK(n2 == 0u);
        }
        FUZZ_CHECK(n == ((n2 < cap) ? n2 : cap));
        FUZZ_CHECK(memcmp(objects, all, (size_t)n * sizeof *objects) == 0);
        check_objects(all, n2, &scan, since_restart, centre_check);
        free(objects);
        free(range);
        free(table);
    }
    return 0;
}
