/* moving_ref.c - double-precision oracle of ego_moving's geometry
 * (moving_ref.h). Straight from the definitions in estimator/ego_moving.h:
 * no fixed point, no shortcuts. */
#include "moving_ref.h"

#include <math.h>

#include "ego_moving.h"
#include "fx_host.h"

/* The constants of ego_moving.h in metres. */
#define REF_MAX_RANGE_M ((double)EGO_MOVING_MAX_RANGE / 65536.0)
#define REF_GAP_M ((double)EGO_MOVING_GAP / 65536.0)

double moving_ref_cast(const moving_ref_wall_t *walls, size_t n, double ox, double oy,
                       double dir_rad, double max_m)
{
    const double dx = cos(dir_rad);
    const double dy = sin(dir_rad);
    double best = max_m;
    bool hit = false;
    for (size_t i = 0u; i < n; i++) {
        /* o + t d = a + s e: t = (a - o) x e / (d x e), s = (a - o) x d / (d x e). */
        const double ex = walls[i].x1 - walls[i].x0;
        const double ey = walls[i].y1 - walls[i].y0;
        const double den = dx * ey - dy * ex;
        if (fabs(den) < 1e-12) {
            continue; /* parallel: never hit (a box's other sides are) */
        }
        const double ax = walls[i].x0 - ox;
        const double ay = walls[i].y0 - oy;
        const double t = (ax * ey - ay * ex) / den;
        const double s = (ax * dy - ay * dx) / den;
        if (s >= 0.0 && s <= 1.0 && t > 0.0 && t <= best) {
            best = t;
            hit = true;
        }
    }
    return hit ? best : 0.0;
}

void moving_ref_box_walls(double cx, double cy, double heading_rad, double length, double width,
                          moving_ref_wall_t out[4])
{
    const double c = cos(heading_rad);
    const double s = sin(heading_rad);
    const double hl = length / 2.0;
    const double hw = width / 2.0;
    const double lx[4] = {hl, -hl, -hl, hl};
    const double ly[4] = {hw, hw, -hw, -hw};
    double px[4];
    double py[4];
    for (unsigned i = 0u; i < 4u; i++) {
        px[i] = cx + c * lx[i] - s * ly[i];
        py[i] = cy + s * lx[i] + c * ly[i];
    }
    for (unsigned i = 0u; i < 4u; i++) {
        const unsigned j = (i + 1u) % 4u;
        out[i] = (moving_ref_wall_t){px[i], py[i], px[j], py[j]};
    }
}

static double range_m(const ego_range_scan_t *scan, uint16_t k)
{
    return (double)scan->range[k] * (double)scan->range_unit_um * 1e-6;
}

void moving_ref_point(const ego_range_scan_t *scan, uint16_t k, double *x, double *y)
{
    const double r = range_m(scan, k);
    const double b = fx_bam32_to_rad(ego_range_bearing(scan, k));
    *x = fx_q16_16_to_double(scan->origin_x) + r * cos(b);
    *y = fx_q16_16_to_double(scan->origin_y) + r * sin(b);
}

static bool usable(const ego_range_scan_t *scan, uint16_t k)
{
    return scan->range[k] != 0u && range_m(scan, k) <= REF_MAX_RANGE_M;
}

size_t moving_ref_segments(const ego_range_scan_t *scan, uint16_t *from, uint16_t *to, size_t cap)
{
    size_t n = 0u;
    uint16_t k = 0u;
    while (k < scan->count && n < cap) {
        if (!usable(scan, k)) {
            k++;
            continue;
        }
        const uint16_t start = k;
        k++;
        while (k < scan->count && usable(scan, k) &&
               fabs(range_m(scan, k) - range_m(scan, (uint16_t)(k - 1u))) <= REF_GAP_M) {
            k++;
        }
        from[n] = start;
        to[n] = k;
        n++;
    }
    return n;
}

void moving_ref_chord_box(const ego_range_scan_t *scan, uint16_t from, uint16_t to,
                          moving_ref_box_t *box)
{
    double fx;
    double fy;
    double lx;
    double ly;
    moving_ref_point(scan, from, &fx, &fy);
    moving_ref_point(scan, (uint16_t)(to - 1u), &lx, &ly);
    const double len = hypot(lx - fx, ly - fy);
    const double ux = (len > 0.0) ? (lx - fx) / len : 1.0;
    const double uy = (len > 0.0) ? (ly - fy) / len : 0.0;
    double amin = INFINITY;
    double amax = -INFINITY;
    double wmin = INFINITY;
    double wmax = -INFINITY;
    for (uint16_t k = from; k < to; k++) {
        double px;
        double py;
        moving_ref_point(scan, k, &px, &py);
        const double a = (px - fx) * ux + (py - fy) * uy; /* along the chord */
        const double w = (py - fy) * ux - (px - fx) * uy; /* to its left */
        amin = fmin(amin, a);
        amax = fmax(amax, a);
        wmin = fmin(wmin, w);
        wmax = fmax(wmax, w);
    }
    const double am = (amin + amax) / 2.0;
    const double wm = (wmin + wmax) / 2.0;
    box->cx = fx + am * ux - wm * uy;
    box->cy = fy + am * uy + wm * ux;
    box->length = amax - amin;
    box->width = wmax - wmin;
}

/* Is the segment's end beam `end` the body's own edge, its neighbour
 * outside being `outside` (ranges compared in the scan's units: the same
 * order as in metres)? */
static bool end_uncut(const ego_range_scan_t *scan, uint16_t end, int32_t outside)
{
    if (outside < 0 || outside >= (int32_t)scan->count) {
        return false;
    }
    return scan->range[outside] == 0u || scan->range[outside] > scan->range[end];
}

void moving_ref_marks(const ego_range_scan_t *scan, uint16_t from, uint16_t to,
                      moving_ref_marks_t *marks)
{
    moving_ref_box_t box;
    moving_ref_chord_box(scan, from, to, &box);
    marks->x[0] = box.cx;
    marks->y[0] = box.cy;
    moving_ref_point(scan, from, &marks->x[1], &marks->y[1]);
    moving_ref_point(scan, (uint16_t)(to - 1u), &marks->x[2], &marks->y[2]);
    marks->uncut[0] = true;
    marks->uncut[1] = end_uncut(scan, from, (int32_t)from - 1);
    marks->uncut[2] = end_uncut(scan, (uint16_t)(to - 1u), (int32_t)to);
}

void moving_ref_velocity_start(moving_ref_velocity_t *v, const moving_ref_marks_t *marks)
{
    v->anchor = *marks;
    v->age_us = 0u;
    v->known = false;
    v->from_ends = false;
    v->vx = 0.0;
    v->vy = 0.0;
}

void moving_ref_velocity_age(moving_ref_velocity_t *v, uint32_t dt_us)
{
    v->age_us += dt_us;
}

void moving_ref_velocity_seen(moving_ref_velocity_t *v, const moving_ref_marks_t *marks)
{
    if (v->age_us < EGO_MOVING_VEL_MIN_US) {
        return;
    }
    const double age_s = (double)v->age_us * 1e-6;
    double sx = 0.0;
    double sy = 0.0;
    unsigned n = 0u;
    for (unsigned i = 1u; i < 3u; i++) {
        if (v->anchor.uncut[i] && marks->uncut[i]) {
            sx += (marks->x[i] - v->anchor.x[i]) / age_s;
            sy += (marks->y[i] - v->anchor.y[i]) / age_s;
            n++;
        }
    }
    v->from_ends = n > 0u;
    const double mx = (n > 0u) ? sx / n : (marks->x[0] - v->anchor.x[0]) / age_s;
    const double my = (n > 0u) ? sy / n : (marks->y[0] - v->anchor.y[0]) / age_s;
    if (v->known) {
        v->vx += (mx - v->vx) / 4.0;
        v->vy += (my - v->vy) / 4.0;
    } else {
        v->vx = mx;
        v->vy = my;
        v->known = true;
    }
    if (v->age_us >= EGO_MOVING_VEL_WINDOW_US) {
        v->anchor = *marks;
        v->age_us = 0u;
    }
}
