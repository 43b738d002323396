/* world_path.h - driving paths and speed profiles for lmsworld (host-only).
 *
 * A path is a chain of pieces of constant curvature (straights and circular
 * arcs) from a start pose; the heading is continuous along it. A pose on
 * the path is asked for by arc length s, optionally shifted sideways
 * (lateral > 0 = to the left of the direction of travel), e.g. for the
 * oncoming lane.
 *
 * A speed profile is a list of (time, speed) knots joined by half-cosine
 * ramps, so speed and acceleration are continuous; the distance travelled
 * is integrated in closed form.
 */
#ifndef LMSWORLD_PATH_H
#define LMSWORLD_PATH_H

#include <stdbool.h>
#include <stddef.h>

#include "world_geom.h"

#define WPATH_MAX_PIECES 32u

typedef struct {
    double length;    /* m, > 0 */
    double curvature; /* 1/m, > 0 turns left; 0 = straight */
} wpiece_t;

typedef struct {
    wpiece_t pieces[WPATH_MAX_PIECES];
    wpose_t starts[WPATH_MAX_PIECES]; /* pose at the start of each piece */
    double offsets[WPATH_MAX_PIECES]; /* arc length at the start of each piece */
    size_t count;
    double total;                     /* m */
    bool loop;                        /* s wraps modulo total */
} wpath_t;

/* Builds the path; count <= WPATH_MAX_PIECES. */
void wpath_init(wpath_t *path, wpose_t start, const wpiece_t *pieces, size_t count, bool loop);

/* Pose at arc length s (a loop wraps s; an open path continues straight
 * beyond its ends), moved lateral metres to the left. */
wpose_t wpath_pose(const wpath_t *path, double s, double lateral);

typedef struct {
    double t; /* s, increasing */
    double v; /* m/s */
} wknot_t;

/* Speed at time t: the first knot's speed before it, the last's after it. */
double wprofile_speed(const wknot_t *knots, size_t count, double t);

/* Distance travelled from time 0 to t (t >= 0; the first knot is at 0). */
double wprofile_distance(const wknot_t *knots, size_t count, double t);

#endif /* LMSWORLD_PATH_H */
