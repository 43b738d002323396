/* world_map.c - see world_map.h. */
#include "world_map.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define WMAP_MIN_T 1e-9      /* hits closer than this are the ray's own origin */
#define WMAP_BEHIND_SLACK 1e-6 /* metres behind the scanner line still kept */

static void *grow(void *data, size_t *cap, size_t need, size_t item)
{
    if (need <= *cap) {
        return data;
    }
    size_t n = (*cap != 0u) ? *cap : 64u;
    while (n < need) {
        n *= 2u;
    }
    void *grown = realloc(data, n * item);
    if (grown == NULL) {
        (void)fputs("lmsworld: out of memory\n", stderr);
        exit(1);
    }
    *cap = n;
    return grown;
}

void wmap_init(wmap_t *map)
{
    map->segs = NULL;
    map->seg_count = 0u;
    map->seg_cap = 0u;
    map->circles = NULL;
    map->circle_count = 0u;
    map->circle_cap = 0u;
}

void wmap_free(wmap_t *map)
{
    free(map->segs);
    free(map->circles);
    wmap_init(map);
}

void wmap_clear(wmap_t *map)
{
    map->seg_count = 0u;
    map->circle_count = 0u;
}

void wmap_add_segment(wmap_t *map, double ax, double ay, double bx, double by)
{
    map->segs = grow(map->segs, &map->seg_cap, map->seg_count + 1u, sizeof *map->segs);
    wseg_t *s = &map->segs[map->seg_count++];
    s->ax = ax;
    s->ay = ay;
    s->bx = bx;
    s->by = by;
}

void wmap_add_circle(wmap_t *map, double cx, double cy, double r)
{
    map->circles =
        grow(map->circles, &map->circle_cap, map->circle_count + 1u, sizeof *map->circles);
    wcircle_t *c = &map->circles[map->circle_count++];
    c->cx = cx;
    c->cy = cy;
    c->r = r;
}

void wmap_add_polyline(wmap_t *map, const double *xy, size_t n, int closed)
{
    for (size_t i = 0u; i + 1u < n; i++) {
        wmap_add_segment(map, xy[2u * i], xy[2u * i + 1u], xy[2u * i + 2u], xy[2u * i + 3u]);
    }
    if (closed && n > 2u) {
        wmap_add_segment(map, xy[2u * n - 2u], xy[2u * n - 1u], xy[0], xy[1]);
    }
}

void wmap_add_rect(wmap_t *map, double x0, double y0, double x1, double y1)
{
    const double xy[8] = {x0, y0, x1, y0, x1, y1, x0, y1};
    wmap_add_polyline(map, xy, 4u, 1);
}

void wmap_add_box(wmap_t *map, double cx, double cy, double heading, double length,
                  double width)
{
    const double c = cos(heading);
    const double s = sin(heading);
    const double hl = 0.5 * length;
    const double hw = 0.5 * width;
    /* Corners in the box frame: front left, rear left, rear right, front right. */
    const double local[8] = {hl, hw, -hl, hw, -hl, -hw, hl, -hw};
    double xy[8];
    for (size_t i = 0u; i < 4u; i++) {
        const double u = local[2u * i];
        const double v = local[2u * i + 1u];
        xy[2u * i] = cx + c * u - s * v;
        xy[2u * i + 1u] = cy + s * u + c * v;
    }
    wmap_add_polyline(map, xy, 4u, 1);
}

/* p + t d = a + u (b - a): t = cross(a - p, e) / cross(d, e),
 * u = cross(a - p, d) / cross(d, e), e = b - a. */
static double segment_hit(const wseg_t *s, double x, double y, double dx, double dy)
{
    const double ex = s->bx - s->ax;
    const double ey = s->by - s->ay;
    const double den = dx * ey - dy * ex;
    if (fabs(den) <= 1e-15 * (fabs(ex) + fabs(ey))) {
        return INFINITY; /* parallel: a grazing ray sees no surface */
    }
    const double wx = s->ax - x;
    const double wy = s->ay - y;
    const double t = (wx * ey - wy * ex) / den;
    const double u = (wx * dy - wy * dx) / den;
    if (t <= WMAP_MIN_T || u < 0.0 || u > 1.0) {
        return INFINITY;
    }
    return t;
}

/* |p + t d - c|^2 = r^2 with |d| = 1: t^2 + 2 b t + q = 0. From inside the
 * circle the ray meets its far side. */
static double circle_hit(const wcircle_t *c, double x, double y, double dx, double dy)
{
    const double ox = x - c->cx;
    const double oy = y - c->cy;
    const double b = ox * dx + oy * dy;
    const double q = ox * ox + oy * oy - c->r * c->r;
    const double disc = b * b - q;
    if (disc < 0.0) {
        return INFINITY;
    }
    const double root = sqrt(disc);
    const double near = -b - root;
    if (near > WMAP_MIN_T) {
        return near;
    }
    const double far = -b + root;
    return (far > WMAP_MIN_T) ? far : INFINITY;
}

double wmap_cast(const wmap_t *map, double x, double y, double dx, double dy)
{
    double best = INFINITY;
    for (size_t i = 0u; i < map->seg_count; i++) {
        const double t = segment_hit(&map->segs[i], x, y, dx, dy);
        if (t < best) {
            best = t;
        }
    }
    for (size_t i = 0u; i < map->circle_count; i++) {
        const double t = circle_hit(&map->circles[i], x, y, dx, dy);
        if (t < best) {
            best = t;
        }
    }
    return best;
}

static double segment_distance(const wseg_t *s, double x, double y)
{
    const double ex = s->bx - s->ax;
    const double ey = s->by - s->ay;
    const double len2 = ex * ex + ey * ey;
    double u = 0.0;
    if (len2 > 0.0) {
        u = ((x - s->ax) * ex + (y - s->ay) * ey) / len2;
        u = fmin(1.0, fmax(0.0, u));
    }
    return hypot(x - (s->ax + u * ex), y - (s->ay + u * ey));
}

double wmap_clearance(const wmap_t *map, double x, double y)
{
    double best = INFINITY;
    for (size_t i = 0u; i < map->seg_count; i++) {
        best = fmin(best, segment_distance(&map->segs[i], x, y));
    }
    for (size_t i = 0u; i < map->circle_count; i++) {
        const wcircle_t *c = &map->circles[i];
        best = fmin(best, fabs(hypot(x - c->cx, y - c->cy) - c->r));
    }
    return best;
}

void wmap_select(const wmap_t *src, double x, double y, double fx, double fy, double radius,
                 wmap_t *dst)
{
    for (size_t i = 0u; i < src->seg_count; i++) {
        const wseg_t *s = &src->segs[i];
        const double ahead_a = (s->ax - x) * fx + (s->ay - y) * fy;
        const double ahead_b = (s->bx - x) * fx + (s->by - y) * fy;
        if (ahead_a < -WMAP_BEHIND_SLACK && ahead_b < -WMAP_BEHIND_SLACK) {
            continue;
        }
        if (segment_distance(s, x, y) > radius) {
            continue;
        }
        wmap_add_segment(dst, s->ax, s->ay, s->bx, s->by);
    }
    for (size_t i = 0u; i < src->circle_count; i++) {
        const wcircle_t *c = &src->circles[i];
        const double ahead = (c->cx - x) * fx + (c->cy - y) * fy;
        if (ahead + c->r < -WMAP_BEHIND_SLACK) {
            continue;
        }
        if (hypot(x - c->cx, y - c->cy) - c->r > radius) {
            continue;
        }
        wmap_add_circle(dst, c->cx, c->cy, c->r);
    }
}
