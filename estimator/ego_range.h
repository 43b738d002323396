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
 * the scan, each step in (0, half a turn), and the last beam, as a 32-bit
 * binary angle, at most EGO_MAX_SWEEP after the first: a 360-degree
 * scanner's 720 beams 0.5 deg apart are fine, a scan whose last beam
 * repeats the first's direction is not (its middle bearing, which every
 * search through the scan order measures from, would be that direction).
 *
 * Beam times (for de-skewing under motion; all zero: measured at once). A
 * rotating sensor measures its beams beam_ns apart; one that interlaces
 * passes (the LMS 2xx builds a 0.5-deg scan from two mirror turns, a
 * 0.25-deg one from four) measures beam k in pass k % passes, k / passes
 * beams into it, the passes pass_us apart:
 *     t_k = (k % passes) * pass_us * 1000 + (k / passes) * beam_ns  (ns)
 * The scan's time, the instant its pose and its dt refer to, is the mean
 * of its beams' times (ego_range_mean_ns); a scan spans at most 1 s.
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
    fx_q16_16_t origin_x;      /* the sensor's origin in the vehicle frame, m, */
    fx_q16_16_t origin_y;      /* each within +-EGO_MAX_ORIGIN */
    uint64_t first_bearing;    /* beam 0: Q32.32 binary angle, vehicle frame */
    uint64_t bearing_step;     /* between beams: Q32.32 binary angle */
    const fx_bam32_t *bearing; /* NULL: uniform; else count bearings, vehicle frame */
    uint8_t passes;            /* interlaced passes, 0 (taken as 1) .. EGO_MAX_PASSES */
    uint32_t pass_us;          /* between the starts of neighbouring passes, us */
    uint32_t beam_ns;          /* between neighbouring beams of one pass, ns */
} ego_range_scan_t;

#define EGO_MAX_PASSES 4u
/* The farthest a sensor's origin may be from the vehicle's, on each axis,
 * Q16.16 m: a sensor on the vehicle, with room. The points' arithmetic
 * takes them within a few hundred metres of the vehicle's origin. */
#define EGO_MAX_ORIGIN FX_Q16_16_C(100.0)
/* The longest scan, from its first beam to its last, ns. */
#define EGO_MAX_SCAN_SPAN_NS 1000000000u

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

static inline uint32_t ego_range_passes(const ego_range_scan_t *scan)
{
    return (scan->passes == 0u) ? 1u : scan->passes;
}

/* Time of beam k after beam 0, ns (the scan passed ego_range_check). */
static inline uint32_t ego_range_beam_ns(const ego_range_scan_t *scan, uint16_t k)
{
    const uint32_t passes = ego_range_passes(scan);
    return (k % passes) * scan->pass_us * 1000u + (k / passes) * scan->beam_ns;
}

/* The scan's time: the mean of its beams' times after beam 0, ns, rounded
 * down (0 for an empty scan). */
static inline uint32_t ego_range_mean_ns(const ego_range_scan_t *scan)
{
    uint64_t sum = 0u;
    for (uint16_t k = 0u; k < scan->count; k++) {
        sum += ego_range_beam_ns(scan, k);
    }
    return (scan->count > 0u) ? (uint32_t)(sum / scan->count) : 0u;
}

/* From the scan's time to its last beam, ns: how long before the sensor
 * can have sent it the scan's time was. */
static inline uint32_t ego_range_lag_ns(const ego_range_scan_t *scan)
{
    uint32_t last = 0u;
    for (uint16_t k = 0u; k < scan->count; k++) {
        const uint32_t t = ego_range_beam_ns(scan, k);
        last = (t > last) ? t : last;
    }
    return last - ego_range_mean_ns(scan);
}

/* The beam times span at most EGO_MAX_SCAN_SPAN_NS (so every time and
 * every offset from the mean fits 31 bits). */
static inline bool ego_range_times_ok(const ego_range_scan_t *scan)
{
    const uint32_t passes = ego_range_passes(scan);
    if (passes > EGO_MAX_PASSES || scan->pass_us > EGO_MAX_SCAN_SPAN_NS / 1000u ||
        scan->beam_ns > EGO_MAX_SCAN_SPAN_NS) {
        return false;
    }
    const uint32_t per_pass = (scan->count > 0u) ? (uint32_t)(scan->count - 1u) / passes : 0u;
    const uint64_t span =
        (uint64_t)(passes - 1u) * scan->pass_us * 1000u + (uint64_t)per_pass * scan->beam_ns;
    return span <= EGO_MAX_SCAN_SPAN_NS;
}

/* The widest scan, first beam to last, in 32-bit binary-angle units: a
 * turn less two, so that every beam lies strictly within half a turn of
 * the middle one (the searches through the scan order compare int32
 * bearings relative to it). Found by fuzz_itcp (docs/robustness.md, E4):
 * with uniform steps of a whole turn in all the last beam rounded onto the
 * first, and the bearing searches placed points by where they started. */
#define EGO_MAX_SWEEP 0xFFFFFFFEu

/* True when the scan is usable: arrays given, count within the capacity,
 * a range unit in 1 um .. 0.5 m (the largest range, 65535 units, then
 * fits Q16.16 metres), the origin within EGO_MAX_ORIGIN, beam times within
 * ego_range_times_ok, every step between neighbouring bearings in (0, half
 * a turn), the last beam at most EGO_MAX_SWEEP after the first (uniform
 * steps: steps * bearing_step at most (EGO_MAX_SWEEP - 1) * 2^32, which
 * ego_range_bearing's rounding keeps within it). One pass over the
 * bearings of a table. */
bool ego_range_check(const ego_range_scan_t *scan); /* in ego_scan.c */

#endif /* EGO_RANGE_H */
