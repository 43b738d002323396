/* ego_range.h - the estimator's input: one scan of any 2-D range sensor.
 *
 * A scan is count beams in scan order. Beam k has a bearing (its
 * direction in the vehicle frame: x forward, y left, counter-clockwise
 * positive) and, when valid[k], a range from the sensor's origin. The
 * bearings increase along the scan by less than half a turn per beam and
 * by at most one turn in all, so a full 360-degree sweep is fine. They are
 * either uniform (first_bearing + k * bearing_step, the usual sensor) or
 * given per beam (per_beam_bearing, bearing[k]: a sensor whose beams are
 * not evenly spaced, or one mounted with a known angle table).
 *
 * Nothing in here knows a sensor: the SICK LMS 2xx adapter
 * (firmware/ego_lms.h) fills it from a B0 telegram, the measuring mode,
 * the units and the mounting pose. The caller owns it; it is large
 * (about 9 bytes per beam of capacity), so keep it static.
 */
#ifndef EGO_RANGE_H
#define EGO_RANGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ego_config.h"
#include "ego_fx.h"

typedef struct {
    uint16_t count;            /* beams, <= EGO_MAX_BEAMS */
    fx_q16_16_t origin_x;      /* the sensor's origin in the vehicle frame, m */
    fx_q16_16_t origin_y;
    bool per_beam_bearing;     /* false: first_bearing + k * bearing_step */
    fx_bam32_t first_bearing;  /* beam 0, vehicle frame */
    fx_bam32_t bearing_step;   /* between beams, in (0, half a turn) */
    fx_bam32_t bearing[EGO_MAX_BEAMS]; /* per_beam_bearing: beam k, vehicle frame */
    fx_q16_16_t range[EGO_MAX_BEAMS];  /* metres, Q16.16 (0 .. 32767 m) */
    bool valid[EGO_MAX_BEAMS];         /* false: no range (no return, dazzle, ...) */
} ego_range_scan_t;

/* Bearing of beam k (k < count). */
static inline fx_bam32_t ego_range_bearing(const ego_range_scan_t *scan, uint16_t k)
{
    return scan->per_beam_bearing ? scan->bearing[k]
                                  : scan->first_bearing + (uint32_t)k * scan->bearing_step;
}

/* True when the scan is usable: count within the capacity, every step
 * between neighbouring bearings in (0, half a turn), at most one turn in
 * all. One pass over the beams. */
static inline bool ego_range_check(const ego_range_scan_t *scan)
{
    if (scan == NULL || scan->count > EGO_MAX_BEAMS) {
        return false;
    }
    if (!scan->per_beam_bearing) {
        const uint64_t sweep = (uint64_t)scan->bearing_step * (scan->count > 0u ? scan->count - 1u : 0u);
        return scan->bearing_step != 0u && scan->bearing_step < 0x80000000u && sweep <= 0xFFFFFFFFu;
    }
    uint64_t sweep = 0u;
    for (uint16_t k = 1u; k < scan->count; k++) {
        const uint32_t step = scan->bearing[k] - scan->bearing[k - 1u];
        if (step == 0u || step >= 0x80000000u) {
            return false;
        }
        sweep += step;
    }
    return sweep <= 0xFFFFFFFFu;
}

#endif /* EGO_RANGE_H */
