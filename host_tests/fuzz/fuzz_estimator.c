/* fuzz_estimator.c - libFuzzer target over the estimator through its
 * public input (estimator/ego.h, ego_range.h): arbitrary range scans and
 * arbitrary sequences of them, with and without a prior, under the
 * unbounded defaults (ego_defaults) and the live budget
 * (ego_budget_defaults).
 *
 * Input: byte 0 is the setup: bit 0 a budget (else unbounded),
 * bit 1 a prior with every scan, bit 2 a bearing table (else uniform
 * bearings), bit 3 interlaced passes and beam times, bit 4 a sensor
 * origin off the vehicle's (+-128 m), bit 5 the raw scan fields from the input
 * (most such scans fail ego_range_check: EGO_ERR_SCAN), bits 6-7 the range
 * unit (1000, 10000, 250 um, or from the input). With bit 4 the origin
 * (two u16), then with bit 0 the budget: u8 b, 0 for the live defaults
 * (ego_budget_defaults), else work_per_s and work_min at b / 64 of theirs
 * (1/64 .. 4 times: a slower target's budget, where the meter cuts every
 * stage), and u8 m, max_search_scans (0: the default, 30). Then up to 4
 * scans, each:
 *   u8   count: 1 + c % 181 beams, or c == 255: EGO_MAX_BEAMS (the
 *        capacity; the ranges given repeat), c == 254: 0 beams, c == 253:
 *        the previous scan again (below)
 *   u8   options: bit 0 ego_reset before it; bits 1-7 the sweep, in
 *        128ths of a turn (1 + v), spread evenly over the beams
 *   u32  time step in us (any: jumps, 0, wrap-around)
 *   u32  first bearing (a binary angle)
 *   u16  per beam up to 181: the range in units (0: no range)
 *   with bit 1: 12 bytes of prior (theta u32; x, y i32 cut to +-8 m)
 *   with bit 3: u8 passes, u16 pass_us, u16 beam_ns
 *   with bit 5: u16 count, u32 unit, u64 first bearing, u64 step (raw)
 * A scan again (c == 253) has the previous scan's beams and ranges, read
 * as count, options and step, then instead of the first bearing an i16
 * turn (2^-16 turns added to the previous first bearing: the vehicle
 * turning on the spot) and an i16 added to every range (0 stays 0, within
 * 1..65535), then the prior, timing and raw fields as any scan; none before
 * it: 0 beams. Such scans go on after the fourth, up to 40 in all (any
 * other count byte there ends the input), so that a few bytes make the
 * long sequences the hold (after 8 slow lines) and a search's give-up
 * (after 30 scans, max_search_scans) need; random inputs still end after
 * four scans.
 * A missing byte reads as 0. At most 181 values per scan are read, so an
 * input stays under 1.6 kB and a run stays fast.
 *
 * Checks (abort on violation), for every scan:
 *  - ego_process(_with_prior) returns EGO_ERR_SCAN exactly when
 *    ego_range_check fails, and then leaves the state byte for byte as it
 *    was; EGO_OK otherwise;
 *  - FIRST (the first scan, or after ego_reset or a zero interval): no
 *    motion (zero pose and velocities, dt 0), the flag alone;
 *  - RECOVERING without RECOVERED: no motion claimed (zero pose and
 *    velocities);
 *  - FIRST, PREDICTED, RECOVERING: the covariance says unknown
 *    (EGO_COV_SATURATED variances), as ego.h documents;
 *  - a line with a motion has dt_us > 0 and its velocities are its pose
 *    over dt_us (set_velocities' formula: vx = pose.x * 10^6 / dt_us,
 *    saturated; omega likewise from the signed turn);
 *  - a measured translation (no FIRST, PREDICTED or RECOVERING) is within
 *    2 R + 1 m on each axis, R the largest distance of any range reading
 *    given so far from the vehicle's origin (two scans that overlap
 *    cannot be further apart); a predicted one within MAX_HORIZON (16)
 *    times the largest of those bounds and the prior's;
 *  - points <= the scan's beams (a RECOVERED line's: those of the scan
 *    its search started from, <= EGO_MAX_POINTS), matches and inliers
 *    <= EGO_MAX_POINTS;
 *  - under a budget, work <= work_limit (ego_work.h: a stage that could
 *    overrun the limit does not start); unbounded, work_limit UINT32_MAX;
 *  - ego_reset starts over (ego.h: "the next scan is a first scan"): after
 *    a reset within the sequence, every output equals, byte for byte,
 *    that of a state that never ran fed the same scans from there;
 *  - no crash, no undefined behaviour (ASan, UBSan).
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ego.h"
#include "ego_range.h"
#include "fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_SCANS 4u
#define MAX_SEQUENCE 40u /* with scans again after the fourth */
#define MAX_GIVEN 181u
#define AGAIN 253u
/* Prior translations are cut to +-8 m (Q16.16). */
#define PRIOR_LIMIT (8 * 65536)
/* ego.c: the last motion scaled to an interval at most this many times. */
#define HORIZON 16

static uint64_t take64(fuzz_input_t *in)
{
    const uint64_t lo = fuzz_take(in, 4u);
    return lo | ((uint64_t)fuzz_take(in, 4u) << 32);
}

static int64_t abs64(int64_t v)
{
    return (v < 0) ? -v : v;
}

static void check_motion_free(const ego_output_t *out)
{
    FUZZ_CHECK(out->pose.x == 0 && out->pose.y == 0 && out->pose.theta == 0u);
    FUZZ_CHECK(out->vx == 0 && out->vy == 0 && out->omega == 0);
}

static void check_velocities(const ego_output_t *out)
{
    FUZZ_CHECK(out->dt_us > 0u);
    const int64_t dt = out->dt_us;
    FUZZ_CHECK(out->vx == fx_sat_s32((int64_t)out->pose.x * 1000000 / dt));
    FUZZ_CHECK(out->vy == fx_sat_s32((int64_t)out->pose.y * 1000000 / dt));
    /* 2 pi in Q16.16 per turn, as ego.c's RAD_Q16_PER_TURN. */
    const int64_t per_us = (int64_t)fx_bam32_diff(out->pose.theta, 0u) * 411775 / dt;
    const int64_t limit = INT64_MAX / 1000000; /* beyond: saturated (finding E1) */
    const int32_t omega = (per_us > limit)    ? INT32_MAX
                          : (per_us < -limit) ? -INT32_MAX
                                              : fx_sat_s32(per_us * 1000000 / 4294967296LL);
    FUZZ_CHECK(out->omega == omega);
}

static void check_output(const ego_output_t *out, const ego_range_scan_t *scan, bool budget,
                         int64_t reach_q16, int64_t prior_q16)
{
    const uint16_t f = out->flags;
    const bool first = (f & EGO_FLAG_FIRST) != 0u;
    const bool predicted = (f & EGO_FLAG_PREDICTED) != 0u;
    const bool recovering = (f & EGO_FLAG_RECOVERING) != 0u;
    const bool recovered = (f & EGO_FLAG_RECOVERED) != 0u;
    if (first) {
        FUZZ_CHECK(f == EGO_FLAG_FIRST);
        FUZZ_CHECK(out->dt_us == 0u);
        check_motion_free(out);
    }
    if (recovering && !recovered) {
        check_motion_free(out);
    }
    if (first || predicted || recovering) {
        FUZZ_CHECK(out->cov.xx == EGO_COV_SATURATED && out->cov.yy == EGO_COV_SATURATED &&
                   out->cov.tt == EGO_COV_SATURATED);
    }
    const bool motion = !first && !(recovering && !recovered);
    if (motion) {
        check_velocities(out);
        const int64_t bound = predicted ? HORIZON * ((reach_q16 > prior_q16) ? reach_q16 : prior_q16)
                                        : reach_q16;
        FUZZ_CHECK(abs64(out->pose.x) <= bound && abs64(out->pose.y) <= bound);
    }
    /* A RECOVERED line is the motion to the scan its search started from,
     * and carries that scan's points. */
    FUZZ_CHECK(out->points <= (recovered ? EGO_MAX_POINTS : scan->count));
    FUZZ_CHECK(out->matches <= EGO_MAX_POINTS && out->inliers <= EGO_MAX_POINTS);
    if (budget) {
        FUZZ_CHECK(out->work <= out->work_limit);
    } else {
        FUZZ_CHECK(out->work_limit == UINT32_MAX);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static ego_state_t state;
    static ego_state_t before;
    static ego_state_t fresh; /* after a reset in the sequence: a state that never ran */
    bool twin = false;
    static ego_params_t params;
    static const uint32_t units[3] = {1000u, 10000u, 250u};
    if (size < 1u) {
        return 0;
    }
    fuzz_input_t in = {data, size, 1u};
    const uint8_t setup = data[0];
    const bool budget = (setup & 1u) != 0u;
    const bool with_prior = (setup & 2u) != 0u;
    const bool with_table = (setup & 4u) != 0u;
    const bool with_timing = (setup & 8u) != 0u;
    const bool with_origin = (setup & 16u) != 0u;
    const bool raw = (setup & 32u) != 0u;
    const unsigned unit_pick = (setup >> 6) & 3u;
    /* ego_budget_defaults sets the budget on top of ego_defaults. */
    ego_defaults(&params);
    /* Every input starts from a state that never ran (static storage is
     * zero, then ego_reset), so that an input gives the same outputs
     * whatever ran before it. */
    memset(&state, 0, sizeof state);
    ego_reset(&state);
    uint32_t unit_um = (unit_pick < 3u) ? units[unit_pick] : 1u + fuzz_take(&in, 4u) % 500000u;
    fx_q16_16_t ox = 0;
    fx_q16_16_t oy = 0;
    if (with_origin) {
        /* +-128 m in 4 mm steps: past EGO_MAX_ORIGIN (100 m: EGO_ERR_SCAN)
         * and up to it, where the points' arithmetic must still hold. */
        ox = (fx_q16_16_t)((int32_t)fuzz_take(&in, 2u) - 32768) * 256;
        oy = (fx_q16_16_t)((int32_t)fuzz_take(&in, 2u) - 32768) * 256;
    }
    if (budget) {
        ego_budget_defaults(&params);
        const uint32_t b = fuzz_take(&in, 1u);
        const uint32_t m = fuzz_take(&in, 1u);
        if (b != 0u) {
            params.work_per_s = (uint32_t)((uint64_t)params.work_per_s * b / 64u);
            params.work_min = (uint32_t)((uint64_t)params.work_min * b / 64u);
        }
        if (m != 0u) {
            params.max_search_scans = (uint8_t)m;
        }
    }
    uint32_t time_us = 0u;
    int64_t far_um = 0; /* the farthest reading from the vehicle's origin */
    /* The previous scan, for a scan again (c == AGAIN). */
    static uint16_t last_range[EGO_MAX_BEAMS];
    uint16_t last_count = 0u;
    uint32_t last_first = 0u;
    for (unsigned s = 0u; s < MAX_SEQUENCE && in.pos < in.size; s++) {
        const uint8_t c = (uint8_t)fuzz_take(&in, 1u);
        const bool again = c == AGAIN;
        if (s >= MAX_SCANS && !again) {
            break;
        }
        const uint8_t options = (uint8_t)fuzz_take(&in, 1u);
        const uint32_t step = fuzz_take(&in, 4u);
        time_us += step;
        uint32_t first = 0u;
        int32_t delta = 0;
        if (again) {
            first = last_first + (uint32_t)((int32_t)(int16_t)fuzz_take(&in, 2u) * 65536);
            delta = (int16_t)fuzz_take(&in, 2u);
        } else {
            first = fuzz_take(&in, 4u);
        }
        uint16_t count = (uint16_t)(1u + c % MAX_GIVEN);
        uint16_t given = count;
        if (c == 255u) {
            count = (uint16_t)EGO_MAX_BEAMS; /* the given ranges repeat */
            given = (uint16_t)MAX_GIVEN;
        } else if (c == 254u) {
            count = 0u;
            given = 0u;
        } else if (again) {
            count = last_count;
            given = last_count;
        }
        /* Arrays of exactly count elements on the heap: ASan reports a read
         * past the scan's last beam (a static array of the capacity would
         * hide it and hand over the previous input's values). */
        uint16_t *range = malloc(((count > 0u) ? count : 1u) * sizeof *range);
        fx_bam32_t *table = malloc(((count > 0u) ? count : 1u) * sizeof *table);
        FUZZ_CHECK(range != NULL && table != NULL);
        uint16_t largest = 0u;
        for (uint16_t k = 0u; k < given; k++) {
            if (again) {
                const int32_t r = last_range[k] + delta;
                range[k] = (last_range[k] == 0u) ? 0u
                           : (r < 1)             ? 1u
                           : (r > 65535)         ? 65535u
                                                 : (uint16_t)r;
            } else {
                range[k] = (uint16_t)fuzz_take(&in, 2u);
            }
            largest = (range[k] > largest) ? range[k] : largest;
        }
        for (uint16_t k = given; k < count; k++) {
            range[k] = range[k % given];
        }
        memcpy(last_range, range, count * sizeof *range);
        last_count = count;
        last_first = first;
        ego_range_scan_t scan;
        memset(&scan, 0, sizeof scan);
        scan.count = count;
        scan.range = range;
        scan.range_unit_um = unit_um;
        scan.origin_x = ox;
        scan.origin_y = oy;
        scan.first_bearing = EGO_BEARING_Q32(first);
        /* The sweep, 1..128 128ths of a turn, spread over count - 1 steps. */
        const uint64_t sweep = ((uint64_t)((options >> 1) + 1u)) << 57;
        const uint64_t steps = (count > 1u) ? (uint64_t)(count - 1u) : 1u;
        scan.bearing_step = (sweep == 0u) ? UINT64_MAX / steps : (sweep - 1u) / steps;
        if (with_table) {
            for (uint16_t k = 0u; k < count; k++) {
                table[k] = ego_range_bearing(&scan, k);
            }
            scan.bearing = table;
        }
        ego_pose_t prior = {0u, 0, 0};
        if (with_prior) {
            prior.theta = fuzz_take(&in, 4u);
            prior.x = (fx_q16_16_t)((int32_t)fuzz_take(&in, 4u) % PRIOR_LIMIT);
            prior.y = (fx_q16_16_t)((int32_t)fuzz_take(&in, 4u) % PRIOR_LIMIT);
        }
        if (with_timing) {
            scan.passes = (uint8_t)fuzz_take(&in, 1u);
            scan.pass_us = fuzz_take(&in, 2u);
            scan.beam_ns = fuzz_take(&in, 2u) * 16u;
        }
        if (raw) {
            scan.count = (uint16_t)fuzz_take(&in, 2u);
            if (scan.count > count) {
                scan.count = count; /* the arrays hold count */
            }
            scan.range_unit_um = fuzz_take(&in, 4u);
            scan.first_bearing = take64(&in);
            scan.bearing_step = take64(&in);
            scan.bearing = NULL;
        }
        if ((options & 1u) != 0u && s > 0u) {
            ego_reset(&state);
            memset(&fresh, 0, sizeof fresh);
            ego_reset(&fresh);
            twin = true;
        }
        const bool valid = ego_range_check(&scan);
        if (valid) {
            /* |origin| + the reading, um: R of the header. */
            const int64_t origin_um = (abs64(ox) + abs64(oy)) * 1000000 / 65536 + 1;
            const int64_t r = (int64_t)largest * scan.range_unit_um + origin_um;
            far_um = (r > far_um) ? r : far_um;
        } else {
            memcpy(&before, &state, sizeof state);
        }
        ego_output_t out;
        memset(&out, 0, sizeof out);
        const ego_status_t st =
            with_prior ? ego_process_with_prior(&state, &params, &scan, time_us, &prior, &out)
                       : ego_process(&state, &params, &scan, time_us, &out);
        if (!valid) {
            FUZZ_CHECK(st == EGO_ERR_SCAN);
            FUZZ_CHECK(memcmp(&before, &state, sizeof state) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): a byte copy of itself
            free(range);
            free(table);
            continue;
        }
        FUZZ_CHECK(st == EGO_OK);
        if (twin) {
            ego_output_t other;
            const ego_status_t st2 =
                with_prior ? ego_process_with_prior(&fresh, &params, &scan, time_us, &prior, &other)
                           : ego_process(&fresh, &params, &scan, time_us, &other);
            FUZZ_CHECK(st2 == EGO_OK &&
                       memcmp(&out, &other, sizeof out) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): ego_process zeroes both first
        }
        /* 2 R + 1 m in Q16.16 (um * 65536 / 10^6). */
        const int64_t reach_q16 = (2 * far_um + 1000000) * 65536 / 1000000;
        const int64_t prior_q16 = with_prior ? PRIOR_LIMIT : 0;
        check_output(&out, &scan, budget, reach_q16, prior_q16);
        free(range);
        free(table);
    }
    return 0;
}
