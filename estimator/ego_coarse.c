/* ego_coarse.c - see ego_coarse.h. */
#include "ego_coarse.h"

#include <stddef.h>
#include <string.h>

#include "ego_fx_math.h"
#include "ego_itcp.h"

/* Largest sample; the defaults use 48. */
#define EGO_COARSE_MAX_SAMPLE 128u
/* Most translation steps on each side of the centre. */
#define EGO_COARSE_MAX_STEPS 20

void ego_coarse_defaults(ego_coarse_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->window = FX_Q16_16_C(0.6);
    params->step = FX_Q16_16_C(0.1);
    params->fine_step = FX_Q16_16_C(0.05);
    params->sigma = FX_Q16_16_C(0.10);
    params->rotation_steps = 2u;
    params->rotation_step = FX_BAM32_DEG_C(2.0);
    params->sample_points = 48u;
    params->main_tolerance = FX_BAM32_DEG_C(10.0);
}

/* The sample: indices of current points, in two groups scored with equal
 * total weight (the eq. 10 idea applied to the search): points whose
 * tangent lies along the main direction, and all others. In a corridor
 * the walls say nothing about the motion along it; the few points on
 * door frames and end walls do, and an even sample over the scan would
 * hold only one or two of them. */
typedef struct {
    uint16_t count[2];
    uint16_t index[2][EGO_COARSE_MAX_SAMPLE];
} sample_t;

/* Same rule as ITCP's: tangent directions modulo 180 deg. */
static bool on_main(const ego_scan_t *cur, uint16_t i, fx_bam32_t main_dir, fx_bam32_t tol)
{
    return (cur->flags[i] & EGO_POINT_HAS_TANGENT) != 0u &&
           fx_line_angle_diff(cur->tangent[i], main_dir) <= tol;
}

#define GROUP_ALL 2u /* take_group: every point, into group 0 */

/* Takes `wanted` indices spread evenly over the points of group g (0: on
 * the main direction, 1: the others, GROUP_ALL: all points, stored as
 * group 0). */
static void take_group(const ego_scan_t *cur, fx_bam32_t main_dir, fx_bam32_t tol, unsigned g,
                       uint16_t in_group, uint16_t wanted, sample_t *s)
{
    const unsigned slot = (g == GROUP_ALL) ? 0u : g;
    s->count[slot] = 0u;
    if (in_group == 0u || wanted == 0u) {
        return;
    }
    const uint32_t n = (in_group < wanted) ? in_group : wanted;
    uint32_t seen = 0u; /* group members passed so far */
    uint32_t next = 0u; /* sample slot to fill */
    for (uint16_t i = 0u; i < cur->count && next < n; i++) {
        if (g != GROUP_ALL && (on_main(cur, i, main_dir, tol) ? 0u : 1u) != g) {
            continue;
        }
        /* Slot k takes the group's member number (k in_group + in_group / 2) / n. */
        if (seen == (next * in_group + in_group / 2u) / n) {
            s->index[slot][s->count[slot]++] = i;
            next++;
        }
        seen++;
    }
}

static void take_sample(const ego_scan_t *cur, fx_bam32_t main_dir, fx_bam32_t tol,
                        uint16_t wanted, sample_t *s)
{
    if (wanted > EGO_COARSE_MAX_SAMPLE) {
        wanted = EGO_COARSE_MAX_SAMPLE;
    }
    uint16_t members[2] = {0u, 0u};
    for (uint16_t i = 0u; i < cur->count; i++) {
        members[on_main(cur, i, main_dir, tol) ? 0u : 1u]++;
    }
    /* A group under a fifth of the points is too small to be weighed on
     * its own (its few points' fit is noise): one even sample over all. */
    const uint16_t smaller = (members[0] < members[1]) ? members[0] : members[1];
    if (5u * (uint32_t)smaller < (uint32_t)members[0] + members[1]) {
        take_group(cur, main_dir, tol, GROUP_ALL, cur->count, wanted, s);
        s->count[1] = 0u;
        return;
    }
    /* Half each. */
    uint16_t want[2] = {(uint16_t)(wanted / 2u), (uint16_t)(wanted - wanted / 2u)};
    for (uint8_t g = 0u; g < 2u; g++) {
        const uint8_t o = (uint8_t)(1u - g);
        if (members[g] < want[g]) {
            want[o] = (uint16_t)(want[o] + want[g] - members[g]);
            want[g] = members[g];
        }
    }
    take_group(cur, main_dir, tol, 0u, members[0], want[0], s);
    take_group(cur, main_dir, tol, 1u, members[1], want[1], s);
}

/* Score of one group so far: its points' sum and its penalties. */
typedef struct {
    uint64_t score;
    uint64_t penalty;
} tally_t;

static uint64_t tally_value(const tally_t *t)
{
    return (t->score > t->penalty) ? t->score - t->penalty : 0u;
}

/* The most a group can still reach with `left` points unscored, each
 * scoring at most sigma^2 and none penalised. */
static uint64_t tally_bound(const tally_t *t, uint32_t left, uint64_t per_point)
{
    const uint64_t top = t->score + left * per_point;
    return (top > t->penalty) ? top - t->penalty : 0u;
}

/* Each group's sum weighted by the other group's size: equal total weight
 * per group (one group empty: the plain sum). Bound: 2 * 128 points *
 * sigma^2 (< 2^32 for sigma < 256 m) * 128 < 2^47. */
static uint64_t combine(const sample_t *s, uint64_t main_value, uint64_t other_value)
{
    if (s->count[0] == 0u || s->count[1] == 0u) {
        return main_value + other_value;
    }
    return main_value * s->count[1] + other_value * s->count[0];
}

/* The score of pose: per sample point max(0, sigma^2 - d^2) for a surface
 * at d < sigma, minus sigma^2 where the last scan saw through it; per group
 * clipped at 0, then combined. A pose that cannot beat must_beat even if
 * every point left scored fully (or only tie with it, unless ties_win) is
 * abandoned: it then returns a value that does not beat must_beat (at most
 * must_beat, below it unless ties_win), so the grids, which keep only
 * poses that beat the best, choose as if every point had been scored. */
static uint64_t score_pose(const ego_scan_t *last, const ego_scan_t *cur, const sample_t *s,
                           const ego_pose_t *pose, fx_q16_16_t sigma, uint64_t must_beat,
                           bool ties_win)
{
    fx_q2_30_t sn;
    fx_q2_30_t cs;
    fx_sincos(pose->theta, &sn, &cs);
    const uint64_t sigma_sq = (uint64_t)((int64_t)sigma * sigma);
    const uint64_t per_point = sigma_sq >> 16; /* Q16.16 m^2 */
    ego_itcp_prober_t prober;
    ego_itcp_prober_init(&prober, last, sigma, 2 * sigma);
    tally_t t[2] = {{0u, 0u}, {0u, 0u}};
    for (uint8_t g = 0u; g < 2u; g++) {
        for (uint16_t k = 0u; k < s->count[g]; k++) {
            const uint16_t i = s->index[g][k];
            fx_q16_16_t qx;
            fx_q16_16_t qy;
            ego_pose_apply(pose, sn, cs, cur->x[i], cur->y[i], &qx, &qy);
            uint64_t d2 = 0u;
            const ego_itcp_probe_t found = ego_itcp_probe(&prober, qx, qy, &d2);
            if (found == EGO_ITCP_PROBE_SURFACE) {
                t[g].score += (sigma_sq - d2) >> 16;
            } else if (found == EGO_ITCP_PROBE_SEEN_THROUGH) {
                t[g].penalty += per_point; /* in space the last scan saw empty */
            }
            const uint32_t left = (uint32_t)s->count[g] - k - 1u;
            const uint64_t bound =
                (g == 0u) ? combine(s, tally_bound(&t[0], left, per_point),
                                    tally_bound(&t[1], s->count[1], per_point))
                          : combine(s, tally_value(&t[0]), tally_bound(&t[1], left, per_point));
            if (bound < must_beat || (bound == must_beat && !ties_win)) {
                return bound;
            }
        }
    }
    return combine(s, tally_value(&t[0]), tally_value(&t[1]));
}

static int32_t steps_in(fx_q16_16_t half, fx_q16_16_t step)
{
    if (step <= 0) {
        return 0;
    }
    const int32_t n = half / step;
    return (n > EGO_COARSE_MAX_STEPS) ? EGO_COARSE_MAX_STEPS : n;
}

/* One square grid of translations around a pose, and the best pose so far. */
typedef struct {
    const ego_scan_t *last;
    const ego_scan_t *cur;
    const sample_t *sample;
    ego_pose_t around;
    fx_q16_16_t step;
    fx_q16_16_t sigma;
    int32_t n;          /* steps on each side */
    ego_pose_t best;
    uint64_t best_score;
    int32_t best_rank;  /* the best's place in row order, -1: it came from outside */
} grid_t;

/* Scores the grid point (ix, iy). The points are visited in rings from the
 * centre (the prediction is usually close, and an early good score lets
 * score_pose abandon the far points sooner), but the choice is the one a
 * visit in row order (ix, then iy, ascending) keeping strict improvements
 * would make: a tie goes to the point earlier in row order, never past a
 * best that came from outside the grid. */
static void grid_point(grid_t *g, int32_t ix, int32_t iy)
{
    const int32_t rank = (ix + g->n) * (2 * g->n + 1) + (iy + g->n);
    const bool ties_win = g->best_rank > rank;
    const ego_pose_t p = {g->around.theta, fx_add_q16(g->around.x, ix * g->step),
                          fx_add_q16(g->around.y, iy * g->step)};
    const uint64_t sc =
        score_pose(g->last, g->cur, g->sample, &p, g->sigma, g->best_score, ties_win);
    if (sc > g->best_score || (sc == g->best_score && ties_win)) {
        g->best_score = sc;
        g->best = p;
        g->best_rank = rank;
    }
}

/* Tries the square grid around *around; keeps improvements in *best. */
static void grid(const ego_scan_t *last, const ego_scan_t *cur, const sample_t *s,
                 const ego_pose_t *around, fx_q16_16_t half, fx_q16_16_t step, fx_q16_16_t sigma,
                 ego_pose_t *best, uint64_t *best_score)
{
    grid_t g = {last, cur, s, *around, step, sigma, steps_in(half, step), *best, *best_score, -1};
    grid_point(&g, 0, 0);
    for (int32_t k = 1; k <= g.n; k++) { /* the ring max(|ix|, |iy|) = k */
        for (int32_t i = -k; i <= k; i++) {
            grid_point(&g, i, -k);
            grid_point(&g, i, k);
        }
        for (int32_t i = -k + 1; i < k; i++) {
            grid_point(&g, -k, i);
            grid_point(&g, k, i);
        }
    }
    *best = g.best;
    *best_score = g.best_score;
}

void ego_coarse_search(const ego_scan_t *last, const ego_scan_t *current, fx_bam32_t main_direction,
                   const ego_pose_t *centre, const ego_coarse_params_t *params, ego_pose_t *best,
                   uint64_t *score)
{
    *best = *centre;
    *score = 0u;
    if (last == NULL || current == NULL || last->count < 2u) {
        return;
    }
    sample_t s;
    /* The main direction in the current scan's frame. */
    take_sample(current, main_direction - centre->theta, params->main_tolerance,
                params->sample_points, &s);
    /* The score's distance scale follows the grid: with a finer scale than
     * the step, the grid point nearest the truth (up to 0.7 steps away)
     * may score below a wrong pose that happens to fit a few points. */
    const fx_q16_16_t coarse_sigma = (params->step > params->sigma) ? params->step : params->sigma;
    *score = score_pose(last, current, &s, centre, params->sigma, 0u, true);
    const int32_t r = params->rotation_steps;
    for (int32_t k = -r; k <= r; k++) {
        /* Coarse grid for this rotation, then the fine pass around its
         * best: the rotations compete on the fine score only, because a
         * coarse grid point's score depends on how near the truth the grid
         * happens to fall. */
        ego_pose_t around = *centre;
        around.theta += (fx_bam32_t)((uint32_t)k * params->rotation_step);
        ego_pose_t coarse_best = around;
        uint64_t coarse_score = score_pose(last, current, &s, &around, coarse_sigma, 0u, true);
        grid(last, current, &s, &around, params->window, params->step, coarse_sigma, &coarse_best,
             &coarse_score);
        grid(last, current, &s, &coarse_best, params->step, params->fine_step, params->sigma,
             best, score);
    }
}
