/* moving_ref.h - double-precision oracle of the moving objects' geometric
 * kernels (estimator/ego_moving.h): a scan's points, its segments and a
 * cluster's chord box, in doubles and metres; and the tiny 2-D world of
 * straight walls their tests cast rays in. Host tests only. */
#ifndef MOVING_REF_H
#define MOVING_REF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ego_range.h"

/* A straight wall from (x0, y0) to (x1, y1), m, world frame. */
typedef struct {
    double x0;
    double y0;
    double x1;
    double y1;
} moving_ref_wall_t;

/* The distance (m) from (ox, oy) along direction dir_rad to the nearest
 * of n walls, or 0 when none is hit within max_m. */
double moving_ref_cast(const moving_ref_wall_t *walls, size_t n, double ox, double oy,
                       double dir_rad, double max_m);

/* The four sides of a box: centre (cx, cy), heading_rad (its length's
 * direction), length along it and width across it, m. */
void moving_ref_box_walls(double cx, double cy, double heading_rad, double length, double width,
                          moving_ref_wall_t out[4]);

/* Beam k of the scan in the vehicle frame, m: origin + r (cos b, sin b),
 * r the range in metres exactly, b the beam's bearing (ego_range_bearing)
 * in radians exactly. */
void moving_ref_point(const ego_range_scan_t *scan, uint16_t k, double *x, double *y);

/* The segments of ego_moving.h: runs of usable beams (a range, at most
 * 35 m) whose neighbours' ranges differ by at most 1 m. Writes at most
 * cap [from[i], to[i]) pairs in scan order; returns how many. */
size_t moving_ref_segments(const ego_range_scan_t *scan, uint16_t *from, uint16_t *to, size_t cap);

/* A cluster's box: the bounding box of its points along the chord from
 * its first point to its last (the x axis when they coincide) and across
 * it (to the chord's left), and the centre of that box. */
typedef struct {
    double cx; /* m, vehicle frame */
    double cy;
    double length; /* along the chord, m */
    double width;  /* across it, m */
} moving_ref_box_t;

/* The box of beams [from, to) of the scan (to > from). */
void moving_ref_chord_box(const ego_range_scan_t *scan, uint16_t from, uint16_t to,
                          moving_ref_box_t *box);

/* A cluster's marks (ego_moving.h): its box centre, its first point and
 * its last point, in one frame the caller chooses, and whether each end is
 * the body's own edge (uncut: the neighbouring beam outside the segment
 * exists and has no return or a longer range; the centre: always). */
typedef struct {
    double x[3];
    double y[3];
    bool uncut[3];
} moving_ref_marks_t;

/* The marks of beams [from, to) of the scan, vehicle frame. */
void moving_ref_marks(const ego_range_scan_t *scan, uint16_t from, uint16_t to,
                      moving_ref_marks_t *marks);

/* A track's velocity (ego_moving.h): from an anchor sighting at least
 * 0.1 s old, the mean displacement per second of the ends uncut then and
 * now, else the centre's; the first measurement sets it, later ones move
 * it a quarter of the way; the anchor moves on to the sighting that
 * measured at an age of 0.3 s or more. Marks and velocity in one frame
 * fixed for the track's life (the world's). */
typedef struct {
    moving_ref_marks_t anchor;
    uint32_t age_us; /* of the anchor */
    bool known;
    bool from_ends; /* the last measurement was the ends' */
    double vx;      /* m/s */
    double vy;
} moving_ref_velocity_t;

/* The track's first sighting. */
void moving_ref_velocity_start(moving_ref_velocity_t *v, const moving_ref_marks_t *marks);

/* A line passed (seen or not): the anchor ages by dt_us. */
void moving_ref_velocity_age(moving_ref_velocity_t *v, uint32_t dt_us);

/* A sighting after the first. */
void moving_ref_velocity_seen(moving_ref_velocity_t *v, const moving_ref_marks_t *marks);

#endif /* MOVING_REF_H */
