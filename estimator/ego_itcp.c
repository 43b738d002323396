/* ego_itcp.c - see ego_itcp.h. */
#include "ego_itcp.h"

#include <stddef.h>
#include <string.h>

#include "ego_fx_math.h"

/* How far past the end of an artificially ended surface a point may still
 * be matched to the end: the range noise of the scanner, not more. */
#define END_TOLERANCE FX_Q16_16_C(0.02)

void ego_itcp_defaults(itcp_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->weighted = true;
    params->tangent_gate = false;
    params->gate = FX_BAM32_DEG_C(25.0);
    params->main_tolerance = FX_BAM32_DEG_C(10.0);
    params->radius_start = FX_Q16_16_C(0.6);
    params->radius_min = FX_Q16_16_C(0.08);
    params->radius_fine = FX_Q16_16_C(0.05);
    params->radius_shrink = (fx_q2_30_t)(FX_Q2_30_ONE / 4 * 3); /* 0.75 */
    params->max_iterations = 30u;
    params->converge_translation = FX_Q16_16_C(0.0001);
    params->converge_rotation = FX_BAM32_DEG_C(0.001);
    params->inlier_distance = FX_Q16_16_C(0.10);
    params->aperture_ratio = (fx_q2_30_t)(FX_Q2_30_ONE / 5);
    params->min_matches = 10u;
}

static void sums_add(ego_itcp_group_sums_t *s, fx_q16_16_t x, fx_q16_16_t y, fx_q16_16_t u,
                     fx_q16_16_t v)
{
    s->n++;
    s->sx += x;
    s->sy += y;
    s->su += u;
    s->sv += v;
    s->sxu += (int64_t)x * u;
    s->sxv += (int64_t)x * v;
    s->syu += (int64_t)y * u;
    s->syv += (int64_t)y * v;
}

/* What one matching pass found (ego_itcp.h). */
typedef ego_itcp_pass_t pass_t;

/* Context of a matching pass. */
typedef struct {
    const ego_scan_t *last;
    const itcp_params_t *params;
    fx_bam32_t ref;          /* middle bearing of the last scan */
    fx_bam32_t main_direction;
    fx_q16_16_t radius;
    uint32_t *units;         /* the work of the searches is added here (ego_work.h) */
} matcher_t;

/* Closest point to (qx, qy) on segment j -> j + 1 of the last scan; its
 * squared distance (Q32.32) and the fraction along the segment (Q2.30; 0
 * or 1 when the projection falls outside). */
static uint64_t closest_on_segment(const ego_scan_t *l, uint16_t j, fx_q16_16_t qx,
                                   fx_q16_16_t qy, fx_q16_16_t *cx, fx_q16_16_t *cy,
                                   fx_q2_30_t *t_out)
{
    const int64_t dx = (int64_t)l->x[j + 1u] - l->x[j];
    const int64_t dy = (int64_t)l->y[j + 1u] - l->y[j];
    int64_t num = ((int64_t)qx - l->x[j]) * dx + ((int64_t)qy - l->y[j]) * dy;
    int64_t den = dx * dx + dy * dy;
    fx_q2_30_t t = 0;
    if (num <= 0 || den == 0) {
        t = 0;
    } else if (num >= den) {
        t = FX_Q2_30_ONE;
    } else {
        while (den >= ((int64_t)1 << 32)) { /* keep num << 30 in range */
            num >>= 1;
            den >>= 1;
        }
        t = (den > 0) ? (fx_q2_30_t)((num << 30) / den) : 0;
    }
    *cx = (fx_q16_16_t)(l->x[j] + fx_mul_q16_q30((fx_q16_16_t)dx, t));
    *cy = (fx_q16_16_t)(l->y[j] + fx_mul_q16_q30((fx_q16_16_t)dy, t));
    *t_out = t;
    const int64_t ex = (int64_t)qx - *cx;
    const int64_t ey = (int64_t)qy - *cy;
    return (uint64_t)(ex * ex + ey * ey);
}

/* How far (Q16.16 m) the projection of (qx, qy) falls beyond the end of
 * segment j -> j + 1 where it was clamped (t 0 or 1). */
static int64_t beyond_end(const ego_scan_t *l, uint16_t j, fx_q16_16_t qx, fx_q16_16_t qy,
                          fx_q2_30_t t)
{
    const int64_t dx = (int64_t)l->x[j + 1u] - l->x[j];
    const int64_t dy = (int64_t)l->y[j + 1u] - l->y[j];
    const int64_t num = ((int64_t)qx - l->x[j]) * dx + ((int64_t)qy - l->y[j]) * dy;
    const int64_t den = dx * dx + dy * dy;
    const int64_t length = fx_sqrt_u64((uint64_t)den);
    if (t == 0) {
        return (length > 0) ? -num / length : 0;
    }
    return (num - den) / length;
}

static uint64_t range_sq(const ego_scan_t *l, uint16_t j)
{
    const int64_t dx = (int64_t)l->x[j] - l->origin_x;
    const int64_t dy = (int64_t)l->y[j] - l->origin_y;
    return (uint64_t)(dx * dx + dy * dy);
}

/* Is point e, the end of a surface whose neighbour across the break is n
 * (or none), where the scanner merely stops seeing that surface? True at
 * the edge of the field of view, next to missing values (range limit, no
 * return), and behind a nearer object (e farther than n); false at the
 * real edge of an object (e nearer than n). */
static bool end_is_artificial(const ego_scan_t *l, uint16_t e, int32_t n)
{
    if (n < 0 || n >= (int32_t)l->count) {
        return true;
    }
    const uint16_t link = (uint16_t)((n > (int32_t)e) ? e : (uint16_t)n);
    if ((l->flags[link] & EGO_LINK_GAP) != 0u) {
        return true;
    }
    return range_sq(l, e) > range_sq(l, (uint16_t)n);
}

/* Is point j joined to a surface on its left / right in scan order? */
static bool linked_before(const ego_scan_t *l, uint16_t j)
{
    return j > 0u && (l->flags[j - 1u] & (EGO_LINK_BREAK | EGO_LINK_OCCLUSION)) == 0u;
}

static bool linked_after(const ego_scan_t *l, uint16_t j)
{
    return j + 1u < l->count && (l->flags[j] & (EGO_LINK_BREAK | EGO_LINK_OCCLUSION)) == 0u;
}

typedef struct {
    bool found;
    uint64_t dist_sq;
    fx_q16_16_t x;
    fx_q16_16_t y;
} match_t;

/* What one search for the nearest surface looks for: the current point
 * moved to (x, y), its turned tangent tc (if has_tc), the search radius. */
typedef struct {
    fx_q16_16_t x;
    fx_q16_16_t y;
    bool has_tc;
    fx_bam32_t tc;
    uint64_t radius_sq;
} target_t;

/* The square of half-width radius around the target, as int32 bounds
 * (clamped: a bound past the int32 range excludes nothing there). */
typedef struct {
    int32_t lo_x;
    int32_t hi_x;
    int32_t lo_y;
    int32_t hi_y;
} square_t;

static int32_t clamp_s32(int64_t v)
{
    return (v > INT32_MAX) ? INT32_MAX : (v < INT32_MIN) ? INT32_MIN : (int32_t)v;
}

static square_t square_around(fx_q16_16_t x, fx_q16_16_t y, fx_q16_16_t radius)
{
    const square_t sq = {clamp_s32((int64_t)x - radius), clamp_s32((int64_t)x + radius),
                         clamp_s32((int64_t)y - radius), clamp_s32((int64_t)y + radius)};
    return sq;
}

/* Do points a and b both lie beyond one side of the square? Then so does
 * every point between them, the closest point of their segment included
 * (it lies in their box, rounding included): farther than the radius on
 * one axis. */
static bool outside_square(const ego_scan_t *l, uint16_t a, uint16_t b, const square_t *sq)
{
    const int32_t xa = l->x[a];
    const int32_t xb = l->x[b];
    const int32_t ya = l->y[a];
    const int32_t yb = l->y[b];
    return (xa < sq->lo_x && xb < sq->lo_x) || (xa > sq->hi_x && xb > sq->hi_x) ||
           (ya < sq->lo_y && yb < sq->lo_y) || (ya > sq->hi_y && yb > sq->hi_y);
}

/* Considers point j of the last scan and, if it is a surface, its segment
 * to j + 1, for the target q (find_match calls it only when q is within
 * the radius of the box of the two points). */
static void consider(const matcher_t *m, const target_t *q, uint16_t j, match_t *best)
{
    *m->units += EGO_COST_MATCH_SEGMENT;
    const ego_scan_t *l = m->last;
    const fx_q16_16_t qx = q->x;
    const fx_q16_16_t qy = q->y;
    const uint64_t radius_sq = q->radius_sq;
    fx_q16_16_t cx = l->x[j];
    fx_q16_16_t cy = l->y[j];
    uint64_t d2;
    uint16_t near_point = j;
    bool segment = false;
    if (j + 1u < l->count && (l->flags[j] & (EGO_LINK_BREAK | EGO_LINK_OCCLUSION)) == 0u) {
        fx_q2_30_t t;
        d2 = closest_on_segment(l, j, qx, qy, &cx, &cy, &t);
        if (d2 > radius_sq || (best->found && d2 >= best->dist_sq)) {
            return;
        }
        /* Clamped at an end where the scanner merely stops seeing the
         * surface (range limit, field of view, behind a nearer object):
         * the surface may well go on, so the end point is no evidence.
         * Without this, the ends of the visible walls, which move with the
         * scanner, pull every registration in a corridor towards no motion. */
        if ((t == 0 && !linked_before(l, j) && end_is_artificial(l, j, (int32_t)j - 1)) ||
            (t == FX_Q2_30_ONE && !linked_after(l, (uint16_t)(j + 1u)) &&
             end_is_artificial(l, (uint16_t)(j + 1u), (int32_t)j + 2))) {
            if (beyond_end(l, j, qx, qy, t) > END_TOLERANCE) {
                return;
            }
        }
        near_point = (t > FX_Q2_30_ONE / 2) ? (uint16_t)(j + 1u) : j;
        segment = true;
    } else {
        /* The end of a surface is covered by its segment. A lone point is
         * a feature (a post) unless it only lacks neighbours because the
         * beams graze its surface (occlusion links): far points of a wall
         * seen along its length lie metres apart, and matching them point
         * to point pulls towards no motion. */
        if (linked_before(l, j) || (l->flags[j] & EGO_LINK_OCCLUSION) != 0u ||
            (j > 0u && (l->flags[j - 1u] & EGO_LINK_OCCLUSION) != 0u)) {
            return;
        }
        const int64_t ex = (int64_t)qx - cx;
        const int64_t ey = (int64_t)qy - cy;
        d2 = (uint64_t)(ex * ex + ey * ey);
        if (d2 > radius_sq || (best->found && d2 >= best->dist_sq)) {
            return;
        }
    }
    if (m->params->tangent_gate && q->has_tc) {
        fx_bam32_t tl;
        if ((l->flags[near_point] & EGO_POINT_HAS_TANGENT) != 0u) {
            tl = l->tangent[near_point];
        } else if (segment) {
            tl = fx_atan2((int64_t)l->y[j + 1u] - l->y[j], (int64_t)l->x[j + 1u] - l->x[j]);
        } else {
            return; /* nothing to compare the tangent with */
        }
        if (fx_line_angle_diff(q->tc, tl) > m->params->gate) {
            return;
        }
    }
    best->found = true;
    best->dist_sq = d2;
    best->x = cx;
    best->y = cy;
}

/* Is point j's bearing below rel (relative to m->ref)? False up to an
 * index, true after it: bearings increase along the scan. */
static bool bearing_below(const matcher_t *m, uint16_t j, int64_t rel)
{
    return (int64_t)fx_bam32_diff(m->last->bearing[j], m->ref) < rel;
}

/* Index of the first last-scan point whose bearing is at least rel. The
 * search starts at hint (the last query's answer: consecutive points of a
 * scan fall close together) and gallops outwards, 1, 2, 4, ... points,
 * before the binary search: a few steps instead of log2(count) when the
 * hint is good, at most twice as many when it is not. */
static uint16_t lower_bound(const matcher_t *m, int64_t rel, uint16_t hint)
{
    const uint16_t n = m->last->count;
    uint16_t lo = 0u; /* every j < lo is below */
    uint16_t hi = n;  /* every j >= hi is not */
    if (hint > n) {
        hint = n;
    }
    if (hint < n && bearing_below(m, hint, rel)) {
        lo = (uint16_t)(hint + 1u);
        for (uint32_t step = 1u; (uint32_t)hint + step < n; step *= 2u) {
            const uint16_t at = (uint16_t)(hint + step);
            if (!bearing_below(m, at, rel)) {
                hi = at;
                break;
            }
            lo = (uint16_t)(at + 1u);
        }
    } else {
        hi = hint;
        for (uint32_t step = 1u; step <= hint; step *= 2u) {
            const uint16_t at = (uint16_t)(hint - step);
            if (bearing_below(m, at, rel)) {
                lo = (uint16_t)(at + 1u);
                break;
            }
            hi = at;
        }
    }
    while (lo < hi) {
        const uint16_t mid = (uint16_t)((lo + hi) / 2u);
        if (bearing_below(m, mid, rel)) {
            lo = (uint16_t)(mid + 1u);
        } else {
            hi = mid;
        }
    }
    return lo;
}



/* A current point moved into the last scan's frame, located in its scan
 * order once for every test on it. */
typedef struct {
    fx_q16_16_t x;
    fx_q16_16_t y;
    int64_t ox;    /* from the last scanner */
    int64_t oy;
    int64_t rel;   /* bearing from the last scanner, relative to m->ref */
    int32_t slack; /* how far rel may be from the exact bearing */
    uint16_t j0;   /* first last-scan point with a bearing >= rel (locate) */
} query_t;

/* Where a query starts: its coordinates from the last scanner, rel by
 * quick_bearing (find_match widens its cone by its error). */
static void query_at(const matcher_t *m, fx_q16_16_t qx, fx_q16_16_t qy, query_t *q)
{
    q->x = qx;
    q->y = qy;
    q->ox = (int64_t)qx - m->last->origin_x;
    q->oy = (int64_t)qy - m->last->origin_y;
    q->rel = fx_bam32_diff(fx_atan2_quick(q->oy, q->ox), m->ref);
    q->slack = FX_ATAN2_QUICK_ERROR;
    *m->units += EGO_COST_MATCH_POINT;
}

/* For the walk alone: j0 the first point at or past rel. A start a point
 * off walks the same segments, but for ties and walks cut by
 * EGO_ITCP_MAX_WALK. hint: where the search for j0 starts (lower_bound). */
static void locate(const matcher_t *m, fx_q16_16_t qx, fx_q16_16_t qy, uint16_t hint, query_t *q)
{
    query_at(m, qx, qy, q);
    q->j0 = lower_bound(m, q->rel, hint);
}

/* As locate, with j0 the first point at or past the exact bearing (as
 * fx_atan2 gives it), for seen_through, which needs the beams on both
 * sides: when no last-scan bearing lies within FX_ATAN2_QUICK_ERROR of rel,
 * the first one past rel - FX_ATAN2_QUICK_ERROR is that point; otherwise
 * (a beam within 0.022 deg: a few percent of the points) fx_atan2
 * decides. */
static void locate_exactly(const matcher_t *m, fx_q16_16_t qx, fx_q16_16_t qy, uint16_t hint,
                           query_t *q)
{
    query_at(m, qx, qy, q);
    /* (Within the error of half a turn from ref the exact one may wrap.) */
    const bool wraps = q->rel < (int64_t)INT32_MIN + FX_ATAN2_QUICK_ERROR ||
                       q->rel > (int64_t)INT32_MAX - FX_ATAN2_QUICK_ERROR;
    uint16_t j0 = lower_bound(m, q->rel - FX_ATAN2_QUICK_ERROR, hint);
    if (wraps || (j0 < m->last->count && bearing_below(m, j0, q->rel + FX_ATAN2_QUICK_ERROR))) {
        j0 = lower_bound(m, fx_bam32_diff(fx_atan2(q->oy, q->ox), m->ref), j0);
    }
    q->j0 = j0;
}

/* Half-angle of the cone the search disc subtends: asin(radius / r) <=
 * (pi / 2) (radius / r), i.e. (radius / r) quarter turns, in binary angle: radius 2^30 / r, or a
 * little more (a wider cone only walks a little further), with one 32-bit
 * division: r cut to 16 significant bits (rounded down), radius by the
 * same shift (rounded up), the quotient rounded up, in units of 2^15
 * (0.003 deg). r <= radius: half a turn. */
static int64_t cone_of(fx_q16_16_t radius, int64_t r)
{
    if (r <= radius) {
        return FX_BAM32_HALF;
    }
    if (r > INT32_MAX || radius < 0) {
        return (((int64_t)radius * ((int64_t)1 << 30)) / r) + 1; /* out of any scan's range */
    }
    uint32_t d = (uint32_t)r;
    uint32_t n = (uint32_t)radius;
    const unsigned b = fx_bits_u32(d);
    if (b > 16u) {
        const unsigned shift = b - 16u;
        const uint32_t lost = n & ((1u << shift) - 1u);
        d >>= shift;
        n = (n >> shift) + ((lost != 0u) ? 1u : 0u);
    }
    /* d < 2^16 and n <= d + 1 <= 2^16 (radius < r): n 2^15 + d - 1 < 2^32. */
    return (int64_t)(((n << 15) + d - 1u) / d) << 15;
}

static match_t find_match(const matcher_t *m, const query_t *q, bool has_tc, fx_bam32_t tc)
{
    const ego_scan_t *l = m->last;
    match_t best; /* field by field: an aggregate initialiser is a memset call at -Os */
    best.found = false;
    best.dist_sq = 0u;
    best.x = 0;
    best.y = 0;
    /* A lower bound of the distance from the scanner (no square root): a
     * smaller r only widens the cone, which stays safe. */
    const int64_t ax = (q->ox < 0) ? -q->ox : q->ox;
    const int64_t ay = (q->oy < 0) ? -q->oy : q->oy;
    const int64_t r_q = (ax > ay) ? ax : ay;
    const int64_t cone = cone_of(m->radius, r_q);
    const target_t t = {q->x, q->y, has_tc, tc, (uint64_t)((int64_t)m->radius * m->radius)};
    /* The box test first: it skips most points of the walk before any
     * product or division (consider accepts nothing outside the box of a
     * point and its successor, which holds the point and its segment). */
    const uint16_t end = (uint16_t)(l->count - 1u);
    const square_t sq = square_around(t.x, t.y, m->radius);
    /* The cone's bearing limits in int32 (bearings relative to ref are
     * int32; a limit past that range stops nothing). */
    const int32_t above = clamp_s32(q->rel + cone + q->slack);
    const int32_t below = clamp_s32(q->rel - cone - q->slack);
    uint32_t walked = 0u;
    for (uint16_t j = q->j0, k = 0u; j < l->count && k < EGO_ITCP_MAX_WALK; j++, k++) {
        walked++;
        if (fx_bam32_diff(l->bearing[j], m->ref) > above) {
            break;
        }
        if (!outside_square(l, j, (j < end) ? (uint16_t)(j + 1u) : j, &sq)) {
            consider(m, &t, j, &best);
        }
    }
    for (uint16_t j = q->j0, k = 0u; j > 0u && k < EGO_ITCP_MAX_WALK; k++) {
        j--;
        walked++;
        /* The segment j -> j + 1 lies wholly below the cone. With j0 past
         * the last point (the query's bearing beyond the scan), j is that
         * point and has no segment: its own bearing decides. */
        const uint16_t top = (j < end) ? (uint16_t)(j + 1u) : j;
        if (fx_bam32_diff(l->bearing[top], m->ref) < below) {
            break;
        }
        if (!outside_square(l, j, (j < end) ? (uint16_t)(j + 1u) : j, &sq)) {
            consider(m, &t, j, &best);
        }
    }
    *m->units += walked * EGO_COST_MATCH_STEP;
    return best;
}

/* The middle bearing of a scan: the reference its bearings are compared
 * to, so that they never wrap. */
static fx_bam32_t middle_bearing(const ego_scan_t *l)
{
    return l->bearing[0] + (l->bearing[l->count - 1u] - l->bearing[0]) / 2u;
}

/* Did the last scan see through q: do its beams on both sides of that
 * bearing, neighbours with no missing value between them, both reach more
 * than `margin` beyond it? A current point there lies in space the last
 * scan saw empty, so the pose that put it there is wrong (or the point
 * moved). */
static bool seen_through(const matcher_t *m, const query_t *q, fx_q16_16_t margin)
{
    const ego_scan_t *l = m->last;
    const uint16_t j = q->j0;
    if (j == 0u || j >= l->count || (l->flags[j - 1u] & EGO_LINK_GAP) != 0u) {
        return false;
    }
    /* r = |o| + margin with |o| rounded down; r^2 > |o|^2 for margin >= 1,
     * so a beam no longer than |o| settles it without the square root. */
    const uint64_t o_sq = (uint64_t)(q->ox * q->ox + q->oy * q->oy);
    const uint64_t before = range_sq(l, (uint16_t)(j - 1u));
    const uint64_t after = range_sq(l, j);
    if (margin >= 1 && (before <= o_sq || after <= o_sq)) {
        return false;
    }
    const int64_t r = (int64_t)fx_sqrt_u64(o_sq) + margin;
    const uint64_t r_sq = (uint64_t)(r * r);
    return before > r_sq && after > r_sq;
}

/* A matcher for single queries (no tangents, no groups) around ref. */
static void init_matcher(matcher_t *m, const ego_scan_t *last, fx_bam32_t ref,
                         fx_q16_16_t radius, uint32_t *units)
{
    /* Only the gate switch is read by the search: everything else zero. */
    static const itcp_params_t no_gate;
    m->last = last;
    m->params = &no_gate;
    m->ref = ref;
    m->main_direction = 0u;
    m->radius = radius;
    m->units = units;
}

bool ego_itcp_nearest(const ego_scan_t *last, fx_q16_16_t qx, fx_q16_16_t qy, fx_q16_16_t radius,
                  uint64_t *dist_sq)
{
    if (last == NULL || dist_sq == NULL || last->count == 0u) {
        return false;
    }
    matcher_t m;
    uint32_t units = 0u;
    init_matcher(&m, last, middle_bearing(last), radius, &units);
    query_t q;
    locate_exactly(&m, qx, qy, (uint16_t)(last->count / 2u), &q);
    const match_t best = find_match(&m, &q, false, 0u);
    *dist_sq = best.dist_sq;
    return best.found;
}

bool ego_itcp_seen_through(const ego_scan_t *last, fx_q16_16_t qx, fx_q16_16_t qy,
                       fx_q16_16_t margin)
{
    if (last == NULL || last->count == 0u) {
        return false;
    }
    matcher_t m;
    uint32_t units = 0u;
    init_matcher(&m, last, middle_bearing(last), 0, &units);
    query_t q;
    locate_exactly(&m, qx, qy, (uint16_t)(last->count / 2u), &q);
    return seen_through(&m, &q, margin);
}

void ego_itcp_prober_init(ego_itcp_prober_t *p, const ego_scan_t *last, fx_q16_16_t radius,
                      fx_q16_16_t margin)
{
    p->last = last;
    p->ref = (last != NULL && last->count > 0u) ? middle_bearing(last) : 0u;
    p->radius = radius;
    p->margin = margin;
    p->radius_sq = (uint64_t)((int64_t)radius * radius);
    p->hint = (last != NULL) ? (uint16_t)(last->count / 2u) : 0u;
    p->units = 0u;
}

uint32_t ego_itcp_prober_take_units(ego_itcp_prober_t *p)
{
    const uint32_t units = p->units;
    p->units = 0u;
    return units;
}

ego_itcp_probe_t ego_itcp_probe(ego_itcp_prober_t *p, fx_q16_16_t qx, fx_q16_16_t qy, uint64_t *dist_sq)
{
    if (p == NULL || dist_sq == NULL || p->last == NULL || p->last->count == 0u) {
        return EGO_ITCP_PROBE_NOTHING;
    }
    matcher_t m;
    init_matcher(&m, p->last, p->ref, p->radius, &p->units);
    query_t q;
    locate_exactly(&m, qx, qy, p->hint, &q);
    p->hint = q.j0;
    const match_t best = find_match(&m, &q, false, 0u);
    *dist_sq = best.dist_sq;
    if (best.found && best.dist_sq < p->radius_sq) {
        return EGO_ITCP_PROBE_SURFACE;
    }
    return seen_through(&m, &q, p->margin) ? EGO_ITCP_PROBE_SEEN_THROUGH : EGO_ITCP_PROBE_NOTHING;
}

uint16_t ego_itcp_sample_stride(uint16_t count, uint16_t max_points)
{
    if (max_points == 0u || count <= max_points) {
        return 1u;
    }
    return (uint16_t)(((uint32_t)count + max_points - 1u) / max_points);
}

void ego_itcp_sums_clear(ego_itcp_sums_t *sums)
{
    memset(sums, 0, sizeof *sums);
}

void ego_itcp_sums_add(ego_itcp_sums_t *sums, bool on_main, fx_q16_16_t x, fx_q16_16_t y, fx_q16_16_t u,
                   fx_q16_16_t v)
{
    sums_add(&sums->group[on_main ? 0 : 1], x, y, u, v);
}

static int64_t div_round(int64_t a, int64_t b)
{
    return (a >= 0) ? (a + b / 2) / b : -((-a + b / 2) / b);
}

/* Centred cross sum of one group divided by its size:
 * (1/n) sum (a - am)(b - bm) from raw sums. */
static int64_t centred(const ego_itcp_group_sums_t *g, int64_t sab, int64_t sa, int64_t sb, int64_t am,
                       int64_t bm)
{
    const int64_t total = sab - am * sb - bm * sa + g->n * am * bm;
    return div_round(total, g->n);
}

static void sums_merge(ego_itcp_group_sums_t *into, const ego_itcp_group_sums_t *from)
{
    into->n += from->n;
    into->sx += from->sx;
    into->sy += from->sy;
    into->su += from->su;
    into->sv += from->sv;
    into->sxu += from->sxu;
    into->sxv += from->sxv;
    into->syu += from->syu;
    into->syv += from->syv;
}

void ego_itcp_solve(const ego_itcp_sums_t *sums, bool weighted, bool hold_theta, ego_pose_t *pose)
{
    ego_itcp_group_sums_t all = sums->group[0];
    ego_itcp_group_sums_t none;
    memset(&none, 0, sizeof none);
    if (!weighted) {
        sums_merge(&all, &sums->group[1]);
    }
    const ego_itcp_group_sums_t *g[2] = {&all, weighted ? &sums->group[1] : &none};
    int64_t groups = 0;
    if (g[0]->n <= 0 && g[1]->n <= 0) {
        return; /* nothing to solve with: the pose stays */
    }
    int64_t xm = 0;
    int64_t ym = 0;
    int64_t um = 0;
    int64_t vm = 0;
    for (int k = 0; k < 2; k++) {
        if (g[k]->n > 0) {
            groups++;
            xm += div_round(g[k]->sx, g[k]->n);
            ym += div_round(g[k]->sy, g[k]->n);
            um += div_round(g[k]->su, g[k]->n);
            vm += div_round(g[k]->sv, g[k]->n);
        }
    }
    xm = div_round(xm, groups);
    ym = div_round(ym, groups);
    um = div_round(um, groups);
    vm = div_round(vm, groups);

    if (!hold_theta) {
        int64_t num = 0;
        int64_t den = 0;
        for (int k = 0; k < 2; k++) {
            if (g[k]->n <= 0) {
                continue;
            }
            const ego_itcp_group_sums_t *s = g[k];
            const int64_t xv = centred(s, s->sxv, s->sx, s->sv, xm, vm);
            const int64_t yu = centred(s, s->syu, s->sy, s->su, ym, um);
            const int64_t xu = centred(s, s->sxu, s->sx, s->su, xm, um);
            const int64_t yv = centred(s, s->syv, s->sy, s->sv, ym, vm);
            num += xv - yu;
            den += xu + yv;
        }
        pose->theta = fx_atan2(num, den);
    }
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(pose->theta, &s, &c);
    const fx_q16_16_t rx = fx_sub_q16(fx_mul_q16_q30((fx_q16_16_t)xm, c),
                                      fx_mul_q16_q30((fx_q16_16_t)ym, s));
    const fx_q16_16_t ry = fx_add_q16(fx_mul_q16_q30((fx_q16_16_t)xm, s),
                                      fx_mul_q16_q30((fx_q16_16_t)ym, c));
    pose->x = fx_sub_q16((fx_q16_16_t)um, rx);
    pose->y = fx_sub_q16((fx_q16_16_t)vm, ry);
}

static int64_t abs64(int64_t v)
{
    return (v < 0) ? -v : v;
}

/* A pose step as a 3-vector in metres (Q16.16): the rotation counts as
 * its arc at ACCEL_ARM_M, so that turning and moving compare. */
typedef ego_itcp_step_t step_t;

/* 2 pi * 8 m * 2^16: binary angle (2^32 a turn) -> arc at 8 m, Q16.16. */
#define ACCEL_ARC_PER_BAM 3294199
#define ACCEL_MAX_FACTOR 8

static step_t pose_step(const ego_pose_t *from, const ego_pose_t *to)
{
    step_t d;
    d.v[0] = (int64_t)to->x - from->x;
    d.v[1] = (int64_t)to->y - from->y;
    d.v[2] = ((int64_t)fx_bam32_diff(to->theta, from->theta) * ACCEL_ARC_PER_BAM) / 4294967296LL;
    return d;
}

static int64_t step_dot(const step_t *a, const step_t *b)
{
    return a->v[0] * b->v[0] + a->v[1] * b->v[1] + a->v[2] * b->v[2];
}

/* Point-to-point ICP creeps along surfaces with steps that shrink by a
 * nearly constant ratio r in a nearly constant direction. When two steps
 * agree in direction (cosine > 0.95) and shrink, jump ahead by the rest of
 * the geometric series, r / (1 - r) times the last step (at most
 * ACCEL_MAX_FACTOR), as Besl and McKay's accelerated ICP does. Returns
 * true when it jumped. */
static bool accelerate(ego_pose_t *pose, const step_t *last_step, const step_t *step,
                       fx_bam32_t dtheta)
{
    const int64_t n1 = fx_sqrt_u64((uint64_t)step_dot(last_step, last_step));
    const int64_t n2 = fx_sqrt_u64((uint64_t)step_dot(step, step));
    if (n1 == 0 || n2 == 0 || n2 >= n1) {
        return false;
    }
    /* cos > 0.95  <=>  20 dot > 19 |a| |b|. */
    if (20 * step_dot(last_step, step) <= 19 * n1 * n2) {
        return false;
    }
    /* factor = r / (1 - r) = n2 / (n1 - n2), Q16.16, capped. */
    int64_t factor = (n2 << 16) / (n1 - n2);
    factor = (factor > ((int64_t)ACCEL_MAX_FACTOR << 16)) ? ((int64_t)ACCEL_MAX_FACTOR << 16) : factor;
    pose->x = fx_sat_s32(pose->x + ((step->v[0] * factor) >> 16));
    pose->y = fx_sat_s32(pose->y + ((step->v[1] * factor) >> 16));
    pose->theta += (fx_bam32_t)(uint32_t)(int32_t)((fx_bam32_diff(dtheta, 0u) * factor) >> 16);
    return true;
}


/* The phases of a run (ego_itcp_run_t.phase). */
enum { PHASE_COARSE = 0, PHASE_FINE = 1, PHASE_STATS = 2, PHASE_DONE = 3 };

/* The most steps a run can take: passes (two runs of at most 255
 * iterations and the statistics pass) of at most one step per point and
 * the closing step. Bounds ego_itcp_run_step's loop. */
#define RUN_MAX_STEPS ((2u * 255u + 1u) * ((uint32_t)EGO_MAX_POINTS + 1u))

static void run_matcher(const ego_itcp_run_t *run, uint32_t *units, matcher_t *m)
{
    m->last = run->last;
    m->params = run->params;
    m->ref = run->ref;
    m->main_direction = run->main_direction;
    m->radius = run->radius;
    m->units = units;
}

/* A pass at run->pose with run->radius: the first run's every stride-th
 * point (max_points), every point in the fine run and the statistics pass. */
static void begin_pass(ego_itcp_run_t *run)
{
    memset(&run->pass, 0, sizeof run->pass);
    fx_sincos(run->pose.theta, &run->sin_theta, &run->cos_theta);
    run->hint = (uint16_t)(run->last->count / 2u);
    run->stride = (run->phase == PHASE_COARSE)
                      ? ego_itcp_sample_stride(run->current->count, run->params->max_points)
                      : 1u;
    run->next_point = (uint16_t)(run->stride / 2u);
}

/* Starts a run of iterations from run->pose, the radius shrinking from
 * radius_from (to radius_min in the first run; radius_fine stays), at most
 * max_iteration of them (0: none, the caller ends the run). */
static void begin_iterations(ego_itcp_run_t *run, uint8_t phase, fx_q16_16_t radius_from,
                             uint8_t max_iteration)
{
    run->phase = phase;
    run->radius = radius_from;
    run->iteration = 0u;
    run->max_iteration = max_iteration;
    memset(&run->last_step, 0, sizeof run->last_step);
    memset(&run->jump, 0, sizeof run->jump);
    run->have_last_step = false;
    /* After a jump, a step back means it overshot: no more jumps then, so
     * that jumping and creeping back cannot cycle. */
    run->may_accelerate = true;
    run->jumped = false;
    if (max_iteration > 0u) {
        begin_pass(run);
    }
}

static void begin_statistics(ego_itcp_run_t *run)
{
    /* Statistics at the final pose, with the smallest radius. */
    run->phase = PHASE_STATS;
    run->radius = run->params->radius_min;
    begin_pass(run);
}

static uint32_t pass_matches(const pass_t *pass)
{
    return (uint32_t)(pass->sums.group[0].n + pass->sums.group[1].n);
}

/* The end of a run of iterations: ok (no pass lacked matches), converged.
 * After the first run the fine run may follow, after that the statistics. */
static void end_iterations(ego_itcp_run_t *run, bool ok, bool converged)
{
    const itcp_params_t *params = run->params;
    if (run->phase == PHASE_COARSE) {
        run->status = (int8_t)(ok ? EGO_ITCP_OK : EGO_ITCP_ERR_FEW_MATCHES);
        run->converged = converged;
        const uint8_t fine_iterations =
            (params->fine_iterations != 0u) ? params->fine_iterations : params->max_iterations;
        if (ok && converged && params->radius_fine < params->radius_min && fine_iterations > 0u) {
            /* Converged among the nearby surfaces: now only the close
             * matches. Wrong partners within radius_min pull every pose
             * towards no motion (4-15 mm per scan on the 1-degree campus
             * drive); kept only if it converges too and keeps at least half
             * of the matches. */
            run->coarse_pose = run->pose;
            run->coarse_matches = pass_matches(&run->pass);
            begin_iterations(run, PHASE_FINE, params->radius_fine, fine_iterations);
            return;
        }
    } else if (!ok || !converged ||
               2u * pass_matches(&run->pass) < run->coarse_matches) {
        run->pose = run->coarse_pose; /* the fine run is not kept */
    }
    begin_statistics(run);
}

/* The closing step of an iteration's pass: the closed form from its sums,
 * convergence, acceleration, the next radius; then the next pass or the
 * end of the run. */
static void close_iteration(ego_itcp_run_t *run)
{
    const itcp_params_t *params = run->params;
    if (pass_matches(&run->pass) < params->min_matches) {
        end_iterations(run, false, false);
        return;
    }
    const fx_q16_16_t radius_floor =
        (run->phase == PHASE_COARSE) ? params->radius_min : params->radius_fine;
    ego_pose_t pose = run->pose;
    const ego_pose_t before = pose;
    ego_itcp_solve(&run->pass.sums, params->weighted, run->hold_rotation, &pose);
    run->iterations++;
    const bool at_min = run->radius <= radius_floor;
    const bool still =
        abs64((int64_t)pose.x - before.x) < params->converge_translation &&
        abs64((int64_t)pose.y - before.y) < params->converge_translation &&
        abs64(fx_bam32_diff(pose.theta, before.theta)) < (int64_t)params->converge_rotation;
    if (still && at_min) {
        run->pose = pose;
        end_iterations(run, true, true);
        return;
    }
    /* Accelerate only once the match set has settled (smallest radius). */
    const step_t step = pose_step(&before, &pose);
    if (run->jumped && step_dot(&step, &run->jump) < 0) {
        run->may_accelerate = false;
    }
    run->jumped = false;
    const ego_pose_t stepped = pose;
    if (run->may_accelerate && at_min && run->have_last_step &&
        accelerate(&pose, &run->last_step, &step, pose.theta - before.theta)) {
        run->jumped = true;
        run->jump = pose_step(&stepped, &pose);
        run->have_last_step = false;
    } else {
        run->last_step = step;
        run->have_last_step = at_min;
    }
    run->pose = pose;
    const fx_q16_16_t shrunk = fx_mul_q16_q30(run->radius, params->radius_shrink);
    run->radius = (shrunk > radius_floor) ? shrunk : radius_floor;
    run->iteration++;
    if (run->iteration >= run->max_iteration) {
        end_iterations(run, true, false);
        return;
    }
    begin_pass(run);
}

/* The step of the pass: its next point located, matched and summed.
 * Returns its work (ego_work.h units). */
static uint32_t match_next_point(ego_itcp_run_t *run)
{
    uint32_t units = 0u;
    matcher_t m;
    run_matcher(run, &units, &m);
    const ego_scan_t *cur = run->current;
    const itcp_params_t *params = run->params;
    const uint16_t i = run->next_point;
    pass_t *pass = &run->pass;
    const uint64_t inlier_sq = (uint64_t)((int64_t)params->inlier_distance * params->inlier_distance);
    fx_q16_16_t qx;
    fx_q16_16_t qy;
    ego_pose_apply(&run->pose, run->sin_theta, run->cos_theta, cur->x[i], cur->y[i], &qx, &qy);
    const bool has_tc = (cur->flags[i] & EGO_POINT_HAS_TANGENT) != 0u;
    const fx_bam32_t tc = (cur->tangent[i] + run->pose.theta) & (FX_BAM32_HALF - 1u);
    const bool on_main =
        has_tc && fx_line_angle_diff(tc, run->main_direction) <= params->main_tolerance;
    const unsigned g = on_main ? 0u : 1u;
    pass->group_points[g]++;
    query_t q;
    /* The iterations' passes need the walk only; the statistics pass's
     * free-space test needs the exact place. */
    if (run->phase == PHASE_STATS) {
        locate_exactly(&m, qx, qy, run->hint, &q);
    } else {
        locate(&m, qx, qy, run->hint, &q);
    }
    run->hint = q.j0;
    /* The statistics also count the points the last scan saw through. */
    if (run->phase == PHASE_STATS && seen_through(&m, &q, 2 * params->inlier_distance)) {
        pass->group_seen_through[g]++;
    }
    const match_t best = find_match(&m, &q, has_tc, tc);
    if (best.found) {
        ego_itcp_sums_add(&pass->sums, on_main, cur->x[i], cur->y[i], best.x, best.y);
        pass->sum_sq += best.dist_sq;
        if (best.dist_sq <= inlier_sq) {
            pass->inliers++;
            pass->group_fit[g] += inlier_sq - best.dist_sq;
        }
    }
    const uint32_t next = (uint32_t)i + run->stride;
    run->next_point = (uint16_t)((next < cur->count) ? next : cur->count);
    return units;
}

void ego_itcp_run_start(ego_itcp_run_t *run, const ego_scan_t *last, const ego_scan_t *current,
                        fx_bam32_t main_direction, const ego_pose_t *initial, bool hold_rotation,
                        const itcp_params_t *params)
{
    if (run == NULL) {
        return;
    }
    memset(run, 0, sizeof *run);
    run->phase = PHASE_DONE;
    run->status = (int8_t)EGO_ITCP_ERR_ARG;
    if (last == NULL || current == NULL || initial == NULL || params == NULL) {
        return;
    }
    run->pose = *initial;
    run->status = (int8_t)EGO_ITCP_ERR_FEW_MATCHES;
    if (last->count < 2u || current->count == 0u) {
        return;
    }
    run->last = last;
    run->current = current;
    run->params = params;
    run->ref = middle_bearing(last);
    run->main_direction = main_direction & (FX_BAM32_HALF - 1u);
    run->hold_rotation = hold_rotation;
    run->status = (int8_t)EGO_ITCP_OK;
    begin_iterations(run, PHASE_COARSE, params->radius_start, params->max_iterations);
    if (params->max_iterations == 0u) {
        end_iterations(run, true, false);
    }
}

bool ego_itcp_run_step(ego_itcp_run_t *run, ego_work_t *work)
{
    if (run == NULL || work == NULL) {
        return true;
    }
    for (uint32_t k = 0u; k < RUN_MAX_STEPS && run->phase != PHASE_DONE; k++) {
        if (run->next_point < run->current->count) {
            if (!ego_work_allows(work, EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK))) {
                return false;
            }
            ego_work_spend(work, match_next_point(run));
        } else {
            if (!ego_work_allows(work, EGO_COST_SOLVE)) {
                return false;
            }
            if (run->phase == PHASE_STATS) {
                run->phase = PHASE_DONE; /* ego_itcp_run_result does the arithmetic */
            } else {
                close_iteration(run);
            }
            ego_work_spend(work, EGO_COST_SOLVE);
        }
    }
    return run->phase == PHASE_DONE;
}

ego_itcp_status_t ego_itcp_run_result(const ego_itcp_run_t *run, ego_itcp_result_t *result)
{
    if (result != NULL) {
        memset(result, 0, sizeof *result);
        ego_cov_unknown(&result->cov); /* ITCP's statistics give none */
    }
    if (run == NULL || result == NULL) {
        return EGO_ITCP_ERR_ARG;
    }
    if (run->phase != PHASE_DONE) {
        return EGO_ITCP_ERR_UNFINISHED;
    }
    ego_itcp_status_t status = (ego_itcp_status_t)run->status;
    result->pose = run->pose;
    if (run->params == NULL) {
        return status; /* finished at the start: bad arguments, too few points */
    }
    const itcp_params_t *params = run->params;
    const pass_t *pass = &run->pass;
    result->iterations = (uint8_t)((run->iterations > 255u) ? 255u : run->iterations);
    result->converged = run->converged;
    const uint32_t matches = pass_matches(pass);
    result->matches = (uint16_t)matches;
    result->n_main = (uint16_t)pass->sums.group[0].n;
    result->n_non_main = (uint16_t)pass->sums.group[1].n;
    result->inliers = (uint16_t)pass->inliers;
    const uint64_t inlier_sq =
        (uint64_t)((int64_t)params->inlier_distance * params->inlier_distance);
    for (uint8_t g = 0u; g < 2u; g++) {
        result->group_points[g] = (uint16_t)pass->group_points[g];
        /* fit / (points * inlier_sq) in Q2.30; fit <= points * inlier_sq
         * < 2^16 * 2^34 (inlier_distance < 2 m). */
        /* A point in space the last scan saw empty costs what a perfect
         * inlier gains. */
        const uint64_t full = (uint64_t)pass->group_points[g] * inlier_sq;
        const uint64_t penalty = (uint64_t)pass->group_seen_through[g] * inlier_sq;
        const uint64_t fit = (pass->group_fit[g] > penalty) ? pass->group_fit[g] - penalty : 0u;
        result->group_fit[g] =
            (full == 0u) ? 0 : (fx_q2_30_t)((fit >> 4) * (1ull << 30) / (full >> 4));
    }
    if (matches > 0u) {
        result->residual = (fx_q16_16_t)fx_sqrt_u64(pass->sum_sq / (uint64_t)matches);
    }
    /* Aperture: n_non / n_main < ratio, i.e. n_non < ratio * n_main. */
    result->aperture = pass->sums.group[0].n > 0 &&
                       ((int64_t)pass->sums.group[1].n << 30) <
                           (int64_t)params->aperture_ratio * pass->sums.group[0].n;
    if (status == EGO_ITCP_OK && matches < params->min_matches) {
        status = EGO_ITCP_ERR_FEW_MATCHES;
    }
    return status;
}

ego_itcp_status_t ego_itcp_register(const ego_scan_t *last, const ego_scan_t *current,
                            fx_bam32_t main_direction, const ego_pose_t *initial,
                            bool hold_rotation, const itcp_params_t *params,
                            ego_itcp_result_t *result)
{
    if (result == NULL) {
        return EGO_ITCP_ERR_ARG;
    }
    ego_itcp_run_t run;
    ego_itcp_run_start(&run, last, current, main_direction, initial, hold_rotation, params);
    ego_work_t unlimited;
    ego_work_start(&unlimited, EGO_WORK_UNLIMITED);
    (void)ego_itcp_run_step(&run, &unlimited);
    return ego_itcp_run_result(&run, result);
}
