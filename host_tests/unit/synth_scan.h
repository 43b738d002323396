/* synth_scan.h - a tiny ray caster for estimator unit tests: walls as line
 * segments, a scanner pose, an LMS scan out (double maths, host only). The
 * full scenario generator is host_tests/world/. */
#ifndef SYNTH_SCAN_H
#define SYNTH_SCAN_H

#include "ego_range.h"
#include "lms_decode.h"

typedef struct {
    double x0, y0, x1, y1;
} synth_wall_t;

/* A 180-degree scan of count values (181 or 361) from the scanner at
 * (x, y) heading `heading` rad, in unit (mm ranges saturate at 8.182 m to
 * "beyond max"; cm at 81.82 m). Beams that hit nothing: beyond max. */
void synth_scan(const synth_wall_t *walls, unsigned nwalls, double x, double y, double heading,
                unsigned count, lms_unit_t unit, lms_scan_t *out);

/* A copy of lms through the LMS adapter with its defaults (firmware/
 * ego_lms.h: mode 00, no mount offset) but measured at once (as cast), as
 * a static range scan that the
 * next call overwrites; NULL when the adapter refuses it. */
const ego_range_scan_t *synth_range(const lms_scan_t *lms);

/* A room with a few angled features: 14 walls, about 16 x 10 m. */
extern const synth_wall_t synth_room[];
extern const unsigned synth_room_walls;

/* A corridor 3 m wide along x, from -200 to 200 m: nothing fixes x. */
extern const synth_wall_t synth_corridor[];
extern const unsigned synth_corridor_walls;

#endif /* SYNTH_SCAN_H */
