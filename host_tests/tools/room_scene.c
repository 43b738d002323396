/* room_scene.c - see room_scene.h. Plain ray casting: the inside of the
 * room's rectangle, then every box (slab test) and every pillar (circle),
 * keeping the nearest hit. */
#include "room_scene.h"

#include <math.h>
#include <stddef.h>

#define ROOM_PI 3.14159265358979323846

typedef struct {
    double x0, y0, x1, y1; /* axis-aligned box, m */
} room_box_t;

typedef struct {
    double cx, cy, r; /* round pillar, m */
} room_pillar_t;

static const room_box_t room_boxes[] = {
    {7.4, 3.6, 8.2, 4.3},   /* crate inside the loop */
    {10.4, 0.2, 11.6, 1.0}, /* cabinet against the bottom wall */
    {0.3, 6.8, 2.0, 7.7},   /* table in the top-left corner */
};

static const room_pillar_t room_pillars[] = {
    {4.2, 4.0, 0.25}, /* inside the loop */
    {9.9, 6.6, 0.20}, /* outside the loop, near the top-right */
};

/* Loop: centre, semi-axes. Nearest furniture stays > 1.4 m from it. */
#define LOOP_CX 6.0
#define LOOP_CY 4.0
#define LOOP_A 3.5
#define LOOP_B 2.0

room_pose_t room_scanner_pose(unsigned k)
{
    const double phi =
        2.0 * ROOM_PI * (double)(k % ROOM_SCANS_PER_LOOP) / (double)ROOM_SCANS_PER_LOOP -
        0.5 * ROOM_PI;
    room_pose_t pose;
    pose.x = LOOP_CX + LOOP_A * cos(phi);
    pose.y = LOOP_CY + LOOP_B * sin(phi);
    /* Tangent of the ellipse: d/dphi (a cos, b sin) = (-a sin, b cos). */
    pose.heading = atan2(LOOP_B * cos(phi), -LOOP_A * sin(phi));
    return pose;
}

/* Nearest positive t where x + t dx crosses the room's boundary in one
 * axis; the scanner is inside, so exactly one wall per axis is ahead. */
static double wall_distance(double p, double d, double limit)
{
    if (d > 1e-12) {
        return (limit - p) / d;
    }
    if (d < -1e-12) {
        return -p / d;
    }
    return INFINITY;
}

static double box_distance(const room_box_t *b, double x, double y, double dx, double dy)
{
    double t_near = -INFINITY;
    double t_far = INFINITY;
    const double lo[2] = {b->x0, b->y0};
    const double hi[2] = {b->x1, b->y1};
    const double p[2] = {x, y};
    const double d[2] = {dx, dy};
    for (size_t axis = 0u; axis < 2u; axis++) {
        if (fabs(d[axis]) < 1e-12) {
            if (p[axis] < lo[axis] || p[axis] > hi[axis]) {
                return INFINITY;
            }
            continue;
        }
        double t0 = (lo[axis] - p[axis]) / d[axis];
        double t1 = (hi[axis] - p[axis]) / d[axis];
        if (t0 > t1) {
            const double swap = t0;
            t0 = t1;
            t1 = swap;
        }
        t_near = fmax(t_near, t0);
        t_far = fmin(t_far, t1);
    }
    if (t_near > t_far || t_near <= 0.0) {
        return INFINITY;
    }
    return t_near;
}

static double pillar_distance(const room_pillar_t *c, double x, double y, double dx, double dy)
{
    /* |p + t d - c|^2 = r^2 with |d| = 1: t^2 + 2 b t + q = 0. */
    const double ox = x - c->cx;
    const double oy = y - c->cy;
    const double b = ox * dx + oy * dy;
    const double q = ox * ox + oy * oy - c->r * c->r;
    const double disc = b * b - q;
    if (disc < 0.0) {
        return INFINITY;
    }
    const double t = -b - sqrt(disc);
    return (t > 0.0) ? t : INFINITY;
}

double room_cast_ray(double x, double y, double angle)
{
    const double dx = cos(angle);
    const double dy = sin(angle);
    double best = fmin(wall_distance(x, dx, ROOM_WIDTH_M), wall_distance(y, dy, ROOM_DEPTH_M));
    for (size_t i = 0u; i < sizeof room_boxes / sizeof room_boxes[0]; i++) {
        best = fmin(best, box_distance(&room_boxes[i], x, y, dx, dy));
    }
    for (size_t i = 0u; i < sizeof room_pillars / sizeof room_pillars[0]; i++) {
        best = fmin(best, pillar_distance(&room_pillars[i], x, y, dx, dy));
    }
    return best;
}
