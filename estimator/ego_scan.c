/* ego_scan.c - see ego_scan.h. */
#include "ego_scan.h"

#include <stddef.h>
#include <string.h>

#include "ego_fx_math.h"

/* 0.01 deg in radians, Q2.30: round(pi / 18000 * 2^30). */
#define CDEG_RAD_Q30 187403
/* Centi-degrees in one turn, and a quarter turn (the scanner's 90-degree
 * beam is its x axis). */
#define CDEG_PER_TURN 36000u
#define CDEG_QUARTER 9000u

void ego_prep_defaults(ego_prep_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->min_range = FX_Q16_16_C(0.10);
    params->max_range = FX_Q16_16_C(81.9);
    params->jump_min = FX_Q16_16_C(0.30);
    params->jump_factor = 4u;
    params->occlusion_sin = 186453311; /* sin(10 deg), Q2.30 */
    params->meas_mode = (uint8_t)LMS_MEAS_8M_FIELDS_DAZZLE;
    params->beam_spacing_cdeg = 0u;
}

/* Binary angle of an angle in centi-degrees (0 .. 35999), rounded. */
static fx_bam32_t bam_from_cdeg(uint32_t cdeg)
{
    return (fx_bam32_t)((((uint64_t)cdeg << 32) + CDEG_PER_TURN / 2u) / CDEG_PER_TURN);
}

/* Millimetres to Q16.16 metres, rounded. */
static fx_q16_16_t q16_from_mm(uint32_t mm)
{
    return (fx_q16_16_t)((((uint64_t)mm << 16) + 500u) / 1000u);
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
    const uint32_t ab = fx_sqrt_u64((uint64_t)(dx * dx + dy * dy)); /* Q16.16 */
    const int64_t far = (a->r > b->r) ? a->r : b->r;
    /* Both sides scaled to Q46.(32+14) (< 2^60): the sine keeps 14 bits. */
    const int64_t lhs = ((cross < 0) ? -cross : cross) << 14;
    const int64_t rhs = far * (int64_t)ab * (int64_t)(p->occlusion_sin >> 16);
    return lhs < rhs;
}

ego_prep_status_t ego_scan_prepare(const lms_scan_t *lms, const ego_prep_params_t *params,
                                   ego_scan_t *scan)
{
    if (lms == NULL || params == NULL || scan == NULL) {
        return EGO_PREP_ERR_ARG;
    }
    scan->count = 0u;
    scan->values = 0u;
    scan->origin_x = params->mount_x;
    scan->origin_y = params->mount_y;
    if (lms_meas_mode_bits(params->meas_mode) == 0u ||
        params->meas_mode == (uint8_t)LMS_MEAS_REFLECTIVITY) {
        return EGO_PREP_ERR_ARG;
    }
    lms_layout_t layout;
    if (lms_scan_layout(lms, &layout) != LMS_OK || lms->count > EGO_MAX_POINTS) {
        return EGO_PREP_ERR_LAYOUT;
    }
    scan->values = lms->count;
    /* Every beam_step-th value; at most 8 (8 deg at 1-deg scans). */
    uint16_t beam_step = (uint16_t)(params->beam_spacing_cdeg / layout.step_cdeg);
    beam_step = (beam_step < 1u) ? 1u : ((beam_step > 8u) ? 8u : beam_step);
    const fx_q2_30_t step_rad = (fx_q2_30_t)(layout.step_cdeg * beam_step * CDEG_RAD_Q30);

    sensor_point_t prev = {0, 0, 0};
    uint16_t prev_value = 0u;
    for (uint16_t k = 0u; k < lms->count; k = (uint16_t)(k + beam_step)) {
        lms_value_t v;
        if (lms_value_decode(lms->values[k], params->meas_mode, lms->unit, &v) != LMS_OK ||
            v.kind != LMS_VALUE_RANGE) {
            continue;
        }
        const fx_q16_16_t r = q16_from_mm(v.distance_mm);
        if (r < params->min_range || r > params->max_range) {
            continue;
        }
        /* Beam direction in the vehicle frame: the LMS angle minus 90 deg
         * (scanner x ahead, y left), turned by the mounting angle. The link
         * tests use the point relative to the scanner; they only need
         * lengths and cross products, which the turn does not change. */
        const uint32_t lms_cdeg = (uint32_t)layout.start_cdeg + (uint32_t)k * layout.step_cdeg;
        const fx_bam32_t beam =
            bam_from_cdeg((lms_cdeg + CDEG_PER_TURN - CDEG_QUARTER) % CDEG_PER_TURN) +
            params->mount_theta;
        fx_q2_30_t s;
        fx_q2_30_t c;
        fx_sincos(beam, &s, &c);
        const sensor_point_t here = {fx_mul_q16_q30(r, c), fx_mul_q16_q30(r, s), r};

        const uint16_t i = scan->count;
        scan->x[i] = fx_add_q16(params->mount_x, here.x);
        scan->y[i] = fx_add_q16(params->mount_y, here.y);
        scan->bearing[i] = beam;
        scan->flags[i] = EGO_LINK_BREAK; /* until a next point links to it */
        scan->tangent[i] = 0u;
        scan->tangent_rms[i] = 0u;

        if (i > 0u) {
            uint8_t link = 0u;
            if (k != prev_value + beam_step) {
                link |= EGO_LINK_GAP;
            } else if (is_jump(params, prev.r, r, step_rad)) {
                link |= EGO_LINK_JUMP;
            }
            if ((link & EGO_LINK_GAP) == 0u && is_occlusion(params, &prev, &here)) {
                link |= EGO_LINK_OCCLUSION;
            }
            scan->flags[i - 1u] = (link != 0u) ? (uint8_t)(link | EGO_LINK_BREAK) : 0u;
        }
        prev = here;
        prev_value = k;
        scan->count++;
    }
    return EGO_PREP_OK;
}
