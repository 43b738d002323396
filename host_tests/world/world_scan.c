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

unsigned world_scan_passes(unsigned count)
{
    return (count > 181u) ? 2u : 1u;
}

double world_beam_time(unsigned i, unsigned count)
{
    const unsigned passes = world_scan_passes(count);
    const unsigned pass = i % passes;    /* which mirror turn */
    const unsigned degrees = i / passes; /* into that turn's sweep */
    return (double)pass / WORLD_MIRROR_HZ + (double)degrees / (WORLD_MIRROR_HZ * 360.0);
}

double world_beam_mean_time(unsigned count)
{
    double sum = 0.0;
    for (unsigned i = 0u; i < count; i++) {
        sum += world_beam_time(i, count);
    }
    return (count > 0u) ? sum / (double)count : 0.0;
}

void world_scan_cast_lms(const wscenario_t *sc, const wmap_t *static_map, unsigned k,
                         double period, unsigned count, double res_deg, double max_range,
                         wmap_t *active, wmap_t *scratch, double *ranges)
{
    static wpose_t poses[LMS_SCAN_MAX_VALUES];
    static double offsets[LMS_SCAN_MAX_VALUES];
    const double mean = world_beam_mean_time(count);
    const wpose_t centre = sc->pose(k, period, 0.0);
    double reach = 0.0;
    for (unsigned i = 0u; i < count && i < LMS_SCAN_MAX_VALUES; i++) {
        offsets[i] = world_beam_time(i, count) - mean;
        poses[i] = sc->pose(k, period, offsets[i]);
        reach = fmax(reach, hypot(poses[i].x - centre.x, poses[i].y - centre.y));
    }
    /* Every direction ((0, 0): no half-plane), out to the farthest beam
     * pose plus the maximum range. */
    const double radius = max_range + WORLD_CULL_SLACK + reach;
    wmap_clear(active);
    wmap_select(static_map, centre.x, centre.y, 0.0, 0.0, radius, active);
    wmover_t movers[WORLD_MAX_MOVERS];
    for (unsigned i = 0u; i < count && i < LMS_SCAN_MAX_VALUES; i++) {
        const wpose_t p = poses[i];
        const size_t mover_count =
            (sc->movers != NULL)
                ? sc->movers((double)k * period + offsets[i], movers)
                : 0u;
        wmap_clear(scratch);
        for (size_t j = 0u; j < mover_count; j++) {
            const wmover_t *m = &movers[j];
            wmap_add_box(scratch, m->x, m->y, m->heading, m->length, m->width);
        }
        const double beam = p.theta + world_rad((double)i * res_deg - 90.0);
        const double dx = cos(beam);
        const double dy = sin(beam);
        ranges[i] = fmin(wmap_cast(active, p.x, p.y, dx, dy),
                         wmap_cast(scratch, p.x, p.y, dx, dy));
    }
}

/* The range of the beam from p at LMS angle i * res_deg to mover m alone. */
static double mover_range(const wmover_t *m, wpose_t p, unsigned i, double res_deg,
                          wmap_t *scratch)
{
    wmap_clear(scratch);
    wmap_add_box(scratch, m->x, m->y, m->heading, m->length, m->width);
    const double beam = p.theta + world_rad((double)i * res_deg - 90.0);
    return wmap_cast(scratch, p.x, p.y, cos(beam), sin(beam));
}

size_t world_scan_returns(const wscenario_t *sc, unsigned k, double period, unsigned count,
                          double res_deg, bool lms_timing, const double *ranges,
                          double max_range, wmap_t *scratch, unsigned *returns)
{
    for (size_t j = 0u; j < WORLD_MAX_MOVERS; j++) {
        returns[j] = 0u;
    }
    if (sc->movers == NULL) {
        return 0u;
    }
    wmover_t movers[WORLD_MAX_MOVERS];
    /* The scan's own pose and movers (instant timing), or per value below:
     * each written exactly as world_scan_cast_lms and lmsworld write them. */
    wpose_t pose = sc->pose(k, period, 0.0);
    size_t n = sc->movers((double)k * period, movers);
    const double mean = world_beam_mean_time(count);
    for (unsigned i = 0u; i < count && i < LMS_SCAN_MAX_VALUES; i++) {
        if (!(ranges[i] <= max_range)) {
            continue;
        }
        if (lms_timing) {
            const double offset = world_beam_time(i, count) - mean;
            pose = sc->pose(k, period, offset);
            n = sc->movers((double)k * period + offset, movers);
        }
        for (size_t j = 0u; j < n && j < WORLD_MAX_MOVERS; j++) {
            if (mover_range(&movers[j], pose, i, res_deg, scratch) == ranges[i]) {
                returns[j]++;
                break;
            }
        }
    }
    return n;
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
