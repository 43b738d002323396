/* fx_host.h - conversions between the estimator's fixed-point formats and
 * double, for host tests and host tools only (never in estimator/). */
#ifndef FX_HOST_H
#define FX_HOST_H

#include <math.h>
#include <stdint.h>

#include "ego_fx.h"

#define FX_HOST_PI 3.14159265358979323846

static inline double fx_q16_16_to_double(fx_q16_16_t v)
{
    return (double)v / 65536.0;
}

static inline fx_q16_16_t fx_q16_16_from_double(double v)
{
    return (fx_q16_16_t)llround(v * 65536.0);
}

/* Binary angle to radians in [0, 2 pi). */
static inline double fx_bam32_to_rad(fx_bam32_t a)
{
    return (double)a * (2.0 * FX_HOST_PI / 4294967296.0);
}

/* Radians (any value) to a binary angle, rounded, wrapped. */
static inline fx_bam32_t fx_bam32_from_rad(double rad)
{
    double turns = rad / (2.0 * FX_HOST_PI);
    turns -= floor(turns);
    return (fx_bam32_t)(uint64_t)llround(turns * 4294967296.0);
}

/* Smallest difference of two directions modulo pi, in radians (>= 0). */
static inline double fx_host_line_angle_diff(double a, double b)
{
    double d = fmod(fabs(a - b), FX_HOST_PI);
    return (d > FX_HOST_PI / 2.0) ? FX_HOST_PI - d : d;
}

#endif /* FX_HOST_H */
