/* coarse.c - see coarse.h. */
#include "coarse.h"

#include <stddef.h>
#include <string.h>

#include "fx_math.h"
#include "itcp.h"

/* Largest sample; the defaults use 48. */
#define COARSE_MAX_SAMPLE 128u
/* Most translation steps on each side of the centre. */
#define COARSE_MAX_STEPS 20

void coarse_defaults(coarse_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->window = FX_Q16_16_C(0.6);
    params->step = FX_Q16_16_C(0.2);
    params->fine_step = FX_Q16_16_C(0.05);
    params->sigma = FX_Q16_16_C(0.10);
    params->rotation_steps = 1u;
    params->rotation_step = FX_BAM32_DEG_C(2.0);
    params->sample_points = 48u;
}

/* The sample: indices of current points spread evenly over the scan. */
typedef struct {
    uint16_t count;
    uint16_t index[COARSE_MAX_SAMPLE];
} sample_t;

static void take_sample(const ego_scan_t *cur, uint16_t wanted, sample_t *s)
{
    if (wanted > COARSE_MAX_SAMPLE) {
        wanted = COARSE_MAX_SAMPLE;
    }
    s->count = 0u;
    if (cur->count == 0u || wanted == 0u) {
        return;
    }
    const uint32_t n = (cur->count < wanted) ? cur->count : wanted;
    for (uint32_t k = 0u; k < n; k++) {
        s->index[s->count++] = (uint16_t)((k * cur->count + cur->count / 2u) / n);
    }
}

static uint64_t score_pose(const ego_scan_t *last, const ego_scan_t *cur, const sample_t *s,
                           const ego_pose_t *pose, fx_q16_16_t sigma)
{
    fx_q2_30_t sn;
    fx_q2_30_t cs;
    fx_sincos(pose->theta, &sn, &cs);
    const uint64_t sigma_sq = (uint64_t)((int64_t)sigma * sigma);
    uint64_t score = 0u;
    for (uint16_t k = 0u; k < s->count; k++) {
        const uint16_t i = s->index[k];
        fx_q16_16_t qx;
        fx_q16_16_t qy;
        ego_pose_apply(pose, sn, cs, cur->x[i], cur->y[i], &qx, &qy);
        uint64_t d2 = 0u;
        if (itcp_nearest(last, qx, qy, sigma, &d2) && d2 < sigma_sq) {
            score += (sigma_sq - d2) >> 16; /* Q16.16 m^2 per point */
        }
    }
    return score;
}

static int32_t steps_in(fx_q16_16_t half, fx_q16_16_t step)
{
    if (step <= 0) {
        return 0;
    }
    const int32_t n = half / step;
    return (n > COARSE_MAX_STEPS) ? COARSE_MAX_STEPS : n;
}

/* Tries the square grid around *around; keeps improvements in *best. */
static void grid(const ego_scan_t *last, const ego_scan_t *cur, const sample_t *s,
                 const ego_pose_t *around, fx_q16_16_t half, fx_q16_16_t step, fx_q16_16_t sigma,
                 ego_pose_t *best, uint64_t *best_score)
{
    const int32_t n = steps_in(half, step);
    for (int32_t ix = -n; ix <= n; ix++) {
        for (int32_t iy = -n; iy <= n; iy++) {
            const ego_pose_t p = {around->theta, fx_add_q16(around->x, ix * step),
                                  fx_add_q16(around->y, iy * step)};
            const uint64_t sc = score_pose(last, cur, s, &p, sigma);
            if (sc > *best_score) {
                *best_score = sc;
                *best = p;
            }
        }
    }
}

void coarse_search(const ego_scan_t *last, const ego_scan_t *current, const ego_pose_t *centre,
                   const coarse_params_t *params, ego_pose_t *best, uint64_t *score)
{
    *best = *centre;
    *score = 0u;
    if (last == NULL || current == NULL || last->count < 2u) {
        return;
    }
    sample_t s;
    take_sample(current, params->sample_points, &s);
    /* The score's distance scale follows the grid: with a finer scale than
     * the step, the grid point nearest the truth (up to 0.7 steps away)
     * may score below a wrong pose that happens to fit a few points. */
    const fx_q16_16_t coarse_sigma = (params->step > params->sigma) ? params->step : params->sigma;
    *score = score_pose(last, current, &s, centre, params->sigma);
    const int32_t r = params->rotation_steps;
    for (int32_t k = -r; k <= r; k++) {
        /* Coarse grid for this rotation, then the fine pass around its
         * best: the rotations compete on the fine score only, because a
         * coarse grid point's score depends on how near the truth the grid
         * happens to fall. */
        ego_pose_t around = *centre;
        around.theta += (fx_bam32_t)((uint32_t)k * params->rotation_step);
        ego_pose_t coarse_best = around;
        uint64_t coarse_score = score_pose(last, current, &s, &around, coarse_sigma);
        grid(last, current, &s, &around, params->window, params->step, coarse_sigma, &coarse_best,
             &coarse_score);
        grid(last, current, &s, &coarse_best, params->step, params->fine_step, params->sigma,
             best, score);
    }
}
