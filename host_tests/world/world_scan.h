/* world_scan.h - one LMS 2xx scan from a map and a pose, and the value
 * words that carry its ranges (host-only).
 *
 * Beams: a 180 deg field at res_deg (1 or 0.5), beam i at the LMS angle
 * a_i = i * res_deg (0 = the scanner's right, 90 = ahead, 180 = left), i.e.
 * at a_i - 90 deg in the scanner frame (x forward, y left).
 *
 * Value words (docs/synthetic-worlds.md, "Units and special values"):
 *   cm: measuring mode 00, 13-bit ranges 1..0x1FF6 (81.82 m); a beam with
 *       no surface within the maximum range is 0x1FF7 (beyond max).
 *   mm: measuring mode 0F, 16-bit ranges 1..0xFFFF (65.535 m), no special
 *       codes; a beam with no surface within the maximum range is 0, which
 *       is never a real return.
 */
#ifndef LMSWORLD_SCAN_H
#define LMSWORLD_SCAN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lms_proto.h"
#include "world_geom.h"
#include "world_map.h"
#include "world_scenario.h"

#define WORLD_WORD_MAX_CM 0x1FF6u   /* mode 00: largest range */
#define WORLD_WORD_BEYOND_CM 0x1FF7u /* mode 00: measured value > maximum */
#define WORLD_WORD_MAX_MM 0xFFFFu   /* mode 0F: largest range */
#define WORLD_WORD_NONE_MM 0x0000u  /* mode 0F: no surface within range */

/* Largest --max-range per unit, m. */
#define WORLD_MAX_RANGE_CM 81.82
#define WORLD_MAX_RANGE_MM 65.535

#define WORLD_MIRROR_HZ 75.0 /* mirror turns per second */

/* Passes (mirror turns) a scan of count values interlaces: 2 for more
 * than 181 values, else 1. */
unsigned world_scan_passes(unsigned count);

/* t_i above, s: the time of value i after value 0 of a count-value scan. */
double world_beam_time(unsigned i, unsigned count);

/* The mean of world_beam_time over the count values, s. */
double world_beam_mean_time(unsigned count);

/* Fills active (cleared first) with what the scanner at pose can see up
 * to max_range: the static primitives ahead of it and the movers. */
void world_scan_prepare(const wmap_t *static_map, const wmover_t *movers, size_t mover_count,
                        wpose_t pose, double max_range, wmap_t *active);

/* Ranges of the count beams (count = 180 / res_deg + 1) in metres;
 * INFINITY where nothing is hit. */
void world_scan_cast(const wmap_t *active, wpose_t pose, unsigned count, double res_deg,
                     double *ranges);

/* --timing lms: ranges of scan k (period s) of scenario sc over its
 * static map, value i cast from the scanner's pose and the movers at
 * k * period + (world_beam_time(i) - world_beam_mean_time(count)). The
 * static map is culled once for the scan (all directions, the radius
 * widened by the farthest beam pose) into active; movers go into
 * scratch beam by beam. Same ranges as casting every value on the whole
 * map up to max_range. */
void world_scan_cast_lms(const wscenario_t *sc, const wmap_t *static_map, unsigned k,
                         double period, unsigned count, double res_deg, double max_range,
                         wmap_t *active, wmap_t *scratch, double *ranges);

/* Beams of one scan that hit each mover: returns[j] (j < the scenario's
 * mover count, at most WORLD_MAX_MOVERS; cleared first) counts the beams
 * whose range (ranges, as cast for scan k by world_scan_cast or, with
 * lms_timing, world_scan_cast_lms) is within max_range and lies on mover
 * j at that beam's time and from that beam's pose. The same expressions
 * as the casts give the same doubles, so a beam's range equals the range
 * to the box it hit exactly. scratch is working storage. Returns the
 * number of movers. */
size_t world_scan_returns(const wscenario_t *sc, unsigned k, double period, unsigned count,
                          double res_deg, bool lms_timing, const double *ranges,
                          double max_range, wmap_t *scratch, unsigned *returns);

/* The value word of one beam: range (m, INFINITY for no hit) plus noise
 * (m), rounded to the nearest unit. A true range beyond max_range gives
 * the no-surface word of the unit; a noisy range is kept within
 * 1..the largest range of the unit. */
uint16_t world_range_word(double range, double noise, lms_unit_t unit, double max_range);

#endif /* LMSWORLD_SCAN_H */
