/* world_geom.c - see world_geom.h. */
#include "world_geom.h"

#include <math.h>

double world_wrap(double angle)
{
    double a = fmod(angle + WORLD_PI, 2.0 * WORLD_PI);
    if (a <= 0.0) {
        a += 2.0 * WORLD_PI;
    }
    return a - WORLD_PI;
}

wpose_t world_compose(wpose_t a, wpose_t b)
{
    const double c = cos(a.theta);
    const double s = sin(a.theta);
    wpose_t out;
    out.x = a.x + c * b.x - s * b.y;
    out.y = a.y + s * b.x + c * b.y;
    out.theta = world_wrap(a.theta + b.theta);
    return out;
}

wpose_t world_inverse(wpose_t a)
{
    const double c = cos(a.theta);
    const double s = sin(a.theta);
    wpose_t out;
    out.x = -c * a.x - s * a.y;
    out.y = s * a.x - c * a.y;
    out.theta = world_wrap(-a.theta);
    return out;
}

wpose_t world_between(wpose_t a, wpose_t b)
{
    return world_compose(world_inverse(a), b);
}

double world_rad(double deg)
{
    return deg * (WORLD_PI / 180.0);
}
