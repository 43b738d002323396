/* ego_range.h - the estimator's input: one scan of any 2-D range sensor.
 *
 * A scan is count beams in scan order. Beam k has a bearing (its
 * direction in the vehicle frame: x forward, y left, counter-clockwise
 * positive) and a range from the sensor's origin, or no range.
 *
 * Ranges: range[k] in units of range_unit_um micrometres (UQ16: 1000 for
 * millimetres, 10000 for centimetres, 250 for quarter millimetres), 0 when
 * the beam has no range (no return, dazzle, out of range: any reason).
 * Converted to Q16.16 metres rounded to nearest.
 *
 * Bearings: uniform, beam k at first_bearing + k * bearing_step, both
 * binary angles with 32 more bits of fraction (Q32.32 of a binary angle:
 * 2^64 is one turn; the bearing is rounded to a 32-bit binary angle, so a
 * step that is not a whole binary angle, 0.5 deg say, does not drift); or
 * per beam, bearing[k] (a sensor with an angle table). They increase along
 * the scan, each step in (0, half a turn), at most one turn in all: a full
 * 360-degree sweep is fine.
 *
 * The scan only points at the caller's arrays (nothing is copied, no RAM
 * per beam here); they must stay put until ego_process returns. Nothing in
 * here knows a sensor: the SICK LMS 2xx adapter (firmware/ego_lms.h) turns
 * a B0 telegram's values into ranges in place and fills the rest.
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
    const uint16_t *range;     /* count ranges, units of range_unit_um; 0: none */
    uint32_t range_unit_um;    /* micrometres per range unit, 1 .. 500000 */
    fx_q16_16_t origin_x;      /* the sensor's origin in the vehicle frame, m */
    fx_q16_16_t origin_y;
    uint64_t first_bearing;    /* beam 0: Q32.32 binary angle, vehicle frame */
    uint64_t bearing_step;     /* between beams: Q32.32 binary angle */
    const fx_bam32_t *bearing; /* NULL: uniform; else count bearings, vehicle frame */
} ego_range_scan_t;

/* Q32.32 binary angle of a whole 32-bit one. */
#define EGO_BEARING_Q32(bam) ((uint64_t)(uint32_t)(bam) << 32)

/* Bearing of beam k (k < count), rounded to a binary angle. */
static inline fx_bam32_t ego_range_bearing(const ego_range_scan_t *scan, uint16_t k)
{
    if (scan->bearing != NULL) {
        return scan->bearing[k];
    }
    const uint64_t b = scan->first_bearing + (uint64_t)k * scan->bearing_step;
    return (fx_bam32_t)((b + 0x80000000u) >> 32);
}

/* True when the scan is usable: arrays given, count within the capacity,
 * a range unit in 1 um .. 0.5 m (the largest range, 65535 units, then
 * fits Q16.16 metres), every step between neighbouring bearings in (0, half a
 * turn), at most one turn in all. One pass over the bearings of a table. */
static inline bool ego_range_check(const ego_range_scan_t *scan)
{
    if (scan == NULL || scan->count > EGO_MAX_BEAMS || (scan->count > 0u && scan->range == NULL) ||
        scan->range_unit_um == 0u || scan->range_unit_um > 500000u) {
        return false;
    }
    const uint16_t steps = (scan->count > 0u) ? (uint16_t)(scan->count - 1u) : 0u;
    if (scan->bearing == NULL) {
        const uint64_t half = (uint64_t)1 << 63;
        /* steps * step <= one turn (2^64), without overflow. */
        return scan->bearing_step != 0u && scan->bearing_step < half &&
               (steps == 0u || scan->bearing_step <= UINT64_MAX / steps);
    }
    uint64_t sweep = 0u;
    for (uint16_t k = 1u; k < scan->count; k++) {
        const uint32_t turn = scan->bearing[k] - scan->bearing[k - 1u];
        if (turn == 0u || turn >= 0x80000000u) {
            return false;
        }
        sweep += turn;
    }
    return sweep <= 0xFFFFFFFFu;
}

#endif /* EGO_RANGE_H */
