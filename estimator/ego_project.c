/* ego_project.c - see ego_project.h. */
#include "ego_project.h"

#include <string.h>

#include "ego_fx_math.h"
#include "ego_work.h"

#define BIN_MASK (EGO_PROJECT_BINS - 1u)

/* A point whose tangent lies within this of the direction is on a surface
 * along it: it says nothing about a motion along it. */
#define ALONG_TOLERANCE FX_BAM32_DEG_C(30.0)

/* Cells closer than this (in cells, either axis) to a better one are the
 * same candidate. */
#define SAME_CELL 2

int32_t ego_project_side(fx_q16_16_t window, fx_q16_16_t bin)
{
    if (bin <= 0 || window <= 0) {
        return 0;
    }
    /* To the nearest cell: 1.6 m at 0.1 m is 16 cells, though the Q16.16
     * values of 0.1 (rounded up) make 1.6 / 0.1 = 15.99. */
    const int32_t n = (int32_t)(((int64_t)window + bin / 2) / bin);
    return (n > EGO_PROJECT_MAX_SIDE) ? EGO_PROJECT_MAX_SIDE : n;
}

/* Shifts on each side that a window of n cells reaches along any
 * direction: n (|cos| + |sin|) <= sqrt(2) n < 1.4375 n, plus one for
 * rounding. */
static int32_t shifts_of(int32_t n)
{
    return n + (7 * n + 15) / 16 + 1;
}

/* Units of one direction: both scans' points, its histograms' bins, and
 * the current histogram's filled bins times the shifts. */
static uint32_t direction_units(const ego_scan_t *last, const ego_scan_t *current,
                                uint32_t filled, uint32_t shifts)
{
    return ((uint32_t)last->count + current->count) * EGO_COST_PROJECT_POINT +
           2u * EGO_PROJECT_BINS * EGO_COST_PROJECT_BIN + filled * shifts * EGO_COST_PROJECT_PRODUCT;
}

/* Units of ranking the (2 n + 1)^2 cells of the window. */
static uint32_t cells_units(int32_t n)
{
    return (2u * (uint32_t)n + 1u) * (2u * (uint32_t)n + 1u) * EGO_COST_PROJECT_CELL;
}

/* The most a direction's correlation over `shifts` shifts can cost: every
 * current point in a bin of its own. */
static uint32_t direction_units_max(const ego_scan_t *last, const ego_scan_t *current,
                                    uint32_t shifts)
{
    const uint32_t filled = (current->count < EGO_PROJECT_BINS) ? current->count : EGO_PROJECT_BINS;
    return direction_units(last, current, filled, shifts);
}

uint32_t ego_project_direction_cost_max(const ego_scan_t *last, const ego_scan_t *current,
                                        fx_q16_16_t window, fx_q16_16_t bin)
{
    const int32_t n = ego_project_side(window, bin);
    return direction_units_max(last, current, 2u * (uint32_t)shifts_of(n) + 1u);
}

uint32_t ego_project_rank_cost(fx_q16_16_t window, fx_q16_16_t bin)
{
    return cells_units(ego_project_side(window, bin));
}

uint32_t ego_project_cost_max(const ego_scan_t *last, const ego_scan_t *current,
                              fx_q16_16_t window, fx_q16_16_t bin)
{
    return EGO_PROJECT_DIRS * ego_project_direction_cost_max(last, current, window, bin) +
           ego_project_rank_cost(window, bin);
}

/* floor(p / bin) for bin > 0. */
static int32_t floor_div(int32_t p, int32_t bin)
{
    const int32_t q = p / bin;
    return (p % bin != 0 && p < 0) ? q - 1 : q;
}

static void add_saturated(uint8_t *h, int32_t b, uint32_t v)
{
    const uint32_t i = (uint32_t)b & BIN_MASK;
    const uint32_t sum = h[i] + v;
    h[i] = (uint8_t)((sum > 255u) ? 255u : sum);
}

/* Does point i of scan s count along direction dir (its tangent turned by
 * turn): one at least ALONG_TOLERANCE from dir, or no tangent unless
 * tangent_needed. */
static bool faces(const ego_scan_t *s, uint16_t i, fx_bam32_t turn, fx_bam32_t dir,
                  bool tangent_needed)
{
    if ((s->flags[i] & EGO_POINT_HAS_TANGENT) == 0u) {
        return !tangent_needed;
    }
    return fx_line_angle_diff(s->tangent[i] + turn, dir) >= ALONG_TOLERANCE;
}

/* Direction k's correlation of the two histograms over shifts -m..m around
 * the window centre's bin, scaled to Q0.16 of its maximum; its units. The
 * direction dir is (c, s); the rotation tried (around->theta), (rc, rs). */
static uint32_t correlate_direction(const ego_scan_t *last, const ego_scan_t *current,
                                    const ego_pose_t *around, fx_q2_30_t rs, fx_q2_30_t rc,
                                    fx_bam32_t dir, fx_q2_30_t s, fx_q2_30_t c, fx_q16_16_t bin,
                                    int32_t m, bool tangent_needed, ego_project_scratch_t *w,
                                    unsigned k)
{
    memset(w->last, 0, sizeof w->last);
    memset(w->current, 0, sizeof w->current);
    /* The last scan's bins spread over their neighbours (2, 1, 1): a
     * current point a fraction of a bin off still meets its surface. */
    for (uint16_t i = 0u; i < last->count; i++) {
        if (faces(last, i, 0u, dir, tangent_needed)) {
            const int64_t p = ((int64_t)last->x[i] * c + (int64_t)last->y[i] * s) >> 30;
            const int32_t b = floor_div((int32_t)p, bin);
            add_saturated(w->last, b, 2u);
            add_saturated(w->last, b - 1, 1u);
            add_saturated(w->last, b + 1, 1u);
        }
    }
    const ego_pose_t turn = {around->theta, 0, 0};
    for (uint16_t i = 0u; i < current->count; i++) {
        if (faces(current, i, around->theta, dir, tangent_needed)) {
            fx_q16_16_t qx = 0;
            fx_q16_16_t qy = 0;
            ego_pose_apply(&turn, rs, rc, current->x[i], current->y[i], &qx, &qy);
            const int64_t p = ((int64_t)qx * c + (int64_t)qy * s) >> 30;
            add_saturated(w->current, floor_div((int32_t)p, bin), 1u);
        }
    }
    /* The centre's shift, rounded to the nearest bin. */
    const int64_t a = ((int64_t)around->x * c + (int64_t)around->y * s) >> 30;
    const int32_t centre = floor_div((int32_t)(a + bin / 2), bin);
    w->centre[k] = centre;
    const uint32_t shifts = 2u * (uint32_t)m + 1u;
    uint32_t sum[2 * EGO_PROJECT_MAX_SHIFT + 1];
    memset(sum, 0, sizeof sum);
    uint32_t filled = 0u;
    for (uint32_t b = 0u; b < EGO_PROJECT_BINS; b++) {
        const uint32_t h = w->current[b];
        if (h == 0u) {
            continue;
        }
        filled++;
        const uint32_t first = b + (uint32_t)(centre - m);
        for (uint32_t j = 0u; j < shifts; j++) {
            sum[j] += h * w->last[(first + j) & BIN_MASK];
        }
    }
    uint32_t top = 0u;
    for (uint32_t j = 0u; j < shifts; j++) {
        top = (sum[j] > top) ? sum[j] : top;
    }
    /* Scaled by one reciprocal (Q16: top < 2^25), not a division each. */
    const uint64_t scale = (top == 0u) ? 0u : ((uint64_t)65535u << 16) / top;
    for (uint32_t j = 0u; j < shifts; j++) {
        const uint64_t v = ((uint64_t)sum[j] * scale) >> 16;
        w->corr[k][j] = (uint16_t)((v > 65535u) ? 65535u : v);
    }
    return direction_units(last, current, filled, shifts);
}

/* Keeps cell (ix, iy) of score v among the best, at most one per
 * neighbourhood (SAME_CELL): a better cell nearby keeps it out, a worse
 * one nearby makes way. score[] runs parallel to out->cell[]. */
static void keep_best(ego_project_cells_t *out, uint64_t *score, int32_t *at, int32_t ix,
                      int32_t iy, uint64_t v, const ego_pose_t *pose)
{
    unsigned k = 0u;
    while (k < out->count) {
        const int32_t dx = at[2u * k] - ix;
        const int32_t dy = at[2u * k + 1u] - iy;
        const bool near = dx >= -SAME_CELL && dx <= SAME_CELL && dy >= -SAME_CELL && dy <= SAME_CELL;
        if (!near) {
            k++;
            continue;
        }
        if (score[k] >= v) {
            return;
        }
        for (unsigned q = k; q + 1u < out->count; q++) { /* remove k */
            score[q] = score[q + 1u];
            out->cell[q] = out->cell[q + 1u];
            at[2u * q] = at[2u * q + 2u];
            at[2u * q + 1u] = at[2u * q + 3u];
        }
        out->count--;
    }
    unsigned place = out->count;
    while (place > 0u && score[place - 1u] < v) {
        place--;
    }
    if (place >= EGO_PROJECT_CELLS) {
        return;
    }
    const unsigned end = (out->count < EGO_PROJECT_CELLS) ? out->count : EGO_PROJECT_CELLS - 1u;
    for (unsigned q = end; q > place; q--) {
        score[q] = score[q - 1u];
        out->cell[q] = out->cell[q - 1u];
        at[2u * q] = at[2u * q - 2u];
        at[2u * q + 1u] = at[2u * q - 1u];
    }
    score[place] = v;
    out->cell[place] = *pose;
    at[2u * place] = ix;
    at[2u * place + 1u] = iy;
    if (out->count < EGO_PROJECT_CELLS) {
        out->count++;
    }
}

/* Direction k: the last scan's main direction turned by k * 180 / DIRS deg. */
static fx_bam32_t direction_of(fx_bam32_t main_direction, unsigned k)
{
    return main_direction + (fx_bam32_t)(k * (FX_BAM32_HALF / EGO_PROJECT_DIRS));
}

uint32_t ego_project_direction(const ego_scan_t *last, const ego_scan_t *current,
                               fx_bam32_t main_direction, const ego_pose_t *around,
                               fx_q16_16_t window, fx_q16_16_t bin, unsigned k,
                               ego_project_scratch_t *scratch)
{
    const int32_t n = ego_project_side(window, bin);
    if (n == 0 || k >= EGO_PROJECT_DIRS) {
        return 0u;
    }
    fx_q2_30_t rs = 0;
    fx_q2_30_t rc = 0;
    fx_sincos(around->theta, &rs, &rc);
    const fx_bam32_t dir = direction_of(main_direction, k);
    fx_q2_30_t s = 0;
    fx_q2_30_t c = 0;
    fx_sincos(dir, &s, &c);
    return correlate_direction(last, current, around, rs, rc, dir, s, c, bin, shifts_of(n), false,
                               scratch, k);
}

uint32_t ego_project_rank(fx_bam32_t main_direction, const ego_pose_t *around, fx_q16_16_t window,
                          fx_q16_16_t bin, const ego_project_scratch_t *scratch,
                          ego_project_cells_t *out)
{
    out->count = 0u;
    const int32_t n = ego_project_side(window, bin);
    if (n == 0) {
        return 0u;
    }
    const int32_t m = shifts_of(n);
    fx_q2_30_t s[EGO_PROJECT_DIRS];
    fx_q2_30_t c[EGO_PROJECT_DIRS];
    for (unsigned k = 0u; k < EGO_PROJECT_DIRS; k++) {
        /* Its unit vector in Q2.30 bins per bin of motion. */
        fx_sincos(direction_of(main_direction, k), &s[k], &c[k]);
    }
    uint64_t score[EGO_PROJECT_CELLS];
    int32_t at[2u * EGO_PROJECT_CELLS];
    /* Cell (ix, iy) is the translation around + (ix, iy) bin: its
     * projection on direction k, in bins (Q2.30), is base[k] + ix c[k] +
     * iy s[k], base[k] the centre's own. */
    int64_t base[EGO_PROJECT_DIRS];
    for (unsigned k = 0u; k < EGO_PROJECT_DIRS; k++) {
        /* Q16.16 m times Q2.30: 46 fraction bits; over Q16.16 m: Q.30 bins. */
        base[k] = ((int64_t)around->x * c[k] + (int64_t)around->y * s[k]) / bin;
    }
    for (int32_t ix = -n; ix <= n; ix++) {
        /* Down a column each step adds s[k]: no multiplication per cell. */
        int64_t p[EGO_PROJECT_DIRS];
        for (unsigned k = 0u; k < EGO_PROJECT_DIRS; k++) {
            p[k] = base[k] + (int64_t)ix * c[k] - (int64_t)n * s[k];
        }
        for (int32_t iy = -n; iy <= n; iy++) {
            uint64_t v = 0u;
            for (unsigned k = 0u; k < EGO_PROJECT_DIRS; k++) {
                const int64_t j = ((p[k] + (INT64_C(1) << 29)) >> 30) - scratch->centre[k];
                if (j >= -m && j <= m) {
                    v += scratch->corr[k][j + m];
                }
                p[k] += s[k];
            }
            /* A full list whose worst is at least v has no room for it,
             * nor a worse neighbour to replace. */
            if (out->count < EGO_PROJECT_CELLS || v > score[EGO_PROJECT_CELLS - 1u]) {
                const ego_pose_t pose = {around->theta, fx_add_q16(around->x, ix * bin),
                                         fx_add_q16(around->y, iy * bin)};
                keep_best(out, score, at, ix, iy, v, &pose);
            }
        }
    }
    return cells_units(n);
}

uint32_t ego_project_cells(const ego_scan_t *last, const ego_scan_t *current,
                           fx_bam32_t main_direction, const ego_pose_t *around,
                           fx_q16_16_t window, fx_q16_16_t bin, ego_project_scratch_t *scratch,
                           ego_project_cells_t *out)
{
    uint32_t units = 0u;
    for (unsigned k = 0u; k < EGO_PROJECT_DIRS; k++) {
        units += ego_project_direction(last, current, main_direction, around, window, bin, k,
                                       scratch);
    }
    return units + ego_project_rank(main_direction, around, window, bin, scratch, out);
}

uint32_t ego_project_along_cost_max(const ego_scan_t *last, const ego_scan_t *current,
                                    fx_q16_16_t window, fx_q16_16_t bin)
{
    return direction_units_max(last, current, 2u * (uint32_t)ego_project_side(window, bin) + 1u);
}

bool ego_project_along(const ego_scan_t *last, const ego_scan_t *current, fx_bam32_t direction,
                       const ego_pose_t *around, fx_q16_16_t window, fx_q16_16_t bin,
                       ego_project_scratch_t *scratch, fx_q16_16_t *shift, uint32_t *units)
{
    *units = 0u;
    const int32_t n = ego_project_side(window, bin);
    if (n == 0) {
        return false;
    }
    fx_q2_30_t rs = 0;
    fx_q2_30_t rc = 0;
    fx_sincos(around->theta, &rs, &rc);
    fx_q2_30_t s = 0;
    fx_q2_30_t c = 0;
    fx_sincos(direction, &s, &c);
    /* Over a 1-D window: n shifts each side. Points with a tangent only:
     * in a corridor the points without one lie on its walls, and their
     * pattern (the beams' fixed bearings) looks the same from anywhere
     * along it: a standstill. */
    *units = correlate_direction(last, current, around, rs, rc, direction, s, c, bin, n, true,
                                 scratch, 0u);
    const uint16_t *corr = scratch->corr[0];
    int32_t best = 0;
    for (int32_t j = 1; j <= n; j++) { /* outwards from the centre: ties stay near it */
        if (corr[n + j] > corr[n + best]) {
            best = j;
        }
        if (corr[n - j] > corr[n + best]) {
            best = -j;
        }
    }
    if (corr[n + best] == 0u) {
        return false;
    }
    /* Best translation's projection (centre + best bins) less around's own. */
    const int64_t a = ((int64_t)around->x * c + (int64_t)around->y * s) >> 30;
    *shift = fx_sat_s32((int64_t)(scratch->centre[0] + best) * bin - a);
    return true;
}
