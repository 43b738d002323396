/* ego_track.c - see ego_track.h. */
#include "ego_track.h"

#include <stddef.h>
#include <string.h>

#include "ego_fx_math.h"

/* The walk from the previous point's place: this many steps, then a
 * binary search (a bounded step whatever the hint). */
#define WALK_MAX 16u

/* Points this far from the origin (Q16.16: 8192 m) match nothing: beyond
 * any scan, and it keeps the differences of fit_segment in 32 bits. */
#define FAR_LIMIT ((int64_t)1 << 29)

/* The work of matching one point, counted as it is done. */
typedef struct {
    uint32_t steps; /* walked (EGO_COST_MATCH_STEP each) */
    uint32_t fits;  /* segments tried (EGO_COST_TRACK_FIT) */
    uint32_t roots; /* square roots taken (EGO_COST_TRACK_NORMAL) */
} point_work_t;

static uint32_t units_of(uint32_t base, const point_work_t *w)
{
    return base + w->steps * EGO_COST_MATCH_STEP + w->fits * EGO_COST_TRACK_FIT +
           w->roots * EGO_COST_TRACK_NORMAL;
}

void ego_track_defaults(ego_track_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->radius_start = FX_Q16_16_C(0.3);
    params->radius = FX_Q16_16_C(0.05);
    params->radius_min = FX_Q16_16_C(0.015);
    params->max_iterations = 10u;
    params->converge_translation = FX_Q16_16_C(0.0002);
    params->converge_rotation = FX_BAM32_DEG_C(0.002);
    params->inlier_distance = FX_Q16_16_C(0.10);
    params->main_tolerance = FX_BAM32_DEG_C(10.0);
    params->aperture_ratio = (fx_q2_30_t)(FX_Q2_30_ONE / 5);
    params->weak_share = (fx_q2_30_t)(FX_Q2_30_ONE / 50);
    params->objects_share = (fx_q2_30_t)(FX_Q2_30_ONE / 5);
    params->min_matches = 10u;
    params->weighted = true;
}

static int64_t abs64(int64_t v)
{
    return (v < 0) ? -v : v;
}

static int64_t rel_bearing(const ego_track_run_t *run, uint16_t j)
{
    return fx_bam32_diff(run->last->bearing[j], run->ref);
}

/* Coarse to fine: the first pass matches every fourth point, the second
 * every other, the rest all of them (a pass keeps at least COARSE_POINTS
 * points). From a prediction good to centimetres the first two passes only
 * need to settle the pose roughly; the full passes make it exact and give
 * the statistics. */
#define COARSE_POINTS 64u

static uint8_t pass_stride(const ego_track_run_t *run)
{
    uint8_t stride = (run->iteration == 0u) ? 4u : (run->iteration == 1u) ? 2u : 1u;
    while (stride > 1u && run->current->count / stride < COARSE_POINTS) {
        stride /= 2u;
    }
    return stride;
}

/* Where the budget ends a run early, a last step this many times the
 * convergence thresholds still counts as converged (1 mm, 0.01 deg). */
#define SETTLED 5

static void begin_pass(ego_track_run_t *run)
{
    memset(run->group, 0, sizeof run->group);
    memset(run->object_info, 0, sizeof run->object_info);
    run->pass_units = 0u;
    fx_sincos(run->pose.theta, &run->sn, &run->cs);
    run->stride = pass_stride(run);
    run->next = 0u;
    run->hint = (uint16_t)(run->last->count / 2u);
}

void ego_track_start(ego_track_run_t *run, const ego_scan_t *last, const ego_scan_t *current,
                     fx_bam32_t main_direction, const ego_pose_t *initial, bool tracking,
                     const ego_track_params_t *params)
{
    memset(run, 0, sizeof *run);
    run->tracking = tracking;
    run->last = last;
    run->current = current;
    run->params = params;
    run->main_direction = main_direction & (FX_BAM32_HALF - 1u);
    run->pose = *initial;
    run->radius = params->radius_start;
    if (last->count < 2u || current->count == 0u || params->max_iterations == 0u) {
        run->finished = true;
        run->failed = true;
        return;
    }
    run->ref = last->bearing[0] + (last->bearing[last->count - 1u] - last->bearing[0]) / 2u;
    begin_pass(run);
}

/* The first last-scan point whose bearing is at least rel: a walk from the
 * hint of at most WALK_MAX steps, then a binary search. *steps counts the
 * work. */
EGO_NOINLINE static uint16_t locate(const ego_track_run_t *run, int64_t rel, uint32_t *steps)
{
    const uint16_t n = run->last->count;
    uint16_t j = run->hint;
    for (uint32_t k = 0u; k < WALK_MAX; k++) {
        (*steps)++;
        if (j < n && rel_bearing(run, j) < rel) {
            j++;
        } else if (j > 0u && rel_bearing(run, (uint16_t)(j - 1u)) >= rel) {
            j--;
        } else {
            return j;
        }
    }
    uint16_t lo = 0u;
    uint16_t hi = n;
    while (lo < hi) {
        (*steps)++;
        const uint16_t mid = (uint16_t)((lo + hi) / 2u);
        if (rel_bearing(run, mid) < rel) {
            lo = (uint16_t)(mid + 1u);
        } else {
            hi = mid;
        }
    }
    return lo;
}

/* How far a match is looked for: the radius of the equations, or the
 * inlier distance of the statistics if that is larger. */
static int64_t reach(const ego_track_run_t *run)
{
    const fx_q16_16_t inlier = run->params->inlier_distance;
    return (run->radius > inlier) ? run->radius : inlier;
}

/* Did the last scan see more than twice the inlier distance beyond (qx,
 * qy): its beams on both sides of that bearing, neighbours with no gap
 * between them, both reach further? A current point there sits where the
 * last scan saw empty space, so the pose that put it there is wrong (or
 * the point moved). */
EGO_NOINLINE static bool seen_through(const ego_track_run_t *run, uint16_t j, fx_q16_16_t qx,
                                      fx_q16_16_t qy, fx_q16_16_t margin, uint32_t *computed)
{
    const ego_scan_t *l = run->last;
    if (j == 0u || j >= l->count || (l->flags[j - 1u] & EGO_LINK_GAP) != 0u) {
        return false;
    }
    const int64_t ox = (int64_t)qx - l->origin_x;
    const int64_t oy = (int64_t)qy - l->origin_y;
    const uint64_t o_sq = (uint64_t)(ox * ox + oy * oy);
    uint64_t beam_sq[2];
    for (uint16_t k = 0u; k < 2u; k++) {
        const int64_t bx = (int64_t)l->x[j - 1u + k] - l->origin_x;
        const int64_t by = (int64_t)l->y[j - 1u + k] - l->origin_y;
        beam_sq[k] = (uint64_t)(bx * bx + by * by);
        if (beam_sq[k] <= o_sq) {
            return false; /* a beam no longer than the point: no root needed */
        }
    }
    (*computed)++;
    const int64_t r = (int64_t)fx_sqrt_u64(o_sq) + margin;
    const uint64_t r_sq = (uint64_t)(r * r);
    return beam_sq[0] > r_sq && beam_sq[1] > r_sq;
}

/* A point's distance to one segment of the last scan. */
typedef struct {
    bool ok;
    int32_t nx; /* the segment's unit normal, Q1.14 */
    int32_t ny;
    int64_t d;  /* signed distance, Q16.16 m */
} segment_fit_t;

/* The unit normal of segment a -> a + 1 (a surface, its ends apart) into
 * the run's cache; false when the segment has no length. *computed counts
 * the square roots and divisions (their work). */
EGO_NOINLINE static bool segment_normal(ego_track_run_t *run, uint16_t a, int32_t sx, int32_t sy,
                                        uint32_t *computed)
{
    int16_t *n = run->normal[a];
    if (n[0] != 0 || n[1] != 0) {
        return true;
    }
    (*computed)++;
    /* The segment scaled to 15 bits (its larger side in [2^14, 2^15)):
     * its direction to 2^-14 rad, and 32-bit arithmetic from here. */
    uint32_t big = (uint32_t)((sx < 0) ? -sx : sx);
    const uint32_t other = (uint32_t)((sy < 0) ? -sy : sy);
    big = (other > big) ? other : big;
    if (big == 0u) {
        return false;
    }
    int32_t down = 1;
    int32_t up = 1;
    for (; big >= (1u << 15); big >>= 1) {
        down *= 2;
    }
    for (; big < (1u << 14); big <<= 1) {
        up *= 2;
    }
    const int32_t x = sx / down * up;
    const int32_t y = sy / down * up;
    const int32_t length = (int32_t)fx_sqrt_u64((uint64_t)((int64_t)x * x + (int64_t)y * y));
    n[0] = (int16_t)((-y * 16384) / length);
    n[1] = (int16_t)((x * 16384) / length);
    return true;
}

/* The point (qx, qy) against segment a -> a + 1: true when the segment is a
 * surface, the point lies along it (at most a quarter of it beyond either
 * end) and within the run's reach of its line. The point is within
 * FAR_LIMIT of the origin and a segment's ends within the LMS's 82 m of
 * it, so the differences below fit in 32 bits and each product is one
 * 32 x 32 -> 64-bit multiplication. */
EGO_NOINLINE static bool fit_segment(ego_track_run_t *run, uint16_t a, fx_q16_16_t qx, fx_q16_16_t qy,
                                     segment_fit_t *f, uint32_t *computed)
{
    const ego_scan_t *l = run->last;
    if (a + 1u >= l->count || (l->flags[a] & EGO_LINK_BREAK) != 0u) {
        return false;
    }
    const int32_t sx = l->x[a + 1u] - l->x[a];
    const int32_t sy = l->y[a + 1u] - l->y[a];
    const int32_t ex = qx - l->x[a];
    const int32_t ey = qy - l->y[a];
    const int64_t along = (int64_t)ex * sx + (int64_t)ey * sy;
    const int64_t length_sq = (int64_t)sx * sx + (int64_t)sy * sy;
    if (length_sq == 0 || 4 * along < -length_sq || 4 * along > 5 * length_sq ||
        !segment_normal(run, a, sx, sy, computed)) {
        return false;
    }
    f->nx = run->normal[a][0];
    f->ny = run->normal[a][1];
    f->d = ((int64_t)ex * f->nx + (int64_t)ey * f->ny) / 16384;
    f->ok = abs64(f->d) <= reach(run);
    return f->ok;
}

/* The index a relative bearing would have in the last scan were its
 * points evenly spread between its first and last bearing (32-bit: the
 * spread cut to 16 bits, the index below 2^14). */
static uint16_t even_guess(const ego_track_run_t *run, int64_t rel)
{
    const uint16_t n = run->last->count;
    const int64_t first = rel_bearing(run, 0u);
    const int64_t spread = rel_bearing(run, (uint16_t)(n - 1u)) - first;
    if (spread <= 0 || rel <= first) {
        return 0u;
    }
    if (rel - first >= spread) {
        return (uint16_t)(n - 1u);
    }
    const uint32_t at = (uint32_t)((rel - first) >> 16);
    const uint32_t all = (uint32_t)(spread >> 16);
    if (all == 0u) {
        return 0u;
    }
    return (uint16_t)((at * (uint32_t)(n - 1u)) / all);
}

/* The last scan's segment for (qx, qy) along its bearing from the last
 * scanner: the segment j - 1 -> j spanning it (j, the first last-scan point
 * at or past that bearing, in *j), else, when that one does not take the
 * point (a break, an end), a neighbour on either side; best.ok false when
 * none does. The walk starts at the run's hint, or where the bearing falls
 * if the beams were evenly spread (probes that jump about the scan). The
 * bearing only picks the segment: the quick arctangent does. Inlined in
 * both callers: as a call, the match cost tracking 3-6 % more instructions
 * on Cortex-M3 (ctest target_replay_*). */
FX_INLINE segment_fit_t along_bearing(ego_track_run_t *run, fx_q16_16_t qx, fx_q16_16_t qy,
                                      bool guess_hint, uint16_t *j, point_work_t *w)
{
    const ego_scan_t *l = run->last;
    const int64_t rel = fx_bam32_diff(
        fx_atan2_quick((int64_t)qy - l->origin_y, (int64_t)qx - l->origin_x), run->ref);
    if (guess_hint) {
        run->hint = even_guess(run, rel);
    }
    *j = locate(run, rel, &w->steps);
    run->hint = *j;
    segment_fit_t best = {false, 0, 0, 0};
    for (int32_t k = 0; k < 3 && (k == 0 || !best.ok); k++) {
        const int32_t a = (k == 0) ? (int32_t)*j - 1 : (k == 1) ? (int32_t)*j - 2 : (int32_t)*j;
        segment_fit_t f;
        if (a >= 0 && fit_segment(run, (uint16_t)a, qx, qy, &f, &w->roots) &&
            (!best.ok || abs64(f.d) < abs64(best.d))) {
            best = f;
        }
        w->fits++;
    }
    return best;
}

/* Matches current point i at the run's pose into its group's sums,
 * counting its work. */
EGO_NOINLINE static void match_point(ego_track_run_t *run, uint16_t i, point_work_t *w)
{
    const ego_scan_t *c = run->current;
    const ego_track_params_t *params = run->params;
    if ((c->flags[i] & run->skip) != 0u) {
        return; /* neither matched nor counted */
    }
    fx_q16_16_t qx;
    fx_q16_16_t qy;
    ego_pose_apply(&run->pose, run->sn, run->cs, c->x[i], c->y[i], &qx, &qy);
    /* The point turned, without the translation (the lever arm's). */
    const int64_t mx = (int64_t)qx - run->pose.x;
    const int64_t my = (int64_t)qy - run->pose.y;
    const bool far = abs64(qx) >= FAR_LIMIT || abs64(qy) >= FAR_LIMIT ||
                     abs64(mx) >= FAR_LIMIT || abs64(my) >= FAR_LIMIT;
    const bool has_tc = (c->flags[i] & EGO_POINT_HAS_TANGENT) != 0u;
    const fx_bam32_t tc = (c->tangent[i] + run->pose.theta) & (FX_BAM32_HALF - 1u);
    const bool on_main =
        has_tc && fx_line_angle_diff(tc, run->main_direction) <= params->main_tolerance;
    ego_track_sums_t *g = &run->group[on_main ? 0 : 1];
    g->points++;
    if (far) {
        return; /* nothing of the last scan is near: unmatched */
    }
    uint16_t j = 0u;
    const segment_fit_t best = along_bearing(run, qx, qy, false, &j, w);
    if (!best.ok) {
        if (seen_through(run, j, qx, qy, 2 * params->inlier_distance, &w->roots)) {
            g->seen_through++; /* in space the last scan saw empty */
        }
        return;
    }
    const int32_t nx = best.nx;
    const int32_t ny = best.ny;
    const int32_t d = (int32_t)best.d; /* |d| <= reach */
    const uint64_t d_sq = (uint64_t)((int64_t)d * d);
    const uint64_t inlier_sq = (uint64_t)((int64_t)params->inlier_distance * params->inlier_distance);
    if (d_sq <= inlier_sq) {
        g->inliers++;
        g->fit += inlier_sq - d_sq;
    }
    if (abs64(d) > run->radius) {
        return; /* counted, not used */
    }
    /* The lever arm, Q16.16 m (|m| < FAR_LIMIT). */
    const int32_t arm = (int32_t)(((int64_t)ny * (int32_t)mx - (int64_t)nx * (int32_t)my) / 16384);
    g->n++;
    g->a[0] += (int64_t)nx * nx;  /* Q28 */
    g->a[1] += (int64_t)nx * ny;
    g->a[2] += (int64_t)nx * arm; /* Q30 m */
    g->a[3] += (int64_t)ny * ny;
    g->a[4] += (int64_t)ny * arm;
    g->a[5] += (int64_t)arm * arm; /* Q32 m^2 */
    g->b[0] += (int64_t)nx * d;   /* Q30 m */
    g->b[1] += (int64_t)ny * d;
    g->b[2] += (int64_t)arm * d;  /* Q32 m^2 */
    g->sum_sq += d_sq;
    if ((c->flags[i] & EGO_POINT_OBJECT) != 0u) {
        run->object_info[0] += (nx * nx) >> 14; /* Q14, at most 2^14 */
        run->object_info[1] += (nx * ny) / 16384;
        run->object_info[2] += (ny * ny) >> 14;
    }
}

/* num / den in Q16.16 (den > 0), both scaled down together while num << 16
 * would overflow. */
static int64_t div_q16(int64_t num, int64_t den)
{
    while (abs64(num) >= ((int64_t)1 << 46) && den > 1) {
        num /= 2;
        den /= 2;
    }
    return (num * 65536) / den;
}

static int64_t matches(const ego_track_run_t *run)
{
    return run->group[0].n + run->group[1].n;
}

/* The step (dx, dy, dtheta) from the pass's normal equations: each group's
 * means, the groups averaged (eq. 10's equal weights), in Q14, damped; false
 * when there is nothing to solve. */
EGO_NOINLINE static bool solve(const ego_track_run_t *run, int64_t *dx, int64_t *dy, int64_t *dtheta,
                               bool *weak_rotation)
{
    int64_t a[6] = {0, 0, 0, 0, 0, 0};
    int64_t b[3] = {0, 0, 0};
    int64_t groups = 0;
    if (run->params->weighted) {
        for (unsigned k = 0u; k < 2u; k++) {
            const ego_track_sums_t *g = &run->group[k];
            if (g->n <= 0) {
                continue;
            }
            groups++;
            for (unsigned m = 0u; m < 6u; m++) {
                a[m] += g->a[m] / g->n;
            }
            for (unsigned m = 0u; m < 3u; m++) {
                b[m] += g->b[m] / g->n;
            }
        }
    } else if (matches(run) > 0) {
        /* Plain ICP: one pool, every match alike. */
        const int64_t n = matches(run);
        groups = 1;
        for (unsigned m = 0u; m < 6u; m++) {
            a[m] = (run->group[0].a[m] + run->group[1].a[m]) / n;
        }
        for (unsigned m = 0u; m < 3u; m++) {
            b[m] = (run->group[0].b[m] + run->group[1].b[m]) / n;
        }
    }
    if (groups == 0) {
        return false;
    }
    /* Q28, Q30 m, Q32 m^2 -> Q14 throughout. */
    const int64_t q28 = groups << 14;
    const int64_t q30 = groups << 16;
    const int64_t q32 = groups << 18;
    const int64_t a00 = a[0] / q28;
    const int64_t a01 = a[1] / q28;
    const int64_t a02 = a[2] / q30;
    const int64_t a11_raw = a[3] / q28;
    const int64_t a12 = a[4] / q30;
    const int64_t a22_raw = a[5] / q32;
    const int64_t b0 = -b[0] / q30;
    const int64_t b1 = -b[1] / q30;
    const int64_t b2 = -b[2] / q32;
    /* Damping: a direction the scans barely see stays where it is. */
    const int64_t damp_t = (a00 + a11_raw) / 1000 + 1;
    const int64_t damp_r = a22_raw / 1000 + 1;
    const int64_t a00d = a00 + damp_t;
    const int64_t a11 = a11_raw + damp_t;
    const int64_t a22 = a22_raw + damp_r;
    /* Cramer's rule with the cofactors of the symmetric matrix. */
    const int64_t c00 = a11 * a22 - a12 * a12;
    const int64_t c01 = a02 * a12 - a01 * a22;
    const int64_t c02 = a01 * a12 - a02 * a11;
    const int64_t c11 = a00d * a22 - a02 * a02;
    const int64_t c12 = a01 * a02 - a00d * a12;
    const int64_t c22 = a00d * a11 - a01 * a01;
    const int64_t det = a00d * c00 + a01 * c01 + a02 * c02;
    if (det <= 0) {
        return false;
    }
    /* The rotation's own information, det / c22 (what is left of a22 once
     * the translation explains what it can, Q14 m^2), no more than the
     * lever arm the beam spacing alone gives (ego_scan.h): every surface
     * faces the scanner (a ring around it), and a turn only moves the
     * points along it, one spacing onto the next beams'. */
    const int64_t most = (int64_t)16 << 16; /* 16 m: no ring is that coarse */
    const int64_t spacing = (run->current->spacing_arm < most) ? run->current->spacing_arm : most;
    *weak_rotation = det < ((spacing * spacing) >> 18) * c22;
    *dx = div_q16(c00 * b0 + c01 * b1 + c02 * b2, det);
    *dy = div_q16(c01 * b0 + c11 * b1 + c12 * b2, det);
    *dtheta = div_q16(c02 * b0 + c12 * b1 + c22 * b2, det); /* Q16.16 rad */
    return true;
}

/* What a point of the next pass should cost: this pass's mean (the
 * passes get no dearer: each has a smaller radius), at least a typical
 * point's. A pass that still runs dry leaves the run unfinished, and its
 * scan's search finishes it in the next scan's budget. */
static uint32_t pass_point_units(const ego_track_run_t *run)
{
    const uint32_t points = (run->current->count + run->stride - 1u) / run->stride;
    const uint32_t mean = run->pass_units / ((points > 0u) ? points : 1u);
    return (mean > EGO_TRACK_TYPICAL_POINT) ? mean : EGO_TRACK_TYPICAL_POINT;
}

/* The radius of the next pass: 0.3 m, then a third of the last down to
 * the radius; tracking's down to 3 RMS distances of this pass, within
 * [radius_min, radius] (ego_track_start). */
static fx_q16_16_t next_radius(const ego_track_run_t *run)
{
    const ego_track_params_t *params = run->params;
    int64_t least = params->radius;
    const int64_t n = matches(run);
    if (run->tracking && n > 0) {
        const uint64_t sum_sq = run->group[0].sum_sq + run->group[1].sum_sq;
        const int64_t trimmed = 3 * (int64_t)fx_sqrt_u64(sum_sq / (uint64_t)n);
        least = (trimmed < params->radius_min) ? params->radius_min
                : (trimmed < least)            ? trimmed
                                               : least;
    }
    return (run->radius / 3 > least) ? run->radius / 3 : (fx_q16_16_t)least;
}

/* The end of a pass: the step, convergence, the next pass or the end. */
static void close_pass(ego_track_run_t *run, const ego_work_t *work)
{
    const ego_track_params_t *params = run->params;
    int64_t dx = 0;
    int64_t dy = 0;
    int64_t dtheta = 0;
    /* A tracking pass with under a quarter of its points matched (the
     * first within its radius, a later one within the inlier distance):
     * the prediction missed (a turn begun, a jump) or the run fell into a
     * wrong minimum, and the rest of the scan's budget is better spent on
     * another start. */
    const ego_track_sums_t *g = run->group;
    const uint32_t points = g[0].points + g[1].points;
    const uint32_t found = (run->iteration == 0u) ? (uint32_t)matches(run)
                                                  : g[0].inliers + g[1].inliers;
    const bool missed = run->tracking && 4u * found < points;
    if (missed || matches(run) < (int64_t)params->min_matches ||
        !solve(run, &dx, &dy, &dtheta, &run->weak_rotation)) {
        run->finished = true;
        run->failed = true;
        return;
    }
    const int64_t turn = (dtheta * FX_BAM_PER_RAD_Q16_X128) / 128;
    run->pose.x = fx_sat_s32((int64_t)run->pose.x + dx);
    run->pose.y = fx_sat_s32((int64_t)run->pose.y + dy);
    run->pose.theta += (fx_bam32_t)(uint32_t)fx_sat_s32(turn);
    run->iteration++;
    const bool still = abs64(dx) < params->converge_translation &&
                       abs64(dy) < params->converge_translation &&
                       abs64(turn) < (int64_t)params->converge_rotation;
    const bool full = run->stride == 1u;
    /* Settled: a full pass whose step was under SETTLED times the
     * thresholds (the steps shrink geometrically: the pose is then within
     * about that of the end; associations that flip between passes keep a
     * step of a millimetre from ever being still). */
    const bool settled = full && run->iteration > 1u &&
                         abs64(dx) < SETTLED * params->converge_translation &&
                         abs64(dy) < SETTLED * params->converge_translation &&
                         abs64(turn) < SETTLED * (int64_t)params->converge_rotation;
    if ((still && full && run->iteration > 1u) || run->iteration >= params->max_iterations) {
        run->converged = still || settled;
        run->finished = true;
        return;
    }
    /* Until the budget: a meter that cannot pay for another pass ends the
     * run here, with the statistics (and the radius) of this one,
     * converged when settled (a pass sized by the typical point alone ran
     * dry on the busy road's dear points, and its scan cost the next
     * one). */
    const uint32_t next_stride = pass_stride(run);
    const uint32_t next_points = (run->current->count + next_stride - 1u) / next_stride;
    const uint32_t pass_units = next_points * pass_point_units(run);
    if (run->tracking && !ego_work_allows(work, pass_units + (run->wary ? pass_units / 8u : 0u) +
                                                        EGO_COST_SOLVE + EGO_COST_COVARIANCE)) {
        run->converged = settled;
        run->finished = true;
        run->cut = !settled;
        return;
    }
    run->radius = next_radius(run);
    begin_pass(run);
}

/* Would close_pass find this pass missed (under a quarter of its points
 * found) even if every point left matched: then the rest of the pass is
 * work for nothing (a turn's onset: the prediction's first pass). */
static bool pass_missed_already(const ego_track_run_t *run)
{
    const ego_track_sums_t *g = run->group;
    const uint32_t count = run->current->count;
    const uint32_t left =
        (run->next < count) ? (count - run->next + run->stride - 1u) / run->stride : 0u;
    const uint32_t seen = g[0].points + g[1].points;
    const uint32_t found = (run->iteration == 0u) ? (uint32_t)matches(run)
                                                  : g[0].inliers + g[1].inliers;
    return 4u * (found + left) < seen + left;
}

bool ego_track_step(ego_track_run_t *run, ego_work_t *work)
{
    /* A point: the walk (at most WALK_MAX steps and a binary search of 16)
     * and at most three segments tried, each with its normal to compute. */
    const uint32_t point_max = EGO_COST_TRACK_POINT + (WALK_MAX + 16u) * EGO_COST_MATCH_STEP +
                               3u * (EGO_COST_TRACK_FIT + EGO_COST_TRACK_NORMAL);
    while (!run->finished) {
        if (run->next < run->current->count) {
            if (!ego_work_allows(work, point_max)) {
                return false;
            }
            point_work_t w = {0u, 0u, 0u};
            match_point(run, run->next, &w);
            run->next = (uint16_t)(run->next + run->stride);
            const uint32_t units = units_of(EGO_COST_TRACK_POINT, &w);
            run->pass_units += units;
            ego_work_spend(work, units);
            if (run->tracking && pass_missed_already(run)) {
                run->next = run->current->count; /* close_pass finds it missed */
            }
        } else {
            /* Any closing step may end the run: room for its covariance. */
            if (!ego_work_allows(work, EGO_COST_SOLVE + EGO_COST_COVARIANCE)) {
                return false;
            }
            ego_work_spend(work, EGO_COST_SOLVE);
            close_pass(run, work);
            if (run->finished && !run->failed) {
                ego_work_spend(work, EGO_COST_COVARIANCE);
            }
        }
    }
    return true;
}

bool ego_track_resume(ego_track_run_t *run)
{
    if (!run->cut) {
        return false;
    }
    run->cut = false;
    run->finished = false;
    begin_pass(run);
    return true;
}

/* The share below which a direction is weak, raised by the normals'
 * noise: a normal from neighbours a spacing s apart whose ranges scatter
 * by the residual r tilts by about r / s, and gives a direction no surface
 * constrains (a corridor's length) about (r / s)^2 of spurious
 * information (at 3 cm of range noise a corridor's length looked as well
 * constrained as a room's). Half of it is added, at most 0.2. */
static fx_q2_30_t weak_share(const ego_track_params_t *params, fx_q16_16_t residual,
                             fx_q16_16_t spacing_arm)
{
    if (spacing_arm <= 0) {
        return params->weak_share;
    }
    const int64_t ratio_q16 = ((int64_t)residual << 16) / spacing_arm;
    const int64_t noise_q30 = (ratio_q16 < ((int64_t)1 << 17)) ? (ratio_q16 * ratio_q16) >> 2 : (int64_t)1 << 32;
    const int64_t share = (int64_t)params->weak_share + noise_q30 / 2;
    const int64_t most = (int64_t)FX_Q2_30_ONE / 5;
    return (fx_q2_30_t)((share < most) ? share : most);
}

ego_itcp_status_t ego_track_result(const ego_track_run_t *run, ego_itcp_result_t *result)
{
    memset(result, 0, sizeof *result);
    ego_cov_unknown(&result->cov);
    result->pose = run->pose;
    if (!run->finished) {
        return EGO_ITCP_ERR_UNFINISHED;
    }
    result->iterations = run->iteration;
    result->converged = run->converged;
    /* The statistics of the last pass (at the pose before its small step). */
    const ego_track_sums_t *g = run->group;
    const int64_t n = matches(run);
    result->matches = (uint16_t)n;
    result->n_main = (uint16_t)g[0].n;
    result->n_non_main = (uint16_t)g[1].n;
    result->inliers = (uint16_t)(g[0].inliers + g[1].inliers);
    const uint64_t inlier_sq =
        (uint64_t)((int64_t)run->params->inlier_distance * run->params->inlier_distance);
    for (unsigned k = 0u; k < 2u; k++) {
        result->group_points[k] = (uint16_t)g[k].points;
        /* A point where the last scan saw empty space costs what a perfect
         * inlier gains (as ITCP's statistics). */
        const uint64_t full = (uint64_t)g[k].points * inlier_sq;
        const uint64_t penalty = (uint64_t)g[k].seen_through * inlier_sq;
        const uint64_t fit = (g[k].fit > penalty) ? g[k].fit - penalty : 0u;
        result->group_fit[k] =
            (full == 0u) ? 0 : (fx_q2_30_t)((fit >> 4) * (1ull << 30) / (full >> 4));
    }
    if (n > 0) {
        result->residual = (fx_q16_16_t)fx_sqrt_u64((g[0].sum_sq + g[1].sum_sq) / (uint64_t)n);
    }
    if (!run->failed) { /* charged with the run's last closing step */
        ego_cov_group_t groups[2];
        for (unsigned k = 0u; k < 2u; k++) {
            groups[k].n = g[k].n;
            memcpy(groups[k].a, g[k].a, sizeof groups[k].a);
            groups[k].sum_sq = g[k].sum_sq;
        }
        ego_cov_estimate(groups, run->radius, run->params->weighted, &result->cov);
        ego_cov_weakest(groups, run->main_direction, run->current->rms_range,
                        weak_share(run->params, result->residual, run->current->spacing_arm) *
                            (run->weak_held ? 2 : 1),
                        &result->weak);
        if (result->weak.kind == EGO_WEAK_NONE) {
            /* Q28 -> Q14 (the squares' sums are not negative). */
            const int32_t all[3] = {(int32_t)((g[0].a[0] + g[1].a[0]) >> 14),
                                    (int32_t)((g[0].a[1] + g[1].a[1]) / 16384),
                                    (int32_t)((g[0].a[3] + g[1].a[3]) >> 14)};
            if (ego_cov_on_objects(all, run->object_info,
                                   run->params->objects_share * (run->objects_held ? 2 : 1))) {
                result->weak.kind = EGO_WEAK_OBJECTS;
            }
        }
    }
    result->weak_rotation = run->weak_rotation;
    result->aperture = g[0].n > 0 &&
                       ((int64_t)g[1].n << 30) < (int64_t)run->params->aperture_ratio * g[0].n;
    return (run->failed || n < (int64_t)run->params->min_matches) ? EGO_ITCP_ERR_FEW_MATCHES
                                                                  : EGO_ITCP_OK;
}

void ego_track_narrow(ego_track_run_t *run, fx_q16_16_t radius)
{
    run->radius = (radius < run->radius) ? radius : run->radius;
}

void ego_track_probe_start(ego_track_run_t *run, const ego_scan_t *last,
                           const ego_track_params_t *params)
{
    memset(run, 0, sizeof *run);
    run->last = last;
    run->params = params;
    run->finished = true; /* no registration */
    if (last->count > 0u) {
        run->ref = last->bearing[0] + (last->bearing[last->count - 1u] - last->bearing[0]) / 2u;
    }
}

ego_itcp_probe_t ego_track_probe(ego_track_run_t *run, fx_q16_16_t qx, fx_q16_16_t qy,
                                 fx_q16_16_t sigma, uint64_t *dist_sq, uint32_t *units)
{
    point_work_t w = {0u, 0u, 0u};
    ego_itcp_probe_t found = EGO_ITCP_PROBE_NOTHING;
    *dist_sq = 0u;
    run->radius = sigma; /* fit_segment's reach */
    if (run->last->count >= 2u && abs64(qx) < FAR_LIMIT && abs64(qy) < FAR_LIMIT) {
        uint16_t j = 0u;
        const segment_fit_t best = along_bearing(run, qx, qy, true, &j, &w);
        if (best.ok && abs64(best.d) < sigma) {
            *dist_sq = (uint64_t)(best.d * best.d);
            found = EGO_ITCP_PROBE_SURFACE;
        } else if (seen_through(run, j, qx, qy, 2 * sigma, &w.roots)) {
            found = EGO_ITCP_PROBE_SEEN_THROUGH;
        }
    }
    *units = units_of(EGO_COST_TRACK_PROBE, &w);
    return found;
}
