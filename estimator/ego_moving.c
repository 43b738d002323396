/* ego_moving.c - moving clusters of a range scan (ego_moving.h). */
#include "ego_moving.h"

#include <stddef.h>

#include "ego_fx_math.h"
#include "ego_pose.h"

/* Lines whose motion is not measured: the chain of poses starts over. */
#define UNMEASURED (EGO_FLAG_FIRST | EGO_FLAG_PREDICTED | EGO_FLAG_RECOVERING | EGO_FLAG_RECOVERED)

/* 2 pi * 2^16: a bearing step in 2^-16 turn times this / 2^16 is Q16.16 rad. */
#define TWO_PI_Q16 411775

#define US_PER_S 1000000

/* A scan's time and motion, and the reference it is judged against. */
typedef struct {
    const ego_range_scan_t *scan;
    const ego_moving_ref_t *ref;
    fx_q2_30_t ref_sin; /* of ref->pose.theta */
    fx_q2_30_t ref_cos;
    uint32_t *units;    /* the scan's work so far (ego_moving.h) */
    uint32_t max_units; /* where its evidence tests stop */
} view_t;

/* A cluster's marks: its box centre, then its first and last points. */
#define MARKS 3u

typedef struct {
    fx_q16_16_t x; /* box centre */
    fx_q16_16_t y;
    fx_q16_16_t mark_x[MARKS];
    fx_q16_16_t mark_y[MARKS];
    bool uncut[MARKS]; /* an end is the body's own edge (the centre: true) */
    fx_q16_16_t length;
    fx_q16_16_t width;
    uint16_t from;   /* its first beam */
    uint16_t points;
    uint8_t track;   /* EGO_MOVING_TRACKS: none */
    bool held;       /* a segment a track holds, not a moving cluster */
} cluster_t;

static fx_q16_16_t range_q16(const ego_range_scan_t *scan, uint16_t k)
{
    /* At most 65535 * 500000 * 65536 < 2^61; the result < 2^31 (ego_range.h). */
    const uint64_t v = (uint64_t)scan->range[k] * scan->range_unit_um * 65536u;
    return (fx_q16_16_t)((v + 500000u) / 1000000u);
}

/* origin + r (cos b, sin b). */
static void point_at(fx_q16_16_t ox, fx_q16_16_t oy, fx_bam32_t b, fx_q16_16_t r, fx_q16_16_t *x,
                     fx_q16_16_t *y)
{
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(b, &s, &c);
    *x = fx_add_q16(ox, fx_mul_q16_q30(r, c));
    *y = fx_add_q16(oy, fx_mul_q16_q30(r, s));
}

static uint64_t dist_sq(fx_q16_16_t dx, fx_q16_16_t dy)
{
    /* Each square < 2^62: the sum fits. Q32.32. */
    return (uint64_t)((int64_t)dx * dx) + (uint64_t)((int64_t)dy * dy);
}

/* (dx, dy) from an origin as range (Q16.16) and bearing. */
/* The length of (dx, dy), Q16.16, saturated. */
static fx_q16_16_t range_of(fx_q16_16_t dx, fx_q16_16_t dy)
{
    const uint32_t root = fx_sqrt_u64(dist_sq(dx, dy));
    return (root > (uint32_t)INT32_MAX) ? INT32_MAX : (fx_q16_16_t)root;
}

static void polar_of(fx_q16_16_t dx, fx_q16_16_t dy, fx_q16_16_t *r, fx_bam32_t *b)
{
    *r = range_of(dx, dy);
    *b = fx_atan2_quick(dy, dx);
}

/* The near test's reach: max(EGO_MOVING_NEAR, r * step) + extra (at
 * range r neighbouring beams step apart, in 2^-16 turn, land r * step
 * apart), squared, and the beams on either side it spans (at most
 * EGO_MOVING_NEAR_BEAMS). */
typedef struct {
    uint64_t sq;   /* Q32.32 */
    int32_t beams;
} near_t;

static near_t near_of(fx_q16_16_t r, uint32_t step, fx_q16_16_t extra)
{
    /* step < 2^16 and r < 2^31: the angle (Q16.16 rad, < 2^19) first. */
    const int64_t angle = ((int64_t)step * TWO_PI_Q16) >> 16;
    const int64_t gap = ((int64_t)r * angle) >> 16;
    const int64_t thr = ((gap > EGO_MOVING_NEAR) ? gap : EGO_MOVING_NEAR) + extra;
    const int64_t beams = (gap > 0) ? thr / gap + 1 : (int64_t)EGO_MOVING_NEAR_BEAMS;
    near_t n;
    n.sq = (thr >= INT32_MAX) ? UINT64_MAX : (uint64_t)(thr * thr);
    n.beams = (beams < (int64_t)EGO_MOVING_NEAR_BEAMS) ? (int32_t)beams : (int32_t)EGO_MOVING_NEAR_BEAMS;
    return n;
}

/* --- the reference ------------------------------------------------------ */

static fx_q16_16_t ref_range(const ego_moving_ref_t *ref, uint16_t i)
{
    return (fx_q16_16_t)(((uint32_t)ref->range_cm[i] * 65536u + 50u) / 100u);
}

/* Point i of the reference, in the reference's vehicle frame. */
static void ref_point(const ego_moving_ref_t *ref, uint16_t i, fx_q16_16_t *x, fx_q16_16_t *y)
{
    point_at(ref->origin_x, ref->origin_y, ref->first + ((uint32_t)ref->offset[i] << 16),
             ref_range(ref, i), x, y);
}

/* The reference beams j, j + 1 on both sides of bearing b; false outside
 * the reference's field. */
static bool ref_bracket(const ego_moving_ref_t *ref, fx_bam32_t b, uint16_t *j)
{
    if (ref->count < 2u) {
        return false;
    }
    const uint32_t o = (b - ref->first) >> 16;
    if (o > ref->offset[ref->count - 1u]) {
        return false;
    }
    uint16_t lo = 0u;
    uint16_t hi = (uint16_t)(ref->count - 1u); /* offset[lo] <= o, lo < hi */
    while ((uint32_t)hi - lo > 1u) {
        const uint16_t mid = (uint16_t)((lo + hi) / 2u);
        if (ref->offset[mid] <= o) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    *j = lo;
    return true;
}

/* Is a reference point within near of (x, y), on the beams near.beams
 * around j and j + 1? Each point looked at is a unit of work. */
static bool ref_near(const ego_moving_ref_t *ref, uint16_t j, fx_q16_16_t x, fx_q16_16_t y,
                     near_t near, uint32_t *units)
{
    const int32_t from = ((int32_t)j > near.beams) ? (int32_t)j - near.beams : 0;
    const int32_t last = (int32_t)j + 1 + near.beams;
    const int32_t to = (last < (int32_t)ref->count) ? last + 1 : (int32_t)ref->count;
    for (int32_t i = from; i < to; i++) {
        *units += 1u;
        if (ref->range_cm[i] == 0u) {
            continue;
        }
        fx_q16_16_t rx;
        fx_q16_16_t ry;
        ref_point(ref, (uint16_t)i, &rx, &ry);
        if (dist_sq(fx_sub_q16(rx, x), fx_sub_q16(ry, y)) < near.sq) {
            return true;
        }
    }
    return false;
}

/* --- the current scan ----------------------------------------------------- */

/* The scan's beams c, c + 1 on both sides of bearing b; false outside. */
static bool scan_bracket(const ego_range_scan_t *scan, fx_bam32_t b, uint16_t *c)
{
    if (scan->count < 2u) {
        return false;
    }
    const fx_bam32_t b0 = ego_range_bearing(scan, 0u);
    const uint32_t o = b - b0;
    if (o > ego_range_bearing(scan, (uint16_t)(scan->count - 1u)) - b0) {
        return false;
    }
    uint16_t lo = 0u;
    uint16_t hi = (uint16_t)(scan->count - 1u);
    while ((uint32_t)hi - lo > 1u) {
        const uint16_t mid = (uint16_t)((lo + hi) / 2u);
        if (ego_range_bearing(scan, mid) - b0 <= o) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    *c = lo;
    return true;
}

static void scan_point(const ego_range_scan_t *scan, uint16_t k, fx_q16_16_t *x, fx_q16_16_t *y)
{
    point_at(scan->origin_x, scan->origin_y, ego_range_bearing(scan, k), range_q16(scan, k), x, y);
}

/* Is a valid current point of beams [from, to) within limit (squared,
 * Q32.32) of (x, y)? Each beam looked at is a unit of work. */
static bool scan_near(const ego_range_scan_t *scan, int32_t from, int32_t to, fx_q16_16_t x,
                      fx_q16_16_t y, uint64_t limit, uint32_t *units)
{
    from = (from > 0) ? from : 0;
    to = (to < (int32_t)scan->count) ? to : (int32_t)scan->count;
    for (int32_t k = from; k < to; k++) {
        *units += 1u;
        if (scan->range[k] == 0u) {
            continue;
        }
        fx_q16_16_t px;
        fx_q16_16_t py;
        scan_point(scan, (uint16_t)k, &px, &py);
        if (dist_sq(fx_sub_q16(px, x), fx_sub_q16(py, y)) < limit) {
            return true;
        }
    }
    return false;
}

/* A reference point, now at (x, y) in the current frame, is gone: the
 * current beams on both sides of it reach EGO_MOVING_BEYOND past it (or
 * have no return) and no current point lies near it. Nor did it move
 * elsewhere: no current point of the EGO_MOVING_REVEAL_BEAMS beams on
 * either side lies nearer it than half its distance to the point (px, py)
 * it is evidence for (a walker stepping aside reveals the wall behind,
 * which is no body receding). */
static bool vanished(const ego_range_scan_t *scan, fx_q16_16_t x, fx_q16_16_t y, fx_q16_16_t px,
                     fx_q16_16_t py, fx_q16_16_t extra, uint32_t *units)
{
    *units += 1u;
    fx_q16_16_t r;
    fx_bam32_t b;
    polar_of(fx_sub_q16(x, scan->origin_x), fx_sub_q16(y, scan->origin_y), &r, &b);
    uint16_t c;
    if (!scan_bracket(scan, b, &c)) {
        return false;
    }
    for (uint16_t k = c; k <= c + 1u; k++) {
        if (scan->range[k] != 0u && range_q16(scan, k) <= fx_add_q16(r, EGO_MOVING_BEYOND + extra)) {
            return false;
        }
    }
    const uint32_t step = (ego_range_bearing(scan, (uint16_t)(c + 1u)) - ego_range_bearing(scan, c)) >> 16;
    const near_t near = near_of(r, step, extra);
    if (scan_near(scan, (int32_t)c - near.beams, (int32_t)c + 2 + near.beams, x, y, near.sq, units)) {
        return false;
    }
    const uint64_t half = dist_sq(fx_sub_q16(px, x), fx_sub_q16(py, y)) / 4u;
    return !scan_near(scan, (int32_t)c - (int32_t)EGO_MOVING_REVEAL_BEAMS,
                      (int32_t)c + 2 + (int32_t)EGO_MOVING_REVEAL_BEAMS, x, y, half, units);
}

/* (a)^2 for a >= 0, Q32.32; 0 for a <= 0. */
static uint64_t square_pos(int64_t a)
{
    return (a > 0) ? (uint64_t)(a * a) : 0u;
}

/* Could a point at squared range d2 from the reference's origin, between
 * its beams j and j + 1, be evidence? The range tests of evidence() on
 * squares (no square root), with the least slack (at range 0) and a unit
 * of the last place to spare (evidence() rounds the root): every point
 * evidence() takes passes, most static points do not. */
static bool maybe_evidence(const ego_moving_ref_t *ref, uint16_t j, uint64_t d2)
{
    const int64_t slack = 2 * (int64_t)ref->slack_xy;
    const int64_t extra = (slack < EGO_MOVING_MAX_SLACK) ? slack : EGO_MOVING_MAX_SLACK;
    bool entered = true;
    for (uint16_t i = j; i <= j + 1u; i++) {
        const int64_t rho = ref_range(ref, i);
        if (ref->range_cm[i] == 0u) {
            continue;
        }
        /* Entered: rho > r + margin + extra. Receding: r in
         * (rho + beyond + extra, rho + recede). */
        entered = entered && square_pos(rho - EGO_MOVING_FREE_MARGIN - extra + 1) > d2;
        if (d2 > square_pos(rho + EGO_MOVING_BEYOND + extra - 1) &&
            d2 < square_pos(rho + EGO_MOVING_RECEDE + 1)) {
            return true;
        }
    }
    return entered;
}

/* Is the current point (px, py) evidence of motion (ego_moving.h)? */
static bool evidence(const view_t *v, fx_q16_16_t px, fx_q16_16_t py)
{
    *v->units += EGO_MOVING_UNITS_POINT;
    const ego_moving_ref_t *ref = v->ref;
    fx_q16_16_t qx;
    fx_q16_16_t qy;
    ego_pose_apply(&ref->pose, v->ref_sin, v->ref_cos, px, py, &qx, &qy);
    const fx_q16_16_t ox = fx_sub_q16(qx, ref->origin_x);
    const fx_q16_16_t oy = fx_sub_q16(qy, ref->origin_y);
    uint16_t j;
    if (!ref_bracket(ref, fx_atan2_quick(oy, ox), &j)) {
        return false;
    }
    if (!maybe_evidence(ref, j, dist_sq(ox, oy))) {
        return false;
    }
    const fx_q16_16_t r = range_of(ox, oy);
    /* The chained motion's uncertainty at this range (2 sigma: the root
     * sum of the lines' variances since the reference). */
    const int64_t slack = 2 * ((int64_t)ref->slack_xy + (((int64_t)r * ref->slack_theta) >> 16));
    const fx_q16_16_t extra = (slack < EGO_MOVING_MAX_SLACK) ? (fx_q16_16_t)slack : EGO_MOVING_MAX_SLACK;
    /* The ranges alone first: most points are neither (cheap). */
    bool entered = true;
    bool receding = false;
    for (uint16_t i = j; i <= j + 1u; i++) {
        const fx_q16_16_t rho = ref_range(ref, i);
        entered = entered &&
                  (ref->range_cm[i] == 0u || rho > fx_add_q16(r, EGO_MOVING_FREE_MARGIN + extra));
        receding = receding || (ref->range_cm[i] != 0u && rho < fx_sub_q16(r, EGO_MOVING_BEYOND + extra) &&
                                rho > fx_sub_q16(r, EGO_MOVING_RECEDE));
    }
    if (!entered && !receding) {
        return false;
    }
    const near_t near = near_of(r, (uint32_t)ref->offset[j + 1u] - ref->offset[j], extra);
    if (ref_near(ref, j, qx, qy, near, v->units)) {
        return false;
    }
    if (entered) {
        return true;
    }
    for (uint16_t i = j; i <= j + 1u; i++) {
        const fx_q16_16_t rho = ref_range(ref, i);
        if (ref->range_cm[i] == 0u || rho >= fx_sub_q16(r, EGO_MOVING_BEYOND + extra) ||
            rho <= fx_sub_q16(r, EGO_MOVING_RECEDE)) {
            continue;
        }
        /* The reference point in the current frame: the pose inverted. */
        fx_q16_16_t sx;
        fx_q16_16_t sy;
        ref_point(ref, i, &sx, &sy);
        const fx_q16_16_t dx = fx_sub_q16(sx, ref->pose.x);
        const fx_q16_16_t dy = fx_sub_q16(sy, ref->pose.y);
        const fx_q16_16_t cx = fx_add_q16(fx_mul_q16_q30(dx, v->ref_cos), fx_mul_q16_q30(dy, v->ref_sin));
        const fx_q16_16_t cy = fx_sub_q16(fx_mul_q16_q30(dy, v->ref_cos), fx_mul_q16_q30(dx, v->ref_sin));
        if (vanished(v->scan, cx, cy, px, py, extra, v->units)) {
            return true;
        }
    }
    return false;
}

/* --- clusters ------------------------------------------------------------- */

static bool usable(const ego_range_scan_t *scan, uint16_t k)
{
    return scan->range[k] != 0u && range_q16(scan, k) <= EGO_MOVING_MAX_RANGE;
}

/* Does beam k continue the segment of beam k - 1? */
static bool continues(const ego_range_scan_t *scan, uint16_t k)
{
    if (k == 0u || !usable(scan, (uint16_t)(k - 1u)) || !usable(scan, k)) {
        return false;
    }
    const int64_t d = (int64_t)range_q16(scan, k) - range_q16(scan, (uint16_t)(k - 1u));
    return d <= EGO_MOVING_GAP && d >= -(int64_t)EGO_MOVING_GAP;
}

/* Is the segment's end beam the body's own edge: its neighbour outside
 * the segment exists (not the field's edge) and lies beyond it or has no
 * return (nothing in front cuts it)? */
static bool uncut(const ego_range_scan_t *scan, uint16_t end, int32_t outside)
{
    if (outside < 0 || outside >= (int32_t)scan->count) {
        return false;
    }
    return scan->range[outside] == 0u || range_q16(scan, (uint16_t)outside) > range_q16(scan, end);
}

/* The box of beams [from, to) along their chord and across it, and the
 * cluster's marks. */
static void box_of(const ego_range_scan_t *scan, uint16_t from, uint16_t to, cluster_t *cl)
{
    fx_q16_16_t fx;
    fx_q16_16_t fy;
    fx_q16_16_t lx;
    fx_q16_16_t ly;
    scan_point(scan, from, &fx, &fy);
    scan_point(scan, (uint16_t)(to - 1u), &lx, &ly);
    const fx_q16_16_t dx = fx_sub_q16(lx, fx);
    const fx_q16_16_t dy = fx_sub_q16(ly, fy);
    const int64_t len = (int64_t)fx_sqrt_u64(dist_sq(dx, dy));
    int64_t ux = (int64_t)1 << 30; /* the chord's direction, Q2.30 */
    int64_t uy = 0;
    if (len > 0) {
        ux = ((int64_t)dx * ((int64_t)1 << 30)) / len;
        uy = ((int64_t)dy * ((int64_t)1 << 30)) / len;
    }
    int64_t amin = INT64_MAX;
    int64_t amax = INT64_MIN;
    int64_t wmin = INT64_MAX;
    int64_t wmax = INT64_MIN;
    for (uint16_t k = from; k < to; k++) {
        fx_q16_16_t px;
        fx_q16_16_t py;
        scan_point(scan, k, &px, &py);
        const int64_t ex = fx_sub_q16(px, fx);
        const int64_t ey = fx_sub_q16(py, fy);
        /* Usable points lie within 35 m: each product < 2^54. */
        const int64_t a = fx_shr_round_s64(ex * ux + ey * uy, 30u); /* Q16.16 */
        const int64_t w = fx_shr_round_s64(ey * ux - ex * uy, 30u);
        amin = (a < amin) ? a : amin;
        amax = (a > amax) ? a : amax;
        wmin = (w < wmin) ? w : wmin;
        wmax = (w > wmax) ? w : wmax;
    }
    const int64_t am = (amin + amax) / 2;
    const int64_t wm = (wmin + wmax) / 2;
    cl->x = fx_add_q16(fx, fx_sat_s32(fx_shr_round_s64(am * ux - wm * uy, 30u)));
    cl->y = fx_add_q16(fy, fx_sat_s32(fx_shr_round_s64(am * uy + wm * ux, 30u)));
    cl->length = fx_sat_s32(amax - amin);
    cl->width = fx_sat_s32(wmax - wmin);
    cl->from = from;
    cl->points = (uint16_t)(to - from);
    cl->track = EGO_MOVING_TRACKS;
    cl->held = false;
    const fx_q16_16_t mx[MARKS] = {cl->x, fx, lx};
    const fx_q16_16_t my[MARKS] = {cl->y, fy, ly};
    for (uint32_t i = 0u; i < MARKS; i++) {
        cl->mark_x[i] = mx[i];
        cl->mark_y[i] = my[i];
    }
    cl->uncut[0] = true;
    cl->uncut[1] = uncut(scan, from, (int32_t)from - 1);
    cl->uncut[2] = uncut(scan, (uint16_t)(to - 1u), (int32_t)to);
}

/* Is the segment [from, to) a moving cluster? */
static bool moving(const view_t *v, uint16_t from, uint16_t to)
{
    const ego_range_scan_t *scan = v->scan;
    const uint32_t n = (uint32_t)to - from;
    if (n < EGO_MOVING_MIN_POINTS) {
        return false;
    }
    fx_q16_16_t fx;
    fx_q16_16_t fy;
    fx_q16_16_t lx;
    fx_q16_16_t ly;
    scan_point(scan, from, &fx, &fy);
    scan_point(scan, (uint16_t)(to - 1u), &lx, &ly);
    const uint64_t extent = (uint64_t)((int64_t)EGO_MOVING_MAX_EXTENT * EGO_MOVING_MAX_EXTENT);
    if (dist_sq(fx_sub_q16(lx, fx), fx_sub_q16(ly, fy)) > extent) {
        return false;
    }
    /* Moving when ev >= 2 and (10 ev >= 3 n or ev >= EGO_MOVING_EVIDENCE_MIN):
     * ev >= need. The count stops once the answer is known. */
    const uint32_t share = (3u * n + 9u) / 10u; /* 30 % of the points, rounded up */
    uint32_t need = EGO_MOVING_EVIDENCE_MIN;
    if (share < need) {
        need = share;
    }
    if (need < 2u) {
        need = 2u;
    }
    uint32_t ev = 0u;
    for (uint16_t k = from; k < to; k++) {
        if (ev >= need || ev + (uint32_t)(to - k) < need) {
            break;
        }
        if (*v->units >= v->max_units) {
            return false; /* the scan's work is spent */
        }
        fx_q16_16_t px;
        fx_q16_16_t py;
        scan_point(scan, k, &px, &py);
        ev += evidence(v, px, py) ? 1u : 0u;
    }
    return ev >= need;
}

/* The next segment [*from, *to) after *to (start with *to = 0): false
 * when there is none. */
static bool next_segment(const ego_range_scan_t *scan, uint16_t *from, uint16_t *to)
{
    uint16_t k = *to;
    while (k < scan->count && !usable(scan, k)) {
        k++;
    }
    if (k >= scan->count) {
        return false;
    }
    *from = k;
    k++;
    while (k < scan->count && continues(scan, k)) {
        k++;
    }
    *to = k;
    return true;
}

/* The moving clusters of the scan, in scan order, at most cap. */
static uint8_t find_clusters(const view_t *v, cluster_t *out, uint8_t cap)
{
    uint8_t n = 0u;
    uint16_t from = 0u;
    uint16_t to = 0u;
    while (n < cap && next_segment(v->scan, &from, &to)) {
        if (moving(v, from, to)) {
            box_of(v->scan, from, to, &out[n++]);
            *v->units += (uint32_t)to - from;
        }
    }
    return n;
}

/* --- tracks --------------------------------------------------------------- */

/* A point of the last scan's frame in the current one: the motion
 * (this scan in the last one's frame) inverted. */
static void into_current(const ego_pose_t *motion, fx_q2_30_t s, fx_q2_30_t c, fx_q16_16_t *x,
                         fx_q16_16_t *y)
{
    const fx_q16_16_t dx = fx_sub_q16(*x, motion->x);
    const fx_q16_16_t dy = fx_sub_q16(*y, motion->y);
    *x = fx_add_q16(fx_mul_q16_q30(dx, c), fx_mul_q16_q30(dy, s));
    *y = fx_sub_q16(fx_mul_q16_q30(dy, c), fx_mul_q16_q30(dx, s));
}

/* Every track moved on by dt and into the current frame. */
static void predict_tracks(ego_moving_t *m, const ego_pose_t *motion, uint32_t dt_us)
{
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(motion->theta, &s, &c);
    for (uint32_t i = 0u; i < EGO_MOVING_TRACKS; i++) {
        ego_moving_track_t *t = &m->track[i];
        t->seen = false;
        if (!t->used) {
            continue;
        }
        if (t->known) {
            t->x = fx_add_q16(t->x, fx_sat_s32((int64_t)t->vx * dt_us / US_PER_S));
            t->y = fx_add_q16(t->y, fx_sat_s32((int64_t)t->vy * dt_us / US_PER_S));
            /* A velocity turns with the frame: no translation. */
            const ego_pose_t turn = {motion->theta, 0, 0};
            into_current(&turn, s, c, &t->vx, &t->vy);
        }
        into_current(motion, s, c, &t->x, &t->y);
        for (uint32_t k = 0u; k < MARKS; k++) {
            into_current(motion, s, c, &t->anchor_x[k], &t->anchor_y[k]);
        }
        const uint64_t age = (uint64_t)t->anchor_age_us + dt_us;
        t->anchor_age_us = (age > UINT32_MAX) ? UINT32_MAX : (uint32_t)age;
    }
}

/* Clusters to tracks, nearest pairs first, within EGO_MOVING_GATE. */
static void associate(ego_moving_t *m, cluster_t *cl, uint8_t n)
{
    const uint64_t gate = (uint64_t)((int64_t)EGO_MOVING_GATE * EGO_MOVING_GATE);
    for (uint8_t round = 0u; round < n; round++) {
        uint64_t best = gate;
        uint8_t bi = n;
        uint8_t bt = EGO_MOVING_TRACKS;
        for (uint8_t i = 0u; i < n; i++) {
            if (cl[i].track != EGO_MOVING_TRACKS) {
                continue;
            }
            for (uint8_t t = 0u; t < EGO_MOVING_TRACKS; t++) {
                const ego_moving_track_t *tr = &m->track[t];
                if (!tr->used || tr->seen) {
                    continue;
                }
                const uint64_t d = dist_sq(fx_sub_q16(cl[i].x, tr->x), fx_sub_q16(cl[i].y, tr->y));
                if (d <= best) {
                    best = d;
                    bi = i;
                    bt = t;
                }
            }
        }
        if (bi == n) {
            return;
        }
        cl[bi].track = bt;
        m->track[bt].seen = true;
    }
}

/* The hold (ego_moving.h): a confirmed vehicle's track that no moving
 * cluster matched takes the nearest other segment whose box centre lies
 * within EGO_MOVING_HOLD_GATE of its prediction. Returns the clusters. */
static uint8_t hold_tracks(ego_moving_t *m, const ego_range_scan_t *scan, cluster_t *cl, uint8_t n)
{
    const int64_t min_speed = EGO_MOVING_HOLD_MIN_SPEED;
    for (uint8_t t = 0u; t < EGO_MOVING_TRACKS && n < EGO_MOVING_CLUSTERS; t++) {
        ego_moving_track_t *tr = &m->track[t];
        if (!tr->used || tr->seen || tr->hits < EGO_MOVING_CONFIRM || !tr->from_ends ||
            tr->length < EGO_MOVING_HOLD_TRACK_LENGTH || tr->held >= EGO_MOVING_MAX_HELD ||
            dist_sq(tr->vx, tr->vy) < (uint64_t)(min_speed * min_speed)) {
            continue;
        }
        /* The segments across the prediction's bearing (a box centre lies
         * within its segment's bearings): at most two. */
        fx_q16_16_t r;
        fx_bam32_t b;
        polar_of(fx_sub_q16(tr->x, scan->origin_x), fx_sub_q16(tr->y, scan->origin_y), &r, &b);
        uint16_t c;
        if (!scan_bracket(scan, b, &c)) {
            continue;
        }
        uint64_t best = (uint64_t)((int64_t)EGO_MOVING_HOLD_GATE * EGO_MOVING_HOLD_GATE);
        bool found = false;
        uint16_t from = 0u;
        uint16_t to = 0u;
        while (next_segment(scan, &from, &to) && from <= c + 1u) {
            bool taken = to <= c || (uint32_t)to - from < EGO_MOVING_MIN_POINTS;
            for (uint8_t i = 0u; i < n && !taken; i++) {
                taken = cl[i].from == from;
            }
            if (taken) {
                continue;
            }
            fx_q16_16_t fx;
            fx_q16_16_t fy;
            fx_q16_16_t lx;
            fx_q16_16_t ly;
            scan_point(scan, from, &fx, &fy);
            scan_point(scan, (uint16_t)(to - 1u), &lx, &ly);
            const uint64_t chord = dist_sq(fx_sub_q16(lx, fx), fx_sub_q16(ly, fy));
            if (chord < (uint64_t)((int64_t)EGO_MOVING_HOLD_MIN_LENGTH * EGO_MOVING_HOLD_MIN_LENGTH) ||
                chord > (uint64_t)((int64_t)EGO_MOVING_MAX_EXTENT * EGO_MOVING_MAX_EXTENT)) {
                continue;
            }
            cluster_t cand;
            box_of(scan, from, to, &cand);
            m->units += (uint32_t)to - from;
            const uint64_t d = dist_sq(fx_sub_q16(cand.x, tr->x), fx_sub_q16(cand.y, tr->y));
            if (d < best) {
                best = d;
                cl[n] = cand;
                found = true;
            }
        }
        if (found) {
            cl[n].track = t;
            cl[n].held = true;
            tr->seen = true;
            n++;
        }
    }
    return n;
}

/* (a - b) per second over age_us. */
static fx_q16_16_t rate(fx_q16_16_t a, fx_q16_16_t b, uint32_t age_us)
{
    return fx_sat_s32(((int64_t)a - b) * US_PER_S / age_us);
}

static void set_anchor(ego_moving_track_t *t, const cluster_t *cl)
{
    for (uint32_t i = 0u; i < MARKS; i++) {
        t->anchor_x[i] = cl->mark_x[i];
        t->anchor_y[i] = cl->mark_y[i];
        t->anchor_uncut[i] = cl->uncut[i];
    }
    t->anchor_age_us = 0u;
}

/* The cluster's velocity since the anchor: the mean of its ends' that
 * were uncut then and now (a body's edges move with it; the centre of its
 * visible part slides while something cuts it), else the centre's.
 * True when it is the ends'. */
static bool measure_velocity(const ego_moving_track_t *t, const cluster_t *cl, fx_q16_16_t *vx,
                             fx_q16_16_t *vy)
{
    int64_t sx = 0;
    int64_t sy = 0;
    int32_t n = 0;
    for (uint32_t i = 1u; i < MARKS; i++) {
        if (t->anchor_uncut[i] && cl->uncut[i]) {
            sx += rate(cl->mark_x[i], t->anchor_x[i], t->anchor_age_us);
            sy += rate(cl->mark_y[i], t->anchor_y[i], t->anchor_age_us);
            n++;
        }
    }
    if (n == 0) {
        *vx = rate(cl->mark_x[0], t->anchor_x[0], t->anchor_age_us);
        *vy = rate(cl->mark_y[0], t->anchor_y[0], t->anchor_age_us);
        return false;
    }
    *vx = (fx_q16_16_t)(sx / n);
    *vy = (fx_q16_16_t)(sy / n);
    return true;
}

static void update_track(ego_moving_track_t *t, const cluster_t *cl)
{
    if (t->anchor_age_us >= EGO_MOVING_VEL_MIN_US) {
        fx_q16_16_t vx;
        fx_q16_16_t vy;
        t->from_ends = measure_velocity(t, cl, &vx, &vy);
        if (t->known) {
            t->vx = fx_add_q16(t->vx, fx_sat_s32(((int64_t)vx - t->vx) / 4));
            t->vy = fx_add_q16(t->vy, fx_sat_s32(((int64_t)vy - t->vy) / 4));
        } else {
            t->vx = vx;
            t->vy = vy;
            t->known = true;
        }
        if (t->anchor_age_us >= EGO_MOVING_VEL_WINDOW_US) {
            set_anchor(t, cl);
        }
    }
    t->x = cl->x;
    t->y = cl->y;
    t->hits = (t->hits < UINT8_MAX) ? (uint8_t)(t->hits + 1u) : UINT8_MAX;
    t->misses = 0u;
    if (cl->held) {
        t->held = (t->held < UINT8_MAX) ? (uint8_t)(t->held + 1u) : UINT8_MAX;
    } else {
        t->held = 0u;
        t->length = (cl->length > t->length) ? cl->length : t->length;
    }
}

/* A slot for a new track: a free one, else the one missed longest. */
static uint8_t free_slot(const ego_moving_t *m)
{
    uint8_t pick = EGO_MOVING_TRACKS;
    uint8_t most = 0u;
    for (uint8_t t = 0u; t < EGO_MOVING_TRACKS; t++) {
        const ego_moving_track_t *tr = &m->track[t];
        if (!tr->used) {
            return t;
        }
        if (!tr->seen && (pick == EGO_MOVING_TRACKS || tr->misses > most)) {
            most = tr->misses;
            pick = t;
        }
    }
    return pick;
}

static void start_track(ego_moving_t *m, uint8_t slot, const cluster_t *cl)
{
    ego_moving_track_t *t = &m->track[slot];
    *t = (ego_moving_track_t){0};
    t->used = true;
    t->seen = true;
    t->x = cl->x;
    t->y = cl->y;
    t->length = cl->length;
    set_anchor(t, cl);
    t->hits = 1u;
    t->id = m->next_id;
    m->next_id = (m->next_id == UINT16_MAX) ? 1u : (uint16_t)(m->next_id + 1u);
}

/* --- references ----------------------------------------------------------- */

static void take_reference(ego_moving_ref_t *ref, const ego_range_scan_t *scan, uint32_t time_us)
{
    ref->pose = (ego_pose_t){0u, 0, 0};
    ref->slack_xy = 0;
    ref->slack_theta = 0;
    ref->var_xy = 0u;
    ref->var_theta = 0u;
    ref->time_us = time_us;
    ref->origin_x = scan->origin_x;
    ref->origin_y = scan->origin_y;
    ref->first = (scan->count > 0u) ? ego_range_bearing(scan, 0u) : 0u;
    const uint32_t stride = ((uint32_t)scan->count + EGO_MOVING_REF_POINTS - 1u) / EGO_MOVING_REF_POINTS;
    uint16_t n = 0u;
    for (uint32_t k = 0u; k < scan->count; k += stride) {
        const uint16_t beam = (uint16_t)k;
        ref->offset[n] = (uint16_t)((ego_range_bearing(scan, beam) - ref->first) >> 16);
        const uint64_t cm = ((uint64_t)scan->range[beam] * scan->range_unit_um + 5000u) / 10000u;
        ref->range_cm[n] = (scan->range[beam] == 0u) ? 0u
                           : (cm == 0u)              ? 1u
                           : (cm > UINT16_MAX)       ? UINT16_MAX
                                                     : (uint16_t)cm;
        n++;
    }
    ref->count = n;
}

void ego_moving_reset(ego_moving_t *m)
{
    *m = (ego_moving_t){0};
    m->next_id = 1u;
}

static int16_t cm_of(fx_q16_16_t v)
{
    const int64_t cm = fx_shr_round_s64((int64_t)v * 100, 16u);
    if (cm > INT16_MAX) {
        return (int16_t)INT16_MAX;
    }
    if (cm <= INT16_MIN) {
        return (int16_t)(INT16_MIN + 1); /* INT16_MIN is EGO_MOVING_UNKNOWN */
    }
    return (int16_t)cm;
}

static uint16_t ucm_of(fx_q16_16_t v)
{
    const int64_t cm = fx_shr_round_s64((int64_t)v * 100, 16u);
    return (cm > UINT16_MAX) ? UINT16_MAX : (cm < 0) ? 0u : (uint16_t)cm;
}

/* An aperture line slower than EGO_MOVING_START_SPEED (dt_us in 1 us ..
 * 1 s: the limit below 2^16). */
static bool starting_off(const ego_output_t *out, uint32_t dt_us)
{
    const int64_t limit = (int64_t)EGO_MOVING_START_SPEED * dt_us / 1000000; /* Q16.16 m */
    return (out->flags & EGO_FLAG_APERTURE) != 0u &&
           dist_sq(out->pose.x, out->pose.y) < (uint64_t)(limit * limit);
}

uint8_t ego_moving_scan(ego_moving_t *m, const ego_range_scan_t *scan, uint32_t time_us,
                        const ego_output_t *out, ego_moving_object_t *objects, uint8_t cap)
{
    const uint32_t dt_us = time_us - m->time_us;
    m->time_us = time_us;
    m->units = 0u;
    if ((out->flags & UNMEASURED) != 0u || dt_us == 0u || dt_us > EGO_MOVING_MAX_DT_US) {
        ego_moving_reset(m);
        m->time_us = time_us;
        take_reference(&m->ref[0], scan, time_us);
        m->refs = 1u;
        return 0u;
    }
    /* A motion without a trustworthy covariance (suspect, on objects, not
     * measured, starting off along a corridor) would move the static world
     * against every reference by an unknown amount: they start over from
     * this scan. Else each reference adds the line's standard deviations
     * to its slack. */
    const bool unknown = starting_off(out, dt_us) ||
                         (out->flags & (EGO_FLAG_SUSPECT | EGO_FLAG_ON_OBJECTS)) != 0u ||
                         out->cov.xx == EGO_COV_SATURATED || out->cov.yy == EGO_COV_SATURATED ||
                         out->cov.tt == EGO_COV_SATURATED;
    m->refs = unknown ? 0u : m->refs;
    /* Q2.30 variances -> Q16.16 deviations. An aperture's weak direction
     * is the prediction's (its variance says nothing of it). */
    const uint64_t var_xy = ((out->flags & EGO_FLAG_APERTURE) != 0u)
                                ? 0u
                                : (uint64_t)((int64_t)out->cov.xx + out->cov.yy) << 2;
    for (uint32_t i = 0u; i < m->refs; i++) {
        ego_moving_ref_t *ref = &m->ref[i];
        ref->pose = ego_pose_then(&ref->pose, &out->pose);
        ref->var_xy += var_xy;
        ref->var_theta += (uint64_t)(uint32_t)out->cov.tt << 2;
        ref->slack_xy = (fx_q16_16_t)fx_sqrt_u64(ref->var_xy);
        ref->slack_theta = (fx_q16_16_t)fx_sqrt_u64(ref->var_theta);
    }
    predict_tracks(m, &out->pose, dt_us);

    cluster_t cl[EGO_MOVING_CLUSTERS];
    uint8_t n = 0u;
    /* Filled in slot order, then the oldest replaced. */
    const uint8_t oldest = (m->refs == EGO_MOVING_REFS) ? (uint8_t)((m->newest + 1u) % EGO_MOVING_REFS) : 0u;
    if (m->refs > 0u && time_us - m->ref[oldest].time_us >= EGO_MOVING_REF_MIN_US) {
        view_t v = {scan, &m->ref[oldest], 0, 0, &m->units,
                    (uint32_t)scan->count * EGO_MOVING_UNITS_PER_BEAM};
        fx_sincos(v.ref->pose.theta, &v.ref_sin, &v.ref_cos);
        n = find_clusters(&v, cl, EGO_MOVING_CLUSTERS);
    }
    associate(m, cl, n);
    n = hold_tracks(m, scan, cl, n);
    for (uint8_t i = 0u; i < n; i++) {
        if (cl[i].track != EGO_MOVING_TRACKS) {
            update_track(&m->track[cl[i].track], &cl[i]);
            continue;
        }
        const uint8_t slot = free_slot(m);
        if (slot != EGO_MOVING_TRACKS) {
            start_track(m, slot, &cl[i]);
            cl[i].track = slot;
        }
    }
    for (uint8_t t = 0u; t < EGO_MOVING_TRACKS; t++) {
        ego_moving_track_t *tr = &m->track[t];
        if (tr->used && !tr->seen && ++tr->misses > EGO_MOVING_MAX_MISSES) {
            tr->used = false;
        }
    }

    if (m->refs == 0u || time_us - m->ref[m->newest].time_us >= EGO_MOVING_REF_EVERY_US) {
        const uint8_t slot = (m->refs < EGO_MOVING_REFS) ? m->refs : oldest;
        take_reference(&m->ref[slot], scan, time_us);
        m->newest = slot;
        m->refs = (m->refs < EGO_MOVING_REFS) ? (uint8_t)(m->refs + 1u) : m->refs;
    }

    uint8_t written = 0u;
    for (uint8_t i = 0u; i < n && written < cap; i++) {
        if (cl[i].track == EGO_MOVING_TRACKS) {
            continue;
        }
        const ego_moving_track_t *tr = &m->track[cl[i].track];
        if (tr->hits < EGO_MOVING_CONFIRM) {
            continue;
        }
        ego_moving_object_t *o = &objects[written++];
        o->id = tr->id;
        o->points = cl[i].points;
        o->cx_cm = cm_of(cl[i].x);
        o->cy_cm = cm_of(cl[i].y);
        o->length_cm = ucm_of(cl[i].length);
        o->width_cm = ucm_of(cl[i].width);
        o->vx_cms = (int16_t)EGO_MOVING_UNKNOWN;
        o->vy_cms = (int16_t)EGO_MOVING_UNKNOWN;
        if (tr->known) {
            o->vx_cms = cm_of(tr->vx);
            o->vy_cms = cm_of(tr->vy);
        }
    }
    return written;
}
