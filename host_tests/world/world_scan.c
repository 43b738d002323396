/* world_scan.c - see world_scan.h. */
#include "world_scan.h"

#include <math.h>
#include <stdbool.h>

/* Slack added to the culling radius so that a surface at exactly the
 * maximum range is never culled by rounding. */
#define WORLD_CULL_SLACK 1.0

void world_scan_prepare(const wmap_t *static_map, const wmover_t *movers, size_t mover_count,
                        wpose_t pose, double max_range, wmap_t *active)
{
    const double fx = cos(pose.theta);
    const double fy = sin(pose.theta);
    const double radius = max_range + WORLD_CULL_SLACK;
    wmap_clear(active);
    wmap_select(static_map, pose.x, pose.y, fx, fy, radius, active);
    for (size_t i = 0u; i < mover_count; i++) {
        const wmover_t *m = &movers[i];
        const double reach = 0.5 * hypot(m->length, m->width);
        if (hypot(m->x - pose.x, m->y - pose.y) - reach <= radius) {
            wmap_add_box(active, m->x, m->y, m->heading, m->length, m->width);
        }
    }
}

void world_scan_cast(const wmap_t *active, wpose_t pose, unsigned count, double res_deg,
                     double *ranges)
{
    for (unsigned i = 0u; i < count; i++) {
        const double beam = pose.theta + world_rad((double)i * res_deg - 90.0);
        ranges[i] = wmap_cast(active, pose.x, pose.y, cos(beam), sin(beam));
    }
}

uint16_t world_range_word(double range, double noise, lms_unit_t unit, double max_range)
{
    const bool mm = (unit == LMS_UNIT_MM);
    if (!(range <= max_range)) {
        return (uint16_t)(mm ? WORLD_WORD_NONE_MM : WORLD_WORD_BEYOND_CM);
    }
    const double units_per_m = mm ? 1000.0 : 100.0;
    const double largest = mm ? (double)WORLD_WORD_MAX_MM : (double)WORLD_WORD_MAX_CM;
    const double units = round((range + noise) * units_per_m);
    return (uint16_t)fmin(largest, fmax(1.0, units));
}
