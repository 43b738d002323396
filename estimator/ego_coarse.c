/* ego_coarse.c - see ego_coarse.h. */
#include "ego_coarse.h"

#include <stddef.h>
#include <string.h>

#include "ego_fx_math.h"
#include "ego_itcp.h"

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
                       uint16_t in_group, uint16_t wanted, ego_coarse_sample_t *s)
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
                        uint16_t wanted, ego_coarse_sample_t *s)
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
typedef ego_coarse_tally_t tally_t;

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
static uint64_t combine(const ego_coarse_sample_t *s, uint64_t main_value, uint64_t other_value)
{
    if (s->count[0] == 0u || s->count[1] == 0u) {
        return main_value + other_value;
    }
    return main_value * s->count[1] + other_value * s->count[0];
}

/* Where the run is (ego_coarse_run_t.phase). */
enum {
    PHASE_SAMPLE = 0, /* take the sample */
    PHASE_CENTRE,     /* score the centre */
    PHASE_ROTATION,   /* the next rotation: score its centre */
    PHASE_COARSE,     /* its coarse grid */
    PHASE_FINE,       /* the fine grid around the coarse grid's best */
    PHASE_PROJECT,    /* projected: rank the rotation's window */
    PHASE_CELLS,      /* projected: the best cells' neighbourhoods */
    PHASE_DONE
};

/* Work of one sample point beyond its probe, and of starting a pose. */
#define COST_SAMPLE_POINT 80u
#define COST_SCORE_POINT 150u
#define COST_POSE 600u
#define COST_PROBE_MAX (EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK) + COST_SCORE_POINT)

/* Starts scoring pose: per sample point max(0, sigma^2 - d^2) for a
 * surface at d < sigma, minus sigma^2 where the last scan saw through it;
 * per group clipped at 0, then combined. A pose that cannot beat must_beat
 * even if every point left scored fully (or only tie with it, unless
 * ties_win) is abandoned: its value then does not beat must_beat (at most
 * must_beat, below it unless ties_win), so the grids, which keep only
 * poses that beat the best, choose as if every point had been scored. */
static void score_begin(ego_coarse_run_t *r, const ego_pose_t *pose, fx_q16_16_t sigma,
                        uint64_t must_beat, bool ties_win)
{
    ego_coarse_score_t *sc = &r->scoring;
    sc->active = true;
    sc->pose = *pose;
    fx_sincos(pose->theta, &sc->sn, &sc->cs);
    sc->sigma = sigma;
    sc->sigma_sq = (uint64_t)((int64_t)sigma * sigma);
    sc->must_beat = must_beat;
    sc->ties_win = ties_win;
    ego_itcp_prober_init(&sc->prober, r->last, sigma, 2 * sigma);
    memset(sc->tally, 0, sizeof sc->tally);
    sc->group = 0u;
    sc->next = 0u;
    sc->value = 0u;
}

/* Scores points of the pose begun until it is decided (true, value in
 * scoring.value) or the meter cannot pay for another point (false). */
static bool score_points(ego_coarse_run_t *r, ego_work_t *work)
{
    ego_coarse_score_t *sc = &r->scoring;
    const ego_coarse_sample_t *s = &r->sample;
    const uint64_t per_point = sc->sigma_sq >> 16; /* Q16.16 m^2 */
    tally_t *t = sc->tally;
    while (sc->group < 2u) {
        const uint8_t g = sc->group;
        if (sc->next >= s->count[g]) {
            sc->group++;
            sc->next = 0u;
            continue;
        }
        if (!ego_work_allows(work, (r->along != NULL) ? EGO_TRACK_PROBE_MAX + COST_SCORE_POINT
                                                      : COST_PROBE_MAX)) {
            return false;
        }
        const uint16_t i = s->index[g][sc->next];
        fx_q16_16_t qx;
        fx_q16_16_t qy;
        ego_pose_apply(&sc->pose, sc->sn, sc->cs, r->current->x[i], r->current->y[i], &qx, &qy);
        uint64_t d2 = 0u;
        uint32_t units = 0u;
        ego_itcp_probe_t found;
        if (r->along != NULL) {
            found = ego_track_probe(r->along, qx, qy, sc->sigma, &d2, &units);
        } else {
            found = ego_itcp_probe(&sc->prober, qx, qy, &d2);
            units = ego_itcp_prober_take_units(&sc->prober);
        }
        ego_work_spend(work, units + COST_SCORE_POINT);
        if (found == EGO_ITCP_PROBE_SURFACE) {
            t[g].score += (sc->sigma_sq - d2) >> 16;
        } else if (found == EGO_ITCP_PROBE_SEEN_THROUGH) {
            t[g].penalty += per_point; /* in space the last scan saw empty */
        }
        sc->next++;
        const uint32_t left = (uint32_t)s->count[g] - sc->next;
        const uint64_t bound =
            (g == 0u) ? combine(s, tally_bound(&t[0], left, per_point),
                                tally_bound(&t[1], s->count[1], per_point))
                      : combine(s, tally_value(&t[0]), tally_bound(&t[1], left, per_point));
        if (bound < sc->must_beat || (bound == sc->must_beat && !sc->ties_win)) {
            sc->value = bound;
            sc->active = false;
            return true;
        }
    }
    sc->value = combine(s, tally_value(&t[0]), tally_value(&t[1]));
    sc->active = false;
    return true;
}

static int32_t steps_in(fx_q16_16_t half, fx_q16_16_t step)
{
    if (step <= 0) {
        return 0;
    }
    const int32_t n = half / step;
    return (n > EGO_COARSE_MAX_STEPS) ? EGO_COARSE_MAX_STEPS : n;
}

/* Starts a square grid of translations around *around at step, scored
 * with sigma, that keeps the best of *best (score best_score) and its own
 * points. The points are visited in rings from the centre (the prediction
 * is usually close, and an early good score lets scoring abandon the far
 * points sooner), but the choice is the one a visit in row order (ix,
 * then iy, ascending) keeping strict improvements would make: a tie goes
 * to the point earlier in row order, never past a best that came from
 * outside the grid. */
static void grid_begin(ego_coarse_grid_t *g, const ego_pose_t *around, fx_q16_16_t half,
                       fx_q16_16_t step, fx_q16_16_t sigma, const ego_pose_t *best,
                       uint64_t best_score)
{
    g->around = *around;
    g->step = step;
    g->sigma = sigma;
    g->n = steps_in(half, step);
    g->best = *best;
    g->best_score = best_score;
    g->best_rank = -1;
    g->ring = 0;
    g->at = 0;
}

/* The grid's next point (ix, iy): false when every point was visited.
 * Ring k >= 1 (max(|ix|, |iy|) = k, 8k points): (i, -k), (i, k) for i =
 * -k .. k, then (-k, i), (k, i) for i = -k + 1 .. k - 1. */
static bool grid_next(const ego_coarse_grid_t *g, int32_t *ix, int32_t *iy)
{
    const int32_t k = g->ring;
    if (k > g->n) {
        return false;
    }
    if (k == 0) {
        *ix = 0;
        *iy = 0;
        return true;
    }
    const int32_t m = g->at;
    if (m < 2 * (2 * k + 1)) {
        *ix = -k + m / 2;
        *iy = (m % 2 == 0) ? -k : k;
    } else {
        const int32_t i = -k + 1 + (m - 2 * (2 * k + 1)) / 2;
        *ix = ((m % 2) == 0) ? -k : k;
        *iy = i;
    }
    return true;
}

static void grid_advance(ego_coarse_grid_t *g)
{
    g->at++;
    if (g->ring == 0 || g->at >= 8 * g->ring) {
        g->ring++;
        g->at = 0;
    }
}

static int32_t grid_rank(const ego_coarse_grid_t *g, int32_t ix, int32_t iy)
{
    return (ix + g->n) * (2 * g->n + 1) + (iy + g->n);
}

/* Begins scoring the grid's next point; false when the grid is done. */
static bool grid_score_next(ego_coarse_run_t *r)
{
    ego_coarse_grid_t *g = &r->grid;
    int32_t ix = 0;
    int32_t iy = 0;
    if (!grid_next(g, &ix, &iy)) {
        return false;
    }
    const int32_t rank = grid_rank(g, ix, iy);
    const ego_pose_t p = {g->around.theta, fx_add_q16(g->around.x, ix * g->step),
                          fx_add_q16(g->around.y, iy * g->step)};
    score_begin(r, &p, g->sigma, g->best_score, g->best_rank > rank);
    return true;
}

/* The scored grid point's value against the grid's best. */
static void grid_take(ego_coarse_run_t *r)
{
    ego_coarse_grid_t *g = &r->grid;
    int32_t ix = 0;
    int32_t iy = 0;
    (void)grid_next(g, &ix, &iy);
    const int32_t rank = grid_rank(g, ix, iy);
    const bool ties_win = g->best_rank > rank;
    const uint64_t sc = r->scoring.value;
    if (sc > g->best_score || (sc == g->best_score && ties_win)) {
        g->best_score = sc;
        g->best = r->scoring.pose;
        g->best_rank = rank;
    }
    grid_advance(g);
}

void ego_coarse_start(ego_coarse_run_t *r, const ego_scan_t *last, const ego_scan_t *current,
                      fx_bam32_t main_direction, const ego_pose_t *centre,
                      const ego_coarse_params_t *params)
{
    memset(r, 0, sizeof *r);
    r->last = last;
    r->current = current;
    r->params = *params;
    r->main_direction = main_direction;
    r->centre = *centre;
    r->best = *centre;
    r->score = 0u;
    r->rotation = -(int32_t)params->rotation_steps;
    r->phase = (last == NULL || current == NULL || last->count < 2u) ? PHASE_DONE : PHASE_SAMPLE;
}

void ego_coarse_along_bearing(ego_coarse_run_t *r, ego_track_run_t *prober,
                              const ego_track_params_t *params)
{
    if (r->last != NULL) {
        ego_track_probe_start(prober, r->last, params);
        r->along = prober;
        r->along_params = params;
    }
}

void ego_coarse_projected(ego_coarse_run_t *r, ego_project_scratch_t *scratch)
{
    if (r->along != NULL) {
        r->scratch = scratch;
    }
}

/* Projected: a rotation whose cells score no more than half the best
 * cell of the rotations before it is passed over, fine grid and all. The
 * grid point nearest the true pose lies at most 0.7 steps from it, where
 * a point's score max(0, sigma^2 - d^2) keeps half of its most: a
 * rotation below half the best has nothing near the truth. Wrong
 * rotations are what a sweep is made of, and they are the dear ones: no
 * good pose lets their scoring stop early. */
static uint64_t cells_cut(const ego_coarse_run_t *r)
{
    const uint64_t half = r->cells_best / 2u;
    return (half > r->grid.best_score) ? half : r->grid.best_score;
}

/* Projected: the 3 x 3 neighbourhood of the cells, one pose at a time;
 * false when every one was scored. */
static bool cells_score_next(ego_coarse_run_t *r, fx_q16_16_t sigma)
{
    const uint32_t k = r->cell;
    if (k >= 9u * r->cells.count) {
        return false;
    }
    const int32_t ix = (int32_t)((k % 9u) / 3u) - 1;
    const int32_t iy = (int32_t)(k % 3u) - 1;
    const ego_pose_t *c = &r->cells.cell[k / 9u];
    const ego_pose_t p = {c->theta, fx_add_q16(c->x, ix * r->params.step),
                          fx_add_q16(c->y, iy * r->params.step)};
    score_begin(r, &p, sigma, cells_cut(r), false);
    return true;
}

bool ego_coarse_step(ego_coarse_run_t *r, ego_work_t *work)
{
    const ego_coarse_params_t *p = &r->params;
    /* The score's distance scale follows the grid: with a finer scale than
     * the step, the grid point nearest the truth (up to 0.7 steps away)
     * may score below a wrong pose that happens to fit a few points. */
    const fx_q16_16_t coarse_sigma = (p->step > p->sigma) ? p->step : p->sigma;
    for (;;) {
        if (r->scoring.active) {
            if (!score_points(r, work)) {
                return false;
            }
            switch (r->phase) {
            case PHASE_CENTRE:
                r->score = r->scoring.value;
                r->phase = PHASE_ROTATION;
                break;
            case PHASE_ROTATION:
                grid_begin(&r->grid, &r->around, p->window, p->step, coarse_sigma, &r->around,
                           r->scoring.value);
                r->phase = PHASE_COARSE;
                break;
            case PHASE_CELLS:
                if (r->scoring.value > cells_cut(r)) {
                    r->grid.best_score = r->scoring.value;
                    r->grid.best = r->scoring.pose;
                }
                r->cell++;
                break;
            default: /* a grid point */
                grid_take(r);
                break;
            }
            continue;
        }
        if (r->phase != PHASE_DONE && !ego_work_allows(work, COST_POSE)) {
            return false;
        }
        switch (r->phase) {
        case PHASE_SAMPLE: {
            const uint32_t cost = (uint32_t)r->current->count * COST_SAMPLE_POINT;
            if (!ego_work_allows(work, cost)) {
                return false;
            }
            ego_work_spend(work, cost);
            /* The main direction in the current scan's frame. */
            take_sample(r->current, r->main_direction - r->centre.theta, p->main_tolerance,
                        p->sample_points, &r->sample);
            r->phase = PHASE_CENTRE;
            ego_work_spend(work, COST_POSE);
            score_begin(r, &r->centre, p->sigma, 0u, true);
            break;
        }
        case PHASE_ROTATION:
            if (r->rotation > (int32_t)p->rotation_steps) {
                r->phase = PHASE_DONE;
                break;
            }
            /* Coarse grid for this rotation, then the fine pass around its
             * best: the rotations compete on the fine score only, because a
             * coarse grid point's score depends on how near the truth the
             * grid happens to fall. */
            r->around = r->centre;
            r->around.theta += (fx_bam32_t)((uint32_t)r->rotation * p->rotation_step);
            if (r->scratch != NULL) {
                r->phase = PHASE_PROJECT;
                r->direction = 0u;
                break;
            }
            ego_work_spend(work, COST_POSE);
            score_begin(r, &r->around, coarse_sigma, 0u, true);
            break;
        case PHASE_PROJECT: {
            /* A direction a step (a sensor-rate budget may not hold the
             * whole ranking of a 361-value scan's window), then the cells. */
            const bool ranking = r->direction >= EGO_PROJECT_DIRS;
            const uint32_t most = ranking ? ego_project_rank_cost(p->window, p->step)
                                          : ego_project_direction_cost_max(r->last, r->current,
                                                                           p->window, p->step);
            if (!ego_work_allows(work, most)) {
                return false;
            }
            if (!ranking) {
                ego_work_spend(work, ego_project_direction(r->last, r->current, r->main_direction,
                                                           &r->around, p->window, p->step,
                                                           r->direction, r->scratch));
                r->direction++;
                break;
            }
            ego_work_spend(work, ego_project_rank(r->main_direction, &r->around, p->window, p->step,
                                                  r->scratch, &r->cells));
            /* The ranking overwrote the prober's cached normals. */
            ego_track_probe_start(r->along, r->last, r->along_params);
            grid_begin(&r->grid, &r->around, 0, p->step, coarse_sigma, &r->around, 0u);
            r->cell = 0u;
            r->phase = PHASE_CELLS;
            break;
        }
        case PHASE_CELLS:
            ego_work_spend(work, COST_POSE);
            if (!cells_score_next(r, coarse_sigma)) {
                if (r->grid.best_score <= r->cells_best / 2u) {
                    r->rotation++; /* nothing near the truth */
                    r->phase = PHASE_ROTATION;
                    break;
                }
                r->cells_best = (r->grid.best_score > r->cells_best) ? r->grid.best_score
                                                                     : r->cells_best;
                const ego_pose_t coarse_best = r->grid.best;
                grid_begin(&r->grid, &coarse_best, p->step, p->fine_step, p->sigma, &r->best,
                           r->score);
                r->phase = PHASE_FINE;
            }
            break;
        case PHASE_COARSE:
            ego_work_spend(work, COST_POSE);
            if (!grid_score_next(r)) {
                const ego_pose_t coarse_best = r->grid.best;
                grid_begin(&r->grid, &coarse_best, p->step, p->fine_step, p->sigma, &r->best,
                           r->score);
                r->phase = PHASE_FINE;
            }
            break;
        case PHASE_FINE:
            ego_work_spend(work, COST_POSE);
            if (!grid_score_next(r)) {
                r->best = r->grid.best;
                r->score = r->grid.best_score;
                r->rotation++;
                r->phase = PHASE_ROTATION;
            }
            break;
        default:
            return true;
        }
    }
}

void ego_coarse_result(const ego_coarse_run_t *r, ego_pose_t *best, uint64_t *score)
{
    *best = r->best;
    *score = r->score;
}

void ego_coarse_search(const ego_scan_t *last, const ego_scan_t *current, fx_bam32_t main_direction,
                   const ego_pose_t *centre, const ego_coarse_params_t *params, ego_pose_t *best,
                   uint64_t *score)
{
    ego_coarse_run_t run;
    ego_work_t unlimited;
    ego_work_start(&unlimited, EGO_WORK_UNLIMITED);
    ego_coarse_start(&run, last, current, main_direction, centre, params);
    (void)ego_coarse_step(&run, &unlimited);
    ego_coarse_result(&run, best, score);
}
