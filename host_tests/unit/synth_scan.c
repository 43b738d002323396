/* synth_scan.c - see synth_scan.h. */
#include "synth_scan.h"

#include "ego_lms.h"

#include <math.h>
#include <string.h>

#define SYNTH_PI 3.14159265358979323846

const synth_wall_t synth_room[] = {
    {-6.0, -5.0, 10.0, -5.0},  {10.0, -5.0, 10.0, 5.0}, {10.0, 5.0, -6.0, 5.0},
    {-6.0, 5.0, -6.0, -5.0},   {3.0, 2.0, 5.0, 3.5},    {5.0, 3.5, 6.0, 2.2},
    {6.5, -3.0, 8.0, -1.0},    {-3.0, -2.5, -1.5, -3.5}, {2.0, -1.0, 2.6, -1.0},
    {2.6, -1.0, 2.6, -0.4},    {2.6, -0.4, 2.0, -0.4},  {2.0, -0.4, 2.0, -1.0},
    {-4.0, 3.0, -2.0, 4.2},    {7.0, 4.0, 9.0, 2.5},
};
const unsigned synth_room_walls = sizeof synth_room / sizeof synth_room[0];

const synth_wall_t synth_corridor[] = {
    {-200.0, -1.5, 200.0, -1.5},
    {-200.0, 1.5, 200.0, 1.5},
};
const unsigned synth_corridor_walls = sizeof synth_corridor / sizeof synth_corridor[0];

/* Distance along the ray (ox, oy) + t (dx, dy) to the wall, or -1. */
static double hit(const synth_wall_t *w, double ox, double oy, double dx, double dy)
{
    const double ex = w->x1 - w->x0;
    const double ey = w->y1 - w->y0;
    const double den = dx * ey - dy * ex;
    if (fabs(den) < 1e-12) {
        return -1.0;
    }
    const double t = ((w->x0 - ox) * ey - (w->y0 - oy) * ex) / den;
    const double u = ((w->x0 - ox) * dy - (w->y0 - oy) * dx) / den;
    return (t > 0.0 && u >= 0.0 && u <= 1.0) ? t : -1.0;
}

void synth_scan(const synth_wall_t *walls, unsigned nwalls, double x, double y, double heading,
                unsigned count, lms_unit_t unit, lms_scan_t *out)
{
    memset(out, 0, sizeof *out);
    out->count = (uint16_t)count;
    out->unit = unit;
    out->address = 0x80u;
    out->status = 0x10u;
    const double step = 180.0 / (double)(count - 1u);
    const double per_unit = (unit == LMS_UNIT_MM) ? 1000.0 : 100.0;
    for (unsigned k = 0u; k < count; k++) {
        const double a = heading + (-90.0 + step * k) * SYNTH_PI / 180.0;
        double best = -1.0;
        for (unsigned w = 0u; w < nwalls; w++) {
            const double t = hit(&walls[w], x, y, cos(a), sin(a));
            if (t > 0.0 && (best < 0.0 || t < best)) {
                best = t;
            }
        }
        const long v = (best > 0.0) ? lround(best * per_unit) : 0x1FF7;
        out->values[k] = (uint16_t)((v > 0x1FF6) ? 0x1FF7 : v);
    }
}

const ego_range_scan_t *synth_range(const lms_scan_t *lms)
{
    static lms_scan_t work; /* the adapter writes the ranges over the values */
    static ego_range_scan_t range;
    ego_lms_params_t params;
    ego_lms_defaults(&params);
    params.timing = (uint8_t)EGO_LMS_TIMING_INSTANT; /* cast at once */
    work = *lms;
    return (ego_lms_to_range(&work, &params, &range) == EGO_LMS_OK) ? &range : NULL;
}
