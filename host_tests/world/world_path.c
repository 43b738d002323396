/* world_path.c - see world_path.h. */
#include "world_path.h"

#include <math.h>

/* The pose after driving s metres along one piece from start. */
static wpose_t advance(wpose_t start, const wpiece_t *piece, double s)
{
    wpose_t p;
    const double k = piece->curvature;
    if (k == 0.0) {
        p.x = start.x + s * cos(start.theta);
        p.y = start.y + s * sin(start.theta);
        p.theta = start.theta;
        return p;
    }
    const double theta = start.theta + k * s;
    p.x = start.x + (sin(theta) - sin(start.theta)) / k;
    p.y = start.y - (cos(theta) - cos(start.theta)) / k;
    p.theta = world_wrap(theta);
    return p;
}

void wpath_init(wpath_t *path, wpose_t start, const wpiece_t *pieces, size_t count, bool loop)
{
    if (count > WPATH_MAX_PIECES) {
        count = WPATH_MAX_PIECES;
    }
    path->count = count;
    path->loop = loop;
    wpose_t at = start;
    double s = 0.0;
    for (size_t i = 0u; i < count; i++) {
        path->pieces[i] = pieces[i];
        path->starts[i] = at;
        path->offsets[i] = s;
        at = advance(at, &pieces[i], pieces[i].length);
        s += pieces[i].length;
    }
    path->total = s;
}

wpose_t wpath_pose(const wpath_t *path, double s, double lateral)
{
    wpose_t p;
    if (path->count == 0u) {
        p.x = 0.0;
        p.y = 0.0;
        p.theta = 0.0;
        return p;
    }
    if (path->loop) {
        s = fmod(s, path->total);
        if (s < 0.0) {
            s += path->total;
        }
    }
    size_t i = 0u;
    while (i + 1u < path->count && s >= path->offsets[i + 1u]) {
        i++;
    }
    double along = s - path->offsets[i];
    if (along < 0.0 || along > path->pieces[i].length) {
        /* Before the start or after the end of an open path: go straight. */
        const bool after = along > 0.0;
        const wpose_t end = after ? advance(path->starts[i], &path->pieces[i],
                                            path->pieces[i].length)
                                  : path->starts[i];
        const double extra = after ? along - path->pieces[i].length : along;
        const wpiece_t straight = {1.0, 0.0};
        p = advance(end, &straight, extra);
    } else {
        p = advance(path->starts[i], &path->pieces[i], along);
    }
    p.x -= lateral * sin(p.theta);
    p.y += lateral * cos(p.theta);
    return p;
}

double wprofile_speed(const wknot_t *knots, size_t count, double t)
{
    if (count == 0u) {
        return 0.0;
    }
    if (t <= knots[0].t) {
        return knots[0].v;
    }
    for (size_t i = 0u; i + 1u < count; i++) {
        if (t <= knots[i + 1u].t) {
            const double u = (t - knots[i].t) / (knots[i + 1u].t - knots[i].t);
            return knots[i].v + (knots[i + 1u].v - knots[i].v) * 0.5 * (1.0 - cos(WORLD_PI * u));
        }
    }
    return knots[count - 1u].v;
}

double wprofile_distance(const wknot_t *knots, size_t count, double t)
{
    if (count == 0u) {
        return 0.0;
    }
    if (t <= knots[0].t) {
        return knots[0].v * t;
    }
    double s = knots[0].v * knots[0].t;
    for (size_t i = 0u; i + 1u < count; i++) {
        const double t0 = knots[i].t;
        const double span = knots[i + 1u].t - t0;
        const double v0 = knots[i].v;
        const double dv = knots[i + 1u].v - v0;
        /* v(tau) = v0 + dv (1 - cos(pi tau / span)) / 2, integrated. */
        const double tau = fmin(t, knots[i + 1u].t) - t0;
        s += v0 * tau + 0.5 * dv * (tau - span / WORLD_PI * sin(WORLD_PI * tau / span));
        if (t <= knots[i + 1u].t) {
            return s;
        }
    }
    return s + knots[count - 1u].v * (t - knots[count - 1u].t);
}
