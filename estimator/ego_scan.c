/* ego_scan.c - see ego_scan.h. */
#include "ego_scan.h"

#include <stddef.h>
#include <string.h>

#include "ego_fx_math.h"

/* Radians per binary-angle unit, 2 pi / 2^32, scaled by 2^60: a binary
 * angle times this, shifted right by 30, is Q2.30 radians.
 * round(pi / 2 * 2^30). */
#define RAD_PER_BAM_Q60 1686629713

void ego_prep_defaults(ego_prep_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->min_range = FX_Q16_16_C(0.10);
    params->max_range = FX_Q16_16_C(81.9);
    params->jump_min = FX_Q16_16_C(0.30);
    params->jump_factor = 4u;
    params->occlusion_sin = 186453311; /* sin(10 deg), Q2.30 */
    params->beam_spacing = 0u;
}

/* Q16.16 metres per range unit, in Q32 (unit_um <= 500000: below 2^47):
 * one division per scan instead of one per beam. unit_um * 2^48 / 10^6 =
 * unit_um * 2^42 / 15625, whose numerator stays below 2^61. */
static uint64_t q48_per_unit(uint32_t unit_um)
{
    return (((uint64_t)unit_um << 42) + 7812u) / 15625u;
}

/* A range in Q16.16 metres, rounded (below 2^31: at most 65535 units of
 * 0.5 m, ego_range_check). The scale's error, under 2^-33 per unit, moves
 * a result only where the exact value lies within 10^-5 of a tie (none
 * for whole micrometres, millimetres or centimetres per unit). */
static fx_q16_16_t q16_from_units(uint16_t value, uint64_t scale_q48)
{
    return (fx_q16_16_t)(((uint64_t)value * scale_q48 + (1ull << 31)) >> 32);
}

/* A bearing step (less than half a turn) in radians, Q2.30. */
static fx_q2_30_t rad_from_step(uint32_t step)
{
    return (fx_q2_30_t)fx_shr_round_s64((int64_t)step * RAD_PER_BAM_Q60, 30u);
}

static fx_q16_16_t abs_q16(fx_q16_16_t v)
{
    return (v < 0) ? -v : v;
}

/* A point relative to the scanner, kept for the link tests. */
typedef struct {
    fx_q16_16_t x;
    fx_q16_16_t y;
    fx_q16_16_t r;
} sensor_point_t;

/* Range jump between neighbouring beams (ranges a, b). */
static bool is_jump(const ego_prep_params_t *p, fx_q16_16_t a, fx_q16_16_t b,
                    fx_q2_30_t step_rad)
{
    const fx_q16_16_t nearer = (a < b) ? a : b;
    /* jump_factor * r * dphi, in Q16.16 metres. */
    const int64_t scaled = fx_shr_round_s64((int64_t)nearer * step_rad, 30u) * p->jump_factor;
    const int64_t limit = (scaled > p->jump_min) ? scaled : p->jump_min;
    return (int64_t)abs_q16(a - b) > limit;
}

/* Sharp-angle criterion: in the triangle scanner-A-B the sine of the angle
 * at the far end is |A x B| / (max(|A|, |B|) |AB|). Below occlusion_sin the
 * segment runs along the beams: an occlusion edge. */
static bool is_occlusion(const ego_prep_params_t *p, const sensor_point_t *a,
                         const sensor_point_t *b)
{
    const int64_t cross = (int64_t)a->x * b->y - (int64_t)a->y * b->x; /* Q32.32, < 2^46 */
    const int64_t dx = (int64_t)b->x - a->x;
    const int64_t dy = (int64_t)b->y - a->y;
    const int64_t far = (a->r > b->r) ? a->r : b->r;
    /* Both sides scaled to Q46.(32+14) (< 2^61): the sine keeps 14 bits. */
    const int64_t lhs = ((cross < 0) ? -cross : cross) << 14;
    const int64_t scale = far * (int64_t)(p->occlusion_sin >> 16);
    /* |AB| (Q16.16, its root rounded down) lies between the larger of
     * |dx|, |dy| and their sum: the root only where those disagree (a
     * surface facing the scanner is decided without it). */
    const int64_t ax = (dx < 0) ? -dx : dx;
    const int64_t ay = (dy < 0) ? -dy : dy;
    if (lhs < scale * ((ax > ay) ? ax : ay)) {
        return true;
    }
    if (lhs >= scale * (ax + ay)) {
        return false;
    }
    const uint32_t ab = fx_sqrt_u64((uint64_t)(dx * dx + dy * dy)); /* Q16.16 */
    return lhs < scale * (int64_t)ab;
}

/* The link from the point before `here` (prev, bearing step_bam apart):
 * 0 or EGO_LINK_* | EGO_LINK_BREAK. gap: beams without a point lie
 * between them. */
static uint8_t link_between(const ego_prep_params_t *params, const sensor_point_t *prev,
                            const sensor_point_t *here, uint32_t step_bam, bool gap)
{
    uint8_t link = 0u;
    if (gap) {
        link |= EGO_LINK_GAP;
    } else if (is_jump(params, prev->r, here->r, rad_from_step(step_bam))) {
        link |= EGO_LINK_JUMP;
    }
    if (!gap && is_occlusion(params, prev, here)) {
        link |= EGO_LINK_OCCLUSION;
    }
    if (link == 0u) {
        return 0u;
    }
    return (uint8_t)(link | EGO_LINK_BREAK | ((here->r > prev->r) ? EGO_LINK_RISES : 0u));
}

/* Moves the point just written at index i back to its bearing's place
 * among the points before it, at most EGO_SCAN_REORDER_MAX places; false
 * (the point left out) when it belongs further back. */
static bool settle_by_bearing(ego_scan_t *scan, uint16_t i)
{
    const fx_q16_16_t x = scan->x[i];
    const fx_q16_16_t y = scan->y[i];
    const fx_bam32_t b = scan->bearing[i];
    uint16_t j = i;
    for (uint32_t moves = 0u; j > 0u && fx_bam32_diff(scan->bearing[j - 1u], b) > 0; moves++) {
        if (moves == EGO_SCAN_REORDER_MAX) {
            return false;
        }
        scan->x[j] = scan->x[j - 1u];
        scan->y[j] = scan->y[j - 1u];
        scan->bearing[j] = scan->bearing[j - 1u];
        j--;
    }
    if (j != i) {
        scan->x[j] = x;
        scan->y[j] = y;
        scan->bearing[j] = b;
    }
    return true;
}

static int64_t clamp_s64(int64_t v, int64_t limit)
{
    return (v > limit) ? limit : ((v < -limit) ? -limit : v);
}

/* The links of de-skewed points, from where they are (relative to the
 * sensor at the scan's time): a bearing step beyond three beam spacings
 * (spacing_bam) is a gap (the passes' skew leaves steps of two and a bit
 * where no beam is missing: a wall seen obliquely as the scanner nears
 * it; a single missing beam is left to the jump and occlusion tests).
 * Each coordinate is taken within the longest range (the link tests'
 * products are sized for it; only an absurd skew moves a point further). */
static void link_deskewed(ego_scan_t *scan, const ego_prep_params_t *params, uint64_t spacing_bam)
{
    sensor_point_t prev = {0, 0, 0};
    const int64_t reach = params->max_range;
    for (uint16_t i = 0u; i < scan->count; i++) {
        const int64_t hx = clamp_s64((int64_t)scan->x[i] - scan->origin_x, reach);
        const int64_t hy = clamp_s64((int64_t)scan->y[i] - scan->origin_y, reach);
        const uint64_t r = fx_sqrt_u64((uint64_t)(hx * hx) + (uint64_t)(hy * hy));
        const sensor_point_t here = {(fx_q16_16_t)hx, (fx_q16_16_t)hy,
                                     (fx_q16_16_t)((r < (uint64_t)reach) ? r : (uint64_t)reach)};
        scan->flags[i] = EGO_LINK_BREAK; /* until a next point links to it */
        if (i > 0u) {
            const uint32_t step = (uint32_t)fx_bam32_diff(scan->bearing[i], scan->bearing[i - 1u]);
            scan->flags[i - 1u] =
                link_between(params, &prev, &here, step, (uint64_t)step > 3u * spacing_bam);
        }
        prev = here;
    }
}

/* EGO_POINT_OBJECT on the points of every object (ego_scan.h): one pass
 * over the segments, each point marked once. */
static void mark_objects(ego_scan_t *scan)
{
    const int64_t extent_sq = (int64_t)EGO_OBJECT_EXTENT * EGO_OBJECT_EXTENT;
    const uint32_t n = scan->count;
    uint32_t first = 0u;
    for (uint32_t i = 0u; i < n; i++) {
        if (i + 1u < n && (scan->flags[i] & EGO_LINK_BREAK) == 0u) {
            continue; /* within a segment */
        }
        /* Within the longest range of each other: no overflow. */
        const int32_t dx = scan->x[i] - scan->x[first];
        const int32_t dy = scan->y[i] - scan->y[first];
        /* In front at both ends: beyond each a gap, or a point farther
         * (before the first: not rising to it; after the last: rising). */
        const uint8_t side = EGO_LINK_GAP | EGO_LINK_RISES;
        const bool object = first > 0u && i + 1u < n &&
                            (int64_t)dx * dx + (int64_t)dy * dy <= extent_sq &&
                            (scan->flags[first - 1u] & side) != EGO_LINK_RISES &&
                            (scan->flags[i] & side) != 0u;
        for (uint32_t k = first; object && k <= i; k++) {
            scan->flags[k] |= EGO_POINT_OBJECT;
        }
        first = i + 1u;
    }
}

ego_prep_status_t ego_scan_prepare(const ego_range_scan_t *in, const ego_prep_params_t *params,
                                   ego_scan_t *scan)
{
    return ego_scan_prepare_deskewed(in, params, NULL, scan);
}

/* The motion over a beam's offset tau (ns) from the scan's time: skew's
 * scaled by tau / dt (translation Q16.16 m, turn binary angle). */
typedef struct {
    int64_t x;
    int64_t y;
    int32_t turn;
} beam_motion_t;

static beam_motion_t motion_at(const ego_skew_t *skew, int64_t tau_ns)
{
    const int64_t dt_ns = (int64_t)skew->dt_us * 1000;
    const beam_motion_t m = {(int64_t)skew->motion.x * tau_ns / dt_ns,
                             (int64_t)skew->motion.y * tau_ns / dt_ns,
                             (int32_t)((int64_t)(int32_t)skew->motion.theta * tau_ns / dt_ns)};
    return m;
}

/* steps * step <= (EGO_MAX_SWEEP - 1) 2^32: rounded (ego_range_bearing),
 * the last of steps + 1 uniform beams then lies at most EGO_MAX_SWEEP after
 * the first. With step < 2^63 and steps < 2^16 the product's part above
 * 32 bits, q, is below 2^48: two 32 x 32-bit products, no 64-bit division
 * (a soft division on the Cortex-M3, 160 instructions a scan more). */
static bool uniform_within_sweep(uint64_t step, uint16_t steps)
{
    const uint64_t low = (step & 0xFFFFFFFFu) * steps;
    const uint64_t q = (step >> 32) * steps + (low >> 32);
    const uint64_t widest = EGO_MAX_SWEEP - 1u; /* in units of 2^32 */
    return q < widest || (q == widest && (uint32_t)low == 0u);
}

/* |v| <= EGO_MAX_ORIGIN: v + EGO_MAX_ORIGIN in [0, 2 EGO_MAX_ORIGIN], in
 * unsigned arithmetic (wrapping, defined) so one comparison does. */
static bool origin_ok(fx_q16_16_t v)
{
    return (uint32_t)v + (uint32_t)EGO_MAX_ORIGIN <= 2u * (uint32_t)EGO_MAX_ORIGIN;
}

/* ego_range.h; here, not inline there: ego_process and the preparation
 * both check, and a copy in each cost the 64 KiB image 0.2 KB. */
bool ego_range_check(const ego_range_scan_t *scan)
{
    if (scan == NULL || scan->count > EGO_MAX_BEAMS || (scan->count > 0u && scan->range == NULL) ||
        scan->range_unit_um == 0u || scan->range_unit_um > 500000u || !ego_range_times_ok(scan) ||
        !origin_ok(scan->origin_x) || !origin_ok(scan->origin_y)) {
        return false;
    }
    const uint16_t steps = (scan->count > 0u) ? (uint16_t)(scan->count - 1u) : 0u;
    if (scan->bearing == NULL) {
        const uint64_t half = (uint64_t)1 << 63;
        return scan->bearing_step != 0u && scan->bearing_step < half &&
               uniform_within_sweep(scan->bearing_step, steps);
    }
    uint64_t sweep = 0u;
    for (uint16_t k = 1u; k < scan->count; k++) {
        const uint32_t turn = scan->bearing[k] - scan->bearing[k - 1u];
        if (turn == 0u || turn >= 0x80000000u) {
            return false;
        }
        sweep += turn;
    }
    return sweep <= EGO_MAX_SWEEP;
}

/* The skew's motion is within EGO_MAX_SPEED over its interval (in whole
 * milliseconds, no 64-bit division), on each axis. */
static bool vehicle_motion(const ego_skew_t *skew)
{
    const int64_t most = (int64_t)(EGO_MAX_SPEED / 1000) * (skew->dt_us / 1000u); /* Q16.16 m */
    const int64_t x = skew->motion.x;
    const int64_t y = skew->motion.y;
    return x <= most && x >= -most && y <= most && y >= -most;
}

ego_prep_status_t ego_scan_prepare_deskewed(const ego_range_scan_t *in, const ego_prep_params_t *params,
                                            const ego_skew_t *skew, ego_scan_t *scan)
{
    if (in == NULL || params == NULL || scan == NULL) {
        return EGO_PREP_ERR_ARG;
    }
    scan->count = 0u;
    scan->beams = 0u;
    scan->spacing_arm = 0;
    scan->rms_range = 0;
    scan->origin_x = in->origin_x;
    scan->origin_y = in->origin_y;
    if (!ego_range_check(in)) {
        return EGO_PREP_ERR_LAYOUT;
    }
    scan->beams = in->count;
    /* Every beam_step-th beam, the spacing rounded to whole beams; at most
     * 8 (8 deg at 1-deg scans). */
    const uint32_t first_step = (in->count < 2u) ? 0u
                                : (uint32_t)(ego_range_bearing(in, 1u) - ego_range_bearing(in, 0u));
    uint32_t beam_step = (first_step == 0u) ? 1u
                         : (uint32_t)(((uint64_t)params->beam_spacing + first_step / 2u) / first_step);
    beam_step = (beam_step < 1u) ? 1u : ((beam_step > 8u) ? 8u : beam_step);

    /* De-skewing: a scan with beam times and a motion over a known
     * interval, a vehicle's (within EGO_MAX_SPEED: 8 m over 1 us, scaled to
     * a beam 10 ms off, moved points by 80 km); offsets from the scan's
     * time within +-1 s (ego_range.h), so a point moves 150 m at most. */
    const bool deskew = skew != NULL && skew->dt_us != 0u && (in->beam_ns != 0u || ego_range_passes(in) > 1u) &&
                        vehicle_motion(skew);
    const int64_t mean_ns = deskew ? (int64_t)ego_range_mean_ns(in) : 0;
    const uint64_t scale_q48 = q48_per_unit(in->range_unit_um);
    sensor_point_t prev = {0, 0, 0};
    uint64_t range_sq = 0u; /* sum of r^2 / 2^16, Q16 m^2: < 2^46 a point */
    uint16_t prev_beam = 0u;
    fx_bam32_t prev_bearing = 0u;
    for (uint32_t k = 0u; k < in->count; k += beam_step) {
        if (in->range[k] == 0u) {
            continue;
        }
        const fx_q16_16_t r = q16_from_units(in->range[k], scale_q48);
        if (r < params->min_range || r > params->max_range) {
            continue;
        }
        /* The link tests use the point relative to the sensor; they only
         * need lengths and cross products, which the bearing's frame does
         * not change. */
        const fx_bam32_t beam = ego_range_bearing(in, (uint16_t)k);
        fx_q2_30_t s;
        fx_q2_30_t c;
        fx_sincos(beam, &s, &c);
        const sensor_point_t here = {fx_mul_q16_q30(r, c), fx_mul_q16_q30(r, s), r};
        const uint64_t r_sq = ((uint64_t)r * (uint64_t)r) >> 16;

        const uint16_t i = scan->count;
        scan->x[i] = fx_add_q16(in->origin_x, here.x);
        scan->y[i] = fx_add_q16(in->origin_y, here.y);
        if (deskew) {
            /* The frame at the beam's time in the frame at the scan's: the
             * beam turned by m.turn (the sensor's offset turned to first
             * order: a 0.07 rad turn moves a 1 m offset 2.5 mm less),
             * then moved by m. */
            const beam_motion_t m = motion_at(skew, (int64_t)ego_range_beam_ns(in, (uint16_t)k) - mean_ns);
            fx_q2_30_t ts;
            fx_q2_30_t tc;
            fx_sincos(beam + (fx_bam32_t)(uint32_t)m.turn, &ts, &tc);
            const int64_t turn_q16 = fx_rad_q16_of_turn(m.turn);
            const int64_t ox = (int64_t)in->origin_x - (turn_q16 * in->origin_y) / 65536;
            const int64_t oy = (int64_t)in->origin_y + (turn_q16 * in->origin_x) / 65536;
            scan->x[i] = fx_sat_s32(ox + fx_mul_q16_q30(r, tc) + m.x);
            scan->y[i] = fx_sat_s32(oy + fx_mul_q16_q30(r, ts) + m.y);
            scan->bearing[i] = fx_atan2((int64_t)scan->y[i] - in->origin_y,
                                        (int64_t)scan->x[i] - in->origin_x);
            scan->tangent[i] = 0u;
            if (settle_by_bearing(scan, i)) {
                range_sq += r_sq;
                scan->count++; /* linked below, where the points are */
            }
            continue;
        }
        scan->bearing[i] = beam;
        scan->flags[i] = EGO_LINK_BREAK; /* until a next point links to it */
        scan->tangent[i] = 0u;

        if (i > 0u) {
            scan->flags[i - 1u] = link_between(params, &prev, &here, beam - prev_bearing,
                                               k != prev_beam + beam_step);
        }
        prev = here;
        prev_beam = (uint16_t)k;
        prev_bearing = beam;
        range_sq += r_sq;
        scan->count++;
    }
    const uint64_t step_bam = (uint64_t)first_step * beam_step; /* < 2^33 */
    if (deskew) {
        link_deskewed(scan, params, step_bam);
    }
    mark_objects(scan);
    if (scan->count > 0u) {
        /* rad Q30 = bam x 2 pi / 4 = bam x (pi / 2 x 2^29) / 2^29. */
        const uint64_t spacing_q30 = (step_bam * 843314857u) >> 29;
        const uint64_t rms = fx_sqrt_u64((range_sq / scan->count) << 16); /* Q16.16 m */
        scan->rms_range = (fx_q16_16_t)((rms < (uint64_t)INT32_MAX) ? rms : (uint64_t)INT32_MAX);
        const uint64_t arm = (rms * spacing_q30) >> 30;
        scan->spacing_arm = (fx_q16_16_t)((arm < (uint64_t)INT32_MAX) ? arm : (uint64_t)INT32_MAX);
    }
    return EGO_PREP_OK;
}
