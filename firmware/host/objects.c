/* objects.c - see objects.h. */
#include "objects.h"

#include <math.h>
#include <string.h>

/* A reference point this much or more in front of a current point on the
 * same bearing, and gone now, is what a receding body left behind. */
#define RECEDE_MIN_M 0.15
/* Neighbouring beams whose points are further apart than this (plus
 * three beam spacings at their range) are a depth jump, not a surface. */
#define SURFACE_GAP_M 0.3

void obj_init(obj_tracker_t *t)
{
    memset(t, 0, sizeof *t);
}

/* Vehicle frame of f -> world frame. */
static void to_world(const obj_frame_t *f, double x, double y, double *wx, double *wy)
{
    const double c = cos(f->pose[2]);
    const double s = sin(f->pose[2]);
    *wx = f->pose[0] + c * x - s * y;
    *wy = f->pose[1] + s * x + c * y;
}

/* World frame -> vehicle frame of f. */
static void to_vehicle(const obj_frame_t *f, double wx, double wy, double *x, double *y)
{
    const double c = cos(f->pose[2]);
    const double s = sin(f->pose[2]);
    const double dx = wx - f->pose[0];
    const double dy = wy - f->pose[1];
    *x = c * dx + s * dy;
    *y = -s * dx + c * dy;
}

/* Beam k of f in its vehicle frame (range > 0). */
static void beam_point(const obj_frame_t *f, uint32_t k, double *x, double *y)
{
    const double b = f->first_bearing + (double)k * f->bearing_step;
    *x = f->origin_x + f->range[k] * cos(b);
    *y = f->origin_y + f->range[k] * sin(b);
}

/* A point of f's vehicle frame as f's sensor sees it: its range and its
 * fractional beam index (may lie outside 0 .. count - 1: not seen). */
static void polar_of_vehicle(const obj_frame_t *f, double x, double y, double *range,
                             double *index)
{
    x -= f->origin_x;
    y -= f->origin_y;
    *range = hypot(x, y);
    *index = (atan2(y, x) - f->first_bearing) / f->bearing_step;
}

/* The same of a world point. */
static void polar(const obj_frame_t *f, double wx, double wy, double *range, double *index)
{
    double x;
    double y;
    to_vehicle(f, wx, wy, &x, &y);
    polar_of_vehicle(f, x, y, range, index);
}

static double segment_distance(double px, double py, double ax, double ay, double bx, double by)
{
    const double ux = bx - ax;
    const double uy = by - ay;
    const double len2 = ux * ux + uy * uy;
    double s = (len2 > 0.0) ? ((px - ax) * ux + (py - ay) * uy) / len2 : 0.0;
    s = (s < 0.0) ? 0.0 : ((s > 1.0) ? 1.0 : s);
    return hypot(px - (ax + s * ux), py - (ay + s * uy));
}

/* True when a surface of f (a point, or the segment between neighbouring
 * points that is not a depth jump) lies within OBJ_NEAR_M of the world
 * point. */
static bool near_surface(const obj_frame_t *f, double wx, double wy)
{
    double x;
    double y;
    to_vehicle(f, wx, wy, &x, &y);
    double range;
    double index;
    polar_of_vehicle(f, x, y, &range, &index);
    const long centre = lround(index);
    for (long j = centre - 3; j <= centre + 3; j++) {
        if (j < 0 || j >= (long)f->count || f->range[j] <= 0.0) {
            continue;
        }
        double ax;
        double ay;
        beam_point(f, (uint32_t)j, &ax, &ay);
        const double near = fmax(OBJ_NEAR_M, f->bearing_step * range);
        if (hypot(x - ax, y - ay) <= near) {
            return true;
        }
        if (j + 1 < (long)f->count && f->range[j + 1] > 0.0) {
            double bx;
            double by;
            beam_point(f, (uint32_t)(j + 1), &bx, &by);
            const double gap = SURFACE_GAP_M + 3.0 * f->bearing_step * f->range[j];
            if (hypot(bx - ax, by - ay) <= gap &&
                segment_distance(x, y, ax, ay, bx, by) <= near) {
                return true;
            }
        }
    }
    return false;
}

/* True when f's beams on both sides of the world point reached more than
 * OBJ_FREE_MARGIN_M beyond it (a beam without a return reached beyond
 * OBJ_MAX_RANGE_M): f saw free space there. */
static bool seen_free(const obj_frame_t *f, double wx, double wy)
{
    double range;
    double index;
    polar(f, wx, wy, &range, &index);
    if (f->count == 0u || !(index >= 0.0) || index > (double)(f->count - 1u) ||
        range > OBJ_MAX_RANGE_M) {
        return false;
    }
    const uint32_t j0 = (uint32_t)floor(index);
    const uint32_t j1 = (j0 + 1u < f->count) ? j0 + 1u : j0;
    for (uint32_t j = j0; j <= j1; j++) {
        if (f->range[j] > 0.0 && f->range[j] <= range + OBJ_FREE_MARGIN_M) {
            return false;
        }
    }
    return true;
}

/* True when a current point outside the segment [k0, k1] lies nearer than
 * OBJ_REVEAL_SHARE of dist to the world point: what stood there has more
 * likely moved to that other body (a person crossing in front of a wall)
 * than receded to the segment, dist behind it. The beams looked at are
 * those that can pass within dist of it. */
static bool nearer_elsewhere(const obj_frame_t *cur, uint32_t k0, uint32_t k1, double wx,
                             double wy, double dist)
{
    double x;
    double y;
    to_vehicle(cur, wx, wy, &x, &y);
    double range;
    double index;
    polar_of_vehicle(cur, x, y, &range, &index);
    /* Only the beams whose bearings can pass within dist of it. */
    const double half =
        (dist < range) ? asin(dist / range) / cur->bearing_step : (double)cur->count;
    const long lo = (long)floor(index - half);
    const long hi = (long)ceil(index + half);
    for (long j = (lo > 0) ? lo : 0; j <= hi && j < (long)cur->count; j++) {
        if (cur->range[j] <= 0.0 || (j >= (long)k0 && j <= (long)k1)) {
            continue;
        }
        double qx;
        double qy;
        beam_point(cur, (uint32_t)j, &qx, &qy);
        if (hypot(qx - x, qy - y) < OBJ_REVEAL_SHARE * dist) {
            return true;
        }
    }
    return false;
}

/* What beam k of the current frame, in the segment [k0, k1], tells of
 * motion against ref. A body receding counts when what it left behind lay
 * at most recede_m in front. */
typedef enum { EV_NONE, EV_MOTION, EV_REVEALED } evidence_t;

static evidence_t evidence(const obj_frame_t *cur, const obj_frame_t *ref, uint32_t k, uint32_t k0,
                           uint32_t k1, double recede_m)
{
    double x;
    double y;
    double wx;
    double wy;
    beam_point(cur, k, &x, &y);
    to_world(cur, x, y, &wx, &wy);
    if (near_surface(ref, wx, wy)) {
        return EV_NONE;
    }
    if (seen_free(ref, wx, wy)) {
        return EV_MOTION; /* entered space that was free */
    }
    double range;
    double index;
    polar(ref, wx, wy, &range, &index);
    const long centre = lround(index);
    evidence_t found = EV_NONE;
    for (long j = centre - 1; j <= centre + 1; j++) {
        if (j < 0 || j >= (long)ref->count || ref->range[j] <= 0.0 ||
            ref->range[j] > range - RECEDE_MIN_M || ref->range[j] < range - recede_m) {
            continue;
        }
        double rx;
        double ry;
        double rwx;
        double rwy;
        beam_point(ref, (uint32_t)j, &rx, &ry);
        to_world(ref, rx, ry, &rwx, &rwy);
        if (seen_free(cur, rwx, rwy) && !near_surface(cur, rwx, rwy)) {
            /* What was in front of it is gone: receded to it, or moved
             * aside to another body nearer, revealing it (objects.h). */
            if (!nearer_elsewhere(cur, k0, k1, rwx, rwy, hypot(rwx - wx, rwy - wy))) {
                return EV_MOTION;
            }
            found = EV_REVEALED;
        }
    }
    return found;
}

/* Least-squares slope of a series of a track (xs, ys) since t0 over the
 * sightings where use[i] (all when use is NULL); false when they span less
 * than OBJ_VEL_MIN_S. */
static bool series_slope(const obj_track_t *tr, const double *xs, const double *ys,
                         const bool *use, double t0, double *vx, double *vy)
{
    double n = 0.0;
    double st = 0.0;
    double sx = 0.0;
    double sy = 0.0;
    double first = 0.0;
    double last = 0.0;
    for (uint32_t i = 0u; i < tr->n; i++) {
        if (tr->t[i] < t0 || (use != NULL && !use[i])) {
            continue;
        }
        if (n == 0.0) {
            first = tr->t[i];
        }
        last = tr->t[i];
        n += 1.0;
        st += tr->t[i];
        sx += xs[i];
        sy += ys[i];
    }
    if (n < 2.0 || last - first < OBJ_VEL_MIN_S) {
        return false;
    }
    const double tm = st / n;
    const double xm = sx / n;
    const double ym = sy / n;
    double stt = 0.0;
    double stx = 0.0;
    double sty = 0.0;
    for (uint32_t i = 0u; i < tr->n; i++) {
        if (tr->t[i] < t0 || (use != NULL && !use[i])) {
            continue;
        }
        const double d = tr->t[i] - tm;
        stt += d * d;
        stx += d * (xs[i] - xm);
        sty += d * (ys[i] - ym);
    }
    *vx = stx / stt;
    *vy = sty / stt;
    return true;
}

/* The mean slope since t0 of the ends uncut throughout (whole) or over
 * the sightings where they were uncut (!whole); false when none has one. */
static bool ends_slope(const obj_track_t *tr, double t0, bool whole, double *vx, double *vy)
{
    double sum_x = 0.0;
    double sum_y = 0.0;
    int ends = 0;
    for (int e = 0; e < 2; e++) {
        bool ok = true;
        for (uint32_t i = 0u; i < tr->n; i++) {
            ok = ok && (tr->t[i] < t0 || tr->ok[e][i]);
        }
        double ex;
        double ey;
        if ((ok || !whole) && series_slope(tr, tr->ex[e], tr->ey[e], tr->ok[e], t0, &ex, &ey)) {
            sum_x += ex;
            sum_y += ey;
            ends++;
        }
    }
    if (ends == 0) {
        return false;
    }
    *vx = sum_x / ends;
    *vy = sum_y / ends;
    return true;
}

/* A track's velocity since t0 (objects.h: its silhouette ends, else its
 * centre); false when unknown. *from_ends (may be NULL) tells which. An end
 * uncut throughout is preferred: one cut now and then may be no corner
 * even where it looks uncut (a side seen at a grazing angle breaks up where
 * its points are more than OBJ_GAP_M apart). Else the ends over the
 * sightings where they were uncut: a car often comes out from behind one
 * thing and goes behind the next, cut at one end and then at the other,
 * and its centre then slides along it. */
static bool track_velocity_from(const obj_track_t *tr, double t0, double *vx, double *vy,
                                bool *from_ends)
{
    const bool ends = ends_slope(tr, t0, true, vx, vy) || ends_slope(tr, t0, false, vx, vy);
    if (from_ends != NULL) {
        *from_ends = ends;
    }
    return ends || series_slope(tr, tr->x, tr->y, NULL, t0, vx, vy);
}

static bool track_velocity(const obj_track_t *tr, double t0, double *vx, double *vy)
{
    return track_velocity_from(tr, t0, vx, vy, NULL);
}

/* Where a track is expected at time ts (world frame). */
static void track_predict(const obj_track_t *tr, double ts, double *x, double *y)
{
    const uint32_t last = tr->n - 1u;
    double vx = 0.0;
    double vy = 0.0;
    if (!track_velocity(tr, tr->t[last] - OBJ_VEL_WINDOW_S, &vx, &vy) && tr->n >= 2u &&
        tr->t[last] > tr->t[last - 1u]) {
        const double dt = tr->t[last] - tr->t[last - 1u];
        vx = (tr->x[last] - tr->x[last - 1u]) / dt;
        vy = (tr->y[last] - tr->y[last - 1u]) / dt;
    }
    *x = tr->x[last] + vx * (ts - tr->t[last]);
    *y = tr->y[last] + vy * (ts - tr->t[last]);
}

static void track_add(obj_track_t *tr, double ts, double x, double y, const obj_object_t *o)
{
    if (tr->n == OBJ_TRACK_POINTS) {
        const size_t keep = OBJ_TRACK_POINTS - 1u;
        memmove(&tr->t[0], &tr->t[1], keep * sizeof tr->t[0]);
        memmove(&tr->x[0], &tr->x[1], keep * sizeof tr->x[0]);
        memmove(&tr->y[0], &tr->y[1], keep * sizeof tr->y[0]);
        for (int e = 0; e < 2; e++) {
            memmove(&tr->ex[e][0], &tr->ex[e][1], keep * sizeof tr->ex[e][0]);
            memmove(&tr->ey[e][0], &tr->ey[e][1], keep * sizeof tr->ey[e][0]);
            memmove(&tr->ok[e][0], &tr->ok[e][1], keep * sizeof tr->ok[e][0]);
        }
        tr->n--;
    }
    tr->t[tr->n] = ts;
    tr->x[tr->n] = x;
    tr->y[tr->n] = y;
    for (int e = 0; e < 2; e++) {
        tr->ex[e][tr->n] = o->end[e][0];
        tr->ey[e][tr->n] = o->end[e][1];
        tr->ok[e][tr->n] = o->end_ok[e];
    }
    tr->n++;
}

/* The box of points [k0, k1] of f along their principal axes (vehicle
 * frame). */
static void cluster_box(const obj_frame_t *f, uint32_t k0, uint32_t k1, obj_object_t *o)
{
    double mx = 0.0;
    double my = 0.0;
    const double n = (double)(k1 - k0 + 1u);
    for (uint32_t k = k0; k <= k1; k++) {
        double x;
        double y;
        beam_point(f, k, &x, &y);
        mx += x / n;
        my += y / n;
    }
    double sxx = 0.0;
    double sxy = 0.0;
    double syy = 0.0;
    for (uint32_t k = k0; k <= k1; k++) {
        double x;
        double y;
        beam_point(f, k, &x, &y);
        sxx += (x - mx) * (x - mx);
        sxy += (x - mx) * (y - my);
        syy += (y - my) * (y - my);
    }
    const double a = 0.5 * atan2(2.0 * sxy, sxx - syy);
    const double ux = cos(a);
    const double uy = sin(a);
    double umin = INFINITY;
    double umax = -INFINITY;
    double vmin = INFINITY;
    double vmax = -INFINITY;
    for (uint32_t k = k0; k <= k1; k++) {
        double x;
        double y;
        beam_point(f, k, &x, &y);
        const double u = (x - mx) * ux + (y - my) * uy;
        const double v = -(x - mx) * uy + (y - my) * ux;
        umin = fmin(umin, u);
        umax = fmax(umax, u);
        vmin = fmin(vmin, v);
        vmax = fmax(vmax, v);
    }
    const double uc = 0.5 * (umin + umax);
    const double vc = 0.5 * (vmin + vmax);
    o->cx = mx + uc * ux - vc * uy;
    o->cy = my + uc * uy + vc * ux;
    o->length = fmax(umax - umin, vmax - vmin);
    o->width = fmin(umax - umin, vmax - vmin);
    o->points = (uint16_t)(k1 - k0 + 1u);
}

/* The frame at least age_s older than the newest, or the oldest one when
 * it is at least half that old; NULL when there is none. */
static const obj_frame_t *reference(const obj_tracker_t *t, double age_s)
{
    const obj_frame_t *cur = &t->frames[t->newest];
    for (uint32_t back = 1u; back < t->frames_used; back++) {
        const obj_frame_t *f = &t->frames[(t->newest + OBJ_HISTORY - back) % OBJ_HISTORY];
        if (cur->time_s - f->time_s >= age_s) {
            return f;
        }
    }
    if (t->frames_used > 1u) {
        const obj_frame_t *f =
            &t->frames[(t->newest + OBJ_HISTORY - (t->frames_used - 1u)) % OBJ_HISTORY];
        if (cur->time_s - f->time_s >= 0.5 * age_s) {
            return f;
        }
    }
    return NULL;
}

/* Enough evidence points among n to call a segment moving (objects.h). */
static bool enough_evidence(uint32_t moving, uint32_t n)
{
    return moving >= 2u &&
           ((double)moving >= OBJ_EVIDENCE_SHARE * n || moving >= OBJ_EVIDENCE_MIN);
}

/* The evidence of the points [k0, k1] of cur against ref, by kind. */
static void count_evidence(const obj_frame_t *cur, const obj_frame_t *ref, uint32_t k0,
                           uint32_t k1, double recede_m, uint32_t count[3])
{
    count[EV_NONE] = 0u;
    count[EV_MOTION] = 0u;
    count[EV_REVEALED] = 0u;
    for (uint32_t j = k0; j <= k1; j++) {
        count[evidence(cur, ref, j, k0, k1, recede_m)]++;
    }
}

/* The segments of the newest frame, moving or not against ref, or for a
 * small one against slow (may be NULL, objects.h): writes up to
 * OBJ_MAX_SEGMENTS into out (id and velocity not set), returns how many. */
static size_t find_clusters(const obj_frame_t *cur, const obj_frame_t *ref,
                            const obj_frame_t *slow, obj_object_t *out)
{
    size_t found = 0u;
    uint32_t k = 0u;
    while (k < cur->count && found < OBJ_MAX_SEGMENTS) {
        if (cur->range[k] <= 0.0 || cur->range[k] > OBJ_MAX_RANGE_M) {
            k++;
            continue;
        }
        uint32_t end = k;
        while (end + 1u < cur->count && cur->range[end + 1u] > 0.0 &&
               cur->range[end + 1u] <= OBJ_MAX_RANGE_M) {
            double ax;
            double ay;
            double bx;
            double by;
            beam_point(cur, end, &ax, &ay);
            beam_point(cur, end + 1u, &bx, &by);
            if (hypot(bx - ax, by - ay) > OBJ_GAP_M) {
                break;
            }
            end++;
        }
        const uint32_t n = end - k + 1u;
        if (n >= OBJ_MIN_POINTS) {
            obj_object_t o;
            memset(&o, 0, sizeof o);
            cluster_box(cur, k, end, &o);
            uint32_t count[3];
            count_evidence(cur, ref, k, end, OBJ_RECEDE_M, count);
            o.moving = enough_evidence(count[EV_MOTION] + count[EV_REVEALED], n);
            o.proven = enough_evidence(count[EV_MOTION], n);
            /* A slow body, a person, moves beyond the margins only over
             * the longer reference (objects.h). */
            if (!o.proven && slow != NULL && o.length <= OBJ_SLOW_MAX_M &&
                n >= OBJ_SLOW_MIN_POINTS) {
                count_evidence(cur, slow, k, end,
                               OBJ_SLOW_MAX_SPEED * (cur->time_s - slow->time_s), count);
                const bool slow_moving =
                    enough_evidence(count[EV_MOTION] + count[EV_REVEALED], n);
                o.slow = !o.moving && slow_moving;
                o.moving = o.moving || slow_moving;
                o.proven = enough_evidence(count[EV_MOTION], n);
            }
            const uint32_t ends[2] = {k, end};
            for (int e = 0; e < 2; e++) {
                double x;
                double y;
                beam_point(cur, ends[e], &x, &y);
                to_world(cur, x, y, &o.end[e][0], &o.end[e][1]);
                /* The neighbour beyond the end: out of the field, or a
                 * return in front of it, cuts the body. */
                const long beyond = (e == 0) ? (long)k - 1 : (long)end + 1;
                o.end_ok[e] = beyond >= 0 && beyond < (long)cur->count &&
                              (cur->range[beyond] <= 0.0 ||
                               cur->range[beyond] > cur->range[ends[e]] + OBJ_GAP_M);
            }
            if (o.length <= OBJ_MAX_EXTENT_M) {
                out[found++] = o;
            }
        }
        k = end + 1u;
    }
    return found;
}

size_t obj_scan(obj_tracker_t *t, uint32_t scan, double time_s, bool measured, double dx,
                double dy, double dtheta, const obj_scan_t *in, obj_object_t *out, size_t cap)
{
    const bool chained = measured && t->frames_used > 0u && scan == t->last_scan + 1u;
    t->last_scan = scan;
    double pose[3] = {0.0, 0.0, 0.0};
    if (chained) {
        const double *p = t->frames[t->newest].pose;
        const double c = cos(p[2]);
        const double s = sin(p[2]);
        pose[0] = p[0] + c * dx - s * dy;
        pose[1] = p[1] + s * dx + c * dy;
        pose[2] = remainder(p[2] + dtheta, 2.0 * 3.14159265358979323846);
    } else {
        t->frames_used = 0u; /* no measured motion: start over */
        t->tracks_used = 0u;
    }
    t->newest = (t->frames_used == 0u) ? 0u : (t->newest + 1u) % OBJ_HISTORY;
    t->frames_used += (t->frames_used < OBJ_HISTORY) ? 1u : 0u;
    obj_frame_t *cur = &t->frames[t->newest];
    cur->time_s = time_s;
    memcpy(cur->pose, pose, sizeof pose);
    cur->count = (in->count <= OBJ_MAX_BEAMS) ? in->count : (uint16_t)OBJ_MAX_BEAMS;
    cur->first_bearing = in->first_bearing;
    cur->bearing_step = in->bearing_step;
    cur->origin_x = in->origin_x;
    cur->origin_y = in->origin_y;
    for (uint32_t k = 0u; k < cur->count; k++) {
        cur->range[k] = (isfinite(in->range[k]) && in->range[k] > 0.0) ? in->range[k] : 0.0;
    }
    const obj_frame_t *ref = reference(t, OBJ_REF_S);
    if (ref == NULL) {
        return 0u;
    }
    const obj_frame_t *slow = reference(t, OBJ_SLOW_REF_S);
    static obj_object_t found[OBJ_MAX_SEGMENTS]; /* 24 KB: static, not reentrant */
    const size_t n = find_clusters(cur, ref, (slow != ref) ? slow : NULL, found);
    double wx[OBJ_MAX_SEGMENTS];
    double wy[OBJ_MAX_SEGMENTS];
    int track_of[OBJ_MAX_SEGMENTS];
    for (size_t i = 0u; i < n; i++) {
        to_world(cur, found[i].cx, found[i].cy, &wx[i], &wy[i]);
        track_of[i] = -1;
    }
    /* Greedy association, nearest pair first. */
    double px[OBJ_MAX_TRACKS];
    double py[OBJ_MAX_TRACKS];
    bool taken[OBJ_MAX_TRACKS] = {false};
    bool hold[OBJ_MAX_TRACKS] = {false};
    for (uint32_t j = 0u; j < t->tracks_used; j++) {
        const obj_track_t *tr = &t->tracks[j];
        track_predict(tr, time_s, &px[j], &py[j]);
        taken[j] = false;
        double vx;
        double vy;
        bool from_ends = false;
        hold[j] = tr->hits >= OBJ_CONFIRM && tr->held < OBJ_MAX_HELD &&
                  tr->length >= OBJ_HOLD_TRACK_LENGTH_M &&
                  track_velocity_from(tr, tr->t[tr->n - 1u] - OBJ_VEL_WINDOW_S, &vx, &vy,
                                      &from_ends) &&
                  from_ends && hypot(vx, vy) >= OBJ_HOLD_MIN_SPEED;
    }
    /* First the moving clusters and any track; then (hold) the other
     * segments and the confirmed tracks still moving that are left. */
    int pass = 0;
    while (pass < 2) {
        double best = (pass == 0) ? OBJ_GATE_M : OBJ_HOLD_GATE_M;
        size_t bi = 0u;
        uint32_t bj = 0u;
        bool any = false;
        for (size_t i = 0u; i < n; i++) {
            if (found[i].moving != (pass == 0)) {
                continue;
            }
            for (uint32_t j = 0u; j < t->tracks_used && track_of[i] < 0; j++) {
                const double d = hypot(wx[i] - px[j], wy[i] - py[j]);
                if (!taken[j] && d <= best &&
                    (pass == 0 || (hold[j] && found[i].length >= OBJ_HOLD_MIN_LENGTH_M))) {
                    best = d;
                    bi = i;
                    bj = j;
                    any = true;
                }
            }
        }
        if (any) {
            track_of[bi] = (int)bj;
            taken[bj] = true;
        } else {
            pass++;
        }
    }
    /* Update, age out, start tracks. */
    for (uint32_t j = 0u; j < t->tracks_used; j++) {
        t->tracks[j].misses = taken[j] ? 0u : t->tracks[j].misses + 1u;
    }
    for (size_t i = 0u; i < n; i++) {
        if (track_of[i] >= 0) {
            obj_track_t *tr = &t->tracks[track_of[i]];
            track_add(tr, time_s, wx[i], wy[i], &found[i]);
            tr->hits++;
            tr->proven = tr->proven || found[i].proven;
            tr->held = found[i].moving ? 0u : tr->held + 1u;
            tr->length = found[i].moving ? fmax(tr->length, found[i].length) : tr->length;
        } else if (found[i].moving && !found[i].slow && t->tracks_used < OBJ_MAX_TRACKS) {
            /* (a slow cluster continues a track but starts none: objects.h) */
            obj_track_t *tr = &t->tracks[t->tracks_used++];
            memset(tr, 0, sizeof *tr);
            tr->id = t->next_id++;
            tr->hits = 1u;
            tr->proven = found[i].proven;
            tr->length = found[i].length;
            track_add(tr, time_s, wx[i], wy[i], &found[i]);
            track_of[i] = (int)(t->tracks_used - 1u);
        }
    }
    size_t written = 0u;
    const double c = cos(cur->pose[2]);
    const double s = sin(cur->pose[2]);
    for (size_t i = 0u; i < n && written < cap; i++) {
        if (track_of[i] < 0 || t->tracks[track_of[i]].hits < OBJ_CONFIRM ||
            !t->tracks[track_of[i]].proven) {
            continue;
        }
        const obj_track_t *tr = &t->tracks[track_of[i]];
        obj_object_t o = found[i];
        o.id = tr->id;
        double vx;
        double vy;
        if (track_velocity(tr, time_s - OBJ_VEL_WINDOW_S, &vx, &vy)) {
            o.vx = c * vx + s * vy;
            o.vy = -s * vx + c * vy;
        } else {
            o.vx = NAN;
            o.vy = NAN;
        }
        out[written++] = o;
    }
    /* Drop the tracks not seen for long (the ids of the ones matched above
     * are already out). */
    uint32_t kept = 0u;
    for (uint32_t j = 0u; j < t->tracks_used; j++) {
        if (t->tracks[j].misses <= OBJ_MAX_MISSES) {
            t->tracks[kept++] = t->tracks[j];
        }
    }
    t->tracks_used = kept;
    return written;
}
