/* world_geom.h - 2-D rigid poses for lmsworld (host-only, doubles).
 *
 * World frame: metres, x east, y north, angles in radians counter-
 * clockwise from +x. A pose (x, y, theta) places a frame whose x axis is
 * the scanner's forward direction (LMS angle 90 deg) and whose y axis
 * points to the scanner's left (LMS angle 180 deg).
 *
 * compose / inverse / between are the SE(2) operations of
 * ../shared/tools/carmenlog.py, so a truth line written from between()
 * means exactly what relpose_eval.py compares against.
 */
#ifndef LMSWORLD_GEOM_H
#define LMSWORLD_GEOM_H

#define WORLD_PI 3.14159265358979323846

typedef struct {
    double x;     /* m */
    double y;     /* m */
    double theta; /* rad */
} wpose_t;

/* An angle wrapped to (-pi, pi] (carmenlog.wrap). */
double world_wrap(double angle);

/* a (+) b: b given in the frame of a, expressed in the frame a lives in. */
wpose_t world_compose(wpose_t a, wpose_t b);

/* The pose whose composition with a is the identity. */
wpose_t world_inverse(wpose_t a);

/* inverse(a) (+) b: the pose b expressed in the frame of a. */
wpose_t world_between(wpose_t a, wpose_t b);

/* Degrees to radians. */
double world_rad(double deg);

#endif /* LMSWORLD_GEOM_H */
