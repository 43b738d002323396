/* fuzz_itcp.c - libFuzzer target over ITCP as a library (estimator/ego_itcp.h):
 * the registration that ego_process no longer runs (docs/estimator.md,
 * issue 15) but the library still offers, and the prober the coarse search
 * uses. Two range scans, prepared and fitted as ego.c does
 * (ego_scan_prepare, ego_tfit_fit_scan with their defaults), registered
 * whole (ego_itcp_register) and in pieces (ego_itcp_run_start / _step /
 * _result under a small meter), then probed at points from the input.
 *
 * Input: byte 0 is the setup: bit 0 plain ICP (else ITCP weights), bit 1
 * the tangent gate, bit 2 hold_rotation, bit 3 the parameters from the
 * input (else ego_itcp_defaults), bit 4 max_points from the input, bits
 * 5-6 the range unit (1000, 10000, 250 um, or 1 + u32 % 500000 from the
 * input), bit 7 the current scan is the last one's ranges again (none
 * read; its own first bearing turns it). Then:
 *   u32  main direction (a binary angle)
 *   u32  theta, i32 x, i32 y: the initial pose (x, y cut to +-8 m)
 *   u16  the meter of each piece: EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK)
 *        + v units (the least that always makes progress, ego_itcp.h)
 *   with bit 3 (the ranges fuzzed; ego_itcp.h gives the defaults):
 *        u16 gate, u16 main_tolerance (2^-16 turns), u16 radius_start
 *        (1 .. 4096 mm), u16 radius_min, u16 radius_fine (0 .. 4095 mm),
 *        u8 shrink (0.5 + v / 512), u8 max_iterations (% 61),
 *        u8 fine_iterations (% 61), u8 converge_translation (0 .. 2.55 mm),
 *        u8 converge_rotation (0 .. 0.255 deg), u16 inlier_distance
 *        (1 .. 1024 mm), u8 aperture_ratio (v / 256), u8 min_matches
 *   with bit 4: u16 max_points (% the current scan's count + 1)
 *   two scans (the last, then the current), each:
 *     u8   count: 1 + c % 181 beams, or c == 255: EGO_MAX_BEAMS (the
 *          capacity; the ranges given repeat)
 *     u8   sweep: 1 + v 256ths of a turn, spread over the beams
 *     u32  first bearing (a binary angle)
 *     u16  per beam up to 181: the range in units (0: no range)
 *   u16  the probes' radius, u16 their margin (mm)
 *   then up to 8 probes: i16 x, i16 y (cm, the last scan's frame)
 * A missing byte reads as 0.
 *
 * Checks (abort on violation):
 *  - ego_scan_prepare returns EGO_PREP_ERR_LAYOUT exactly when
 *    ego_range_check fails (the input then ends), EGO_PREP_OK otherwise;
 *  - ego_itcp_register returns EGO_ITCP_OK or EGO_ITCP_ERR_FEW_MATCHES;
 *    with OK: matches <= the current scan's points, n_main + n_non_main ==
 *    matches, inliers and each group's points within the current points,
 *    group_fit in 0 .. 1, residual >= 0, no covariance (ITCP gives none),
 *    and with hold_rotation theta as given; with FEW_MATCHES and
 *    max_iterations 0 the pose is the initial one;
 *  - the same run in pieces: every piece spends at most its meter, every
 *    piece but the last makes progress, the pieces spend what one
 *    unlimited step spends, and the result is byte for byte the whole
 *    registration's (ego_itcp.h: "however it is cut up");
 *  - every probe agrees with ego_itcp_nearest and ego_itcp_seen_through
 *    asked afresh (the prober starts each search where the last one
 *    ended): SURFACE with the same squared distance, below radius^2,
 *    exactly when the nearest surface lies below radius^2; otherwise
 *    SEEN_THROUGH exactly when the last scan saw margin beyond the point;
 *    the prober's units at most EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK)
 *    a probe;
 *  - no crash, no undefined behaviour (ASan, UBSan).
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ego_itcp.h"
#include "ego_range.h"
#include "ego_scan.h"
#include "ego_tfit.h"
#include "fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_GIVEN 181u
#define MAX_PROBES 8u
#define PRIOR_LIMIT (8 * 65536) /* +-8 m, Q16.16 */
#define POINT_MAX EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK)
#define MM_Q16(mm) ((fx_q16_16_t)(((int64_t)(mm) * 65536 + 500) / 1000))

static void take_params(fuzz_input_t *in, itcp_params_t *p)
{
    p->gate = fuzz_take(in, 2u) << 16;
    p->main_tolerance = fuzz_take(in, 2u) << 16;
    p->radius_start = MM_Q16(1u + fuzz_take(in, 2u) % 4096u);
    p->radius_min = MM_Q16(1u + fuzz_take(in, 2u) % 4096u);
    p->radius_fine = MM_Q16(fuzz_take(in, 2u) % 4096u);
    p->radius_shrink = (fx_q2_30_t)(FX_Q2_30_ONE / 2 + (int32_t)fuzz_take(in, 1u) * (FX_Q2_30_ONE / 512));
    p->max_iterations = (uint8_t)(fuzz_take(in, 1u) % 61u);
    p->fine_iterations = (uint8_t)(fuzz_take(in, 1u) % 61u);
    p->converge_translation = MM_Q16(fuzz_take(in, 1u)) / 100;
    p->converge_rotation = FX_BAM32_DEG_C(0.001) * fuzz_take(in, 1u);
    p->inlier_distance = MM_Q16(1u + fuzz_take(in, 2u) % 1024u);
    p->aperture_ratio = (fx_q2_30_t)((int32_t)fuzz_take(in, 1u) * (FX_Q2_30_ONE / 256));
    p->min_matches = (uint16_t)fuzz_take(in, 1u);
}

/* Reads one range scan into range[] (count elements: a heap array of
 * exactly that many, so that ASan sees a read past the last beam). */
static uint16_t *take_scan(fuzz_input_t *in, ego_range_scan_t *scan, uint32_t unit_um,
                           const uint16_t *again, uint16_t again_count)
{
    const uint8_t c = (uint8_t)fuzz_take(in, 1u);
    const uint8_t sweep_v = (uint8_t)fuzz_take(in, 1u);
    const uint32_t first = fuzz_take(in, 4u);
    uint16_t count = (uint16_t)(1u + c % MAX_GIVEN);
    uint16_t given = count;
    if (again != NULL) {
        count = again_count;
        given = 0u;
    } else if (c == 255u) {
        count = (uint16_t)EGO_MAX_BEAMS;
        given = (uint16_t)MAX_GIVEN;
    }
    uint16_t *range = malloc(((count > 0u) ? count : 1u) * sizeof *range);
    FUZZ_CHECK(range != NULL);
    for (uint16_t k = 0u; k < given; k++) {
        range[k] = (uint16_t)fuzz_take(in, 2u);
    }
    for (uint16_t k = given; k < count; k++) {
        range[k] = (again != NULL) ? again[k] : range[k % given];
    }
    memset(scan, 0, sizeof *scan);
    scan->count = count;
    scan->range = range;
    scan->range_unit_um = unit_um;
    scan->first_bearing = EGO_BEARING_Q32(first);
    /* The sweep, 1..256 256ths of a turn less a unit of the last place (a
     * whole turn wraps to 0 before the unit is taken), over count - 1 steps. */
    const uint64_t steps = (count > 1u) ? (uint64_t)(count - 1u) : 1u;
    scan->bearing_step = ((((uint64_t)sweep_v + 1u) << 56) - 1u) / steps;
    return range;
}

/* Prepared and fitted as ego.c does; false when the layout is refused. */
static bool prepare(const ego_range_scan_t *in, ego_scan_t *scan)
{
    ego_prep_params_t prep;
    ego_prep_defaults(&prep);
    const ego_prep_status_t st = ego_scan_prepare(in, &prep, scan);
    FUZZ_CHECK((st == EGO_PREP_OK) == ego_range_check(in));
    FUZZ_CHECK(st == EGO_PREP_OK || st == EGO_PREP_ERR_LAYOUT);
    if (st != EGO_PREP_OK) {
        return false;
    }
    ego_tfit_params_t fit;
    ego_tfit_defaults(&fit);
    ego_tfit_fit_scan(scan, &fit);
    return true;
}

static void check_result(ego_itcp_status_t st, const ego_itcp_result_t *r, const ego_scan_t *current,
                         const ego_pose_t *initial, bool hold_rotation, const itcp_params_t *params)
{
    FUZZ_CHECK(st == EGO_ITCP_OK || st == EGO_ITCP_ERR_FEW_MATCHES);
    if (st == EGO_ITCP_OK) {
        FUZZ_CHECK(r->matches <= current->count);
        FUZZ_CHECK((uint32_t)r->n_main + r->n_non_main == r->matches);
        FUZZ_CHECK(r->inliers <= current->count);
        FUZZ_CHECK((uint32_t)r->group_points[0] + r->group_points[1] <= current->count);
        for (unsigned g = 0u; g < 2u; g++) {
            FUZZ_CHECK(r->group_fit[g] >= 0 && r->group_fit[g] <= FX_Q2_30_ONE);
        }
        FUZZ_CHECK(r->residual >= 0);
        if (hold_rotation) {
            FUZZ_CHECK(r->pose.theta == initial->theta);
        }
    } else if (params->max_iterations == 0u) {
        FUZZ_CHECK(memcmp(&r->pose, initial, sizeof *initial) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): three 32-bit fields, no padding
    }
    FUZZ_CHECK(r->cov.xx == EGO_COV_SATURATED && r->cov.yy == EGO_COV_SATURATED &&
               r->cov.tt == EGO_COV_SATURATED);
}

static void check_probes(fuzz_input_t *in, const ego_scan_t *last)
{
    const fx_q16_16_t radius = MM_Q16(fuzz_take(in, 2u));
    const fx_q16_16_t margin = MM_Q16(fuzz_take(in, 2u));
    const uint64_t radius_sq = (uint64_t)((int64_t)radius * radius);
    static ego_itcp_prober_t prober;
    ego_itcp_prober_init(&prober, last, radius, margin);
    for (unsigned k = 0u; k < MAX_PROBES && in->pos < in->size; k++) {
        const fx_q16_16_t qx = (fx_q16_16_t)(int16_t)fuzz_take(in, 2u) * 655; /* ~cm */
        const fx_q16_16_t qy = (fx_q16_16_t)(int16_t)fuzz_take(in, 2u) * 655;
        uint64_t d_probe = 0u;
        const ego_itcp_probe_t p = ego_itcp_probe(&prober, qx, qy, &d_probe);
        FUZZ_CHECK(ego_itcp_prober_take_units(&prober) <= POINT_MAX);
        uint64_t d_near = 0u;
        const bool near = ego_itcp_nearest(last, qx, qy, radius, &d_near) && d_near < radius_sq;
        FUZZ_CHECK((p == EGO_ITCP_PROBE_SURFACE) == near);
        if (near) {
            FUZZ_CHECK(d_probe == d_near);
        } else {
            FUZZ_CHECK((p == EGO_ITCP_PROBE_SEEN_THROUGH) == ego_itcp_seen_through(last, qx, qy, margin));
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* Too large for the stack of a sanitized build: static, as a caller's. */
    static ego_scan_t last;
    static ego_scan_t current;
    static ego_itcp_run_t run;
    static const uint32_t units[3] = {1000u, 10000u, 250u};
    if (size < 1u) {
        return 0;
    }
    fuzz_input_t in = {data, size, 1u};
    const uint8_t setup = data[0];
    itcp_params_t params;
    ego_itcp_defaults(&params);
    params.weighted = (setup & 1u) == 0u;
    params.tangent_gate = (setup & 2u) != 0u;
    const bool hold_rotation = (setup & 4u) != 0u;
    const unsigned unit_pick = (setup >> 5) & 3u;
    const uint32_t unit_um = (unit_pick < 3u) ? units[unit_pick] : 1u + fuzz_take(&in, 4u) % 500000u;
    const fx_bam32_t main_direction = fuzz_take(&in, 4u);
    ego_pose_t initial;
    initial.theta = fuzz_take(&in, 4u);
    initial.x = (fx_q16_16_t)((int32_t)fuzz_take(&in, 4u) % PRIOR_LIMIT);
    initial.y = (fx_q16_16_t)((int32_t)fuzz_take(&in, 4u) % PRIOR_LIMIT);
    const uint64_t piece = POINT_MAX + (uint64_t)fuzz_take(&in, 2u);
    if ((setup & 8u) != 0u) {
        take_params(&in, &params);
    }
    const bool with_max_points = (setup & 16u) != 0u;
    const uint16_t max_points = (uint16_t)fuzz_take(&in, with_max_points ? 2u : 0u);

    ego_range_scan_t last_in;
    ego_range_scan_t current_in;
    uint16_t *last_range = take_scan(&in, &last_in, unit_um, NULL, 0u);
    uint16_t *current_range = take_scan(&in, &current_in, unit_um,
                                        ((setup & 128u) != 0u) ? last_range : NULL, last_in.count);
    if (prepare(&last_in, &last) && prepare(&current_in, &current)) {
        params.max_points = with_max_points ? (uint16_t)(max_points % (current.count + 1u)) : 0u;
        ego_itcp_result_t whole;
        const ego_itcp_status_t st = ego_itcp_register(&last, &current, main_direction, &initial,
                                                       hold_rotation, &params, &whole);
        check_result(st, &whole, &current, &initial, hold_rotation, &params);

        /* One unlimited step, then the same run in pieces. */
        ego_work_t work;
        ego_itcp_run_start(&run, &last, &current, main_direction, &initial, hold_rotation, &params);
        ego_work_start(&work, EGO_WORK_UNLIMITED);
        FUZZ_CHECK(ego_itcp_run_step(&run, &work));
        const uint64_t total = work.used;
        ego_itcp_run_start(&run, &last, &current, main_direction, &initial, hold_rotation, &params);
        uint64_t spent = 0u;
        bool finished = false;
        while (!finished) {
            ego_work_start(&work, piece);
            finished = ego_itcp_run_step(&run, &work);
            FUZZ_CHECK(work.used <= work.limit);
            FUZZ_CHECK(finished || work.used > 0u);
            spent += work.used;
            FUZZ_CHECK(spent <= total);
        }
        FUZZ_CHECK(spent == total);
        ego_itcp_result_t pieces;
        FUZZ_CHECK(ego_itcp_run_result(&run, &pieces) == st);
        FUZZ_CHECK(memcmp(&pieces, &whole, sizeof whole) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): both zeroed by ego_itcp_run_result first
        check_probes(&in, &last);
    }
    free(last_range);
    free(current_range);
    return 0;
}
