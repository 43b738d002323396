/* ego_scan.h - scan preparation: a range scan (ego_range.h) -> points in
 * the vehicle frame.
 *
 * One ego_scan_t holds a whole prepared scan: Cartesian points (x forward,
 * y left, metres, Q16.16) in the vehicle frame, in scan order, with the
 * segment structure the later stages need, and (filled by ego_tfit.h) a robust
 * tangent per point. Invalid beams and ranges outside [min_range,
 * max_range] give no point; the gap they leave breaks the segment.
 *
 * Segments: consecutive points belong to one segment unless
 *  - a value between them gave no point (a gap),
 *  - the range jumps by more than max(jump_min, jump_factor * r * dphi)
 *    (r the nearer range, dphi the beam step), or
 *  - the segment between them is an occlusion edge: seen from the scanner
 *    the segment is nearly parallel to the beams (the sharp-angle criterion:
 *    the angle at its far end is below occlusion_angle), so it joins two
 *    different surfaces rather than following one.
 * Points are numbered in scan order; flags[i] says what lies between point
 * i and point i + 1.
 *
 * All memory is the caller's; no allocation; bounded loops (one pass over
 * the beams). Pure function of its inputs.
 */
#ifndef EGO_SCAN_H
#define EGO_SCAN_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_config.h"
#include "ego_fx.h"
#include "ego_pose.h"
#include "ego_range.h"

/* flags[i]: the link from point i to point i + 1. */
#define EGO_LINK_BREAK 0x01u     /* not the same segment (any reason below) */
#define EGO_LINK_GAP 0x02u       /* beams without a point lie between them */
#define EGO_LINK_JUMP 0x04u      /* range jump */
#define EGO_LINK_OCCLUSION 0x08u /* occlusion edge (sharp angle) */
#define EGO_LINK_RISES 0x40u     /* with a break: point i + 1 lies farther from the
                                    sensor than point i */
/* flags[i], set by tfit: point i has a robust tangent. */
#define EGO_POINT_HAS_TANGENT 0x10u
/* flags[i], set by the preparation: point i lies on an object, a segment
 * no longer than EGO_OBJECT_EXTENT that stands in front of what the beams
 * beyond both its ends see (nearer than the next point there, or the
 * beams there gave none; not known at the first and last point, where a
 * wall may be cut short; a tie before the first point counts as in
 * front): the back of a vehicle, a person, a post. Such
 * things may be moving; the trust test of ego_cov_on_objects weighs them
 * apart (issue 17). */
#define EGO_POINT_OBJECT 0x20u
/* The longest object, m: the back of a truck (2.5 m) seen whole, with
 * room for the range noise; a facade is longer, a gap between parked cars
 * shorter. */
#define EGO_OBJECT_EXTENT FX_Q16_16_C(3.0)

typedef struct {
    uint16_t count;                      /* points, <= EGO_MAX_POINTS */
    uint16_t beams;                      /* beams the range scan had */
    fx_q16_16_t origin_x;                /* the sensor in the vehicle frame */
    fx_q16_16_t origin_y;
    fx_q16_16_t spacing_arm;             /* the points' RMS range times the beam
                                            spacing, m: how far a turn of one
                                            spacing moves them (ego_track.c) */
    fx_q16_16_t rms_range;               /* the points' RMS range, m: the lever of a
                                            turn (ego_cov_weakest) */
    fx_q16_16_t x[EGO_MAX_POINTS];       /* vehicle frame, metres */
    fx_q16_16_t y[EGO_MAX_POINTS];
    fx_bam32_t bearing[EGO_MAX_POINTS];  /* beam direction from the origin,
                                            vehicle frame; increases along
                                            the scan */
    uint8_t flags[EGO_MAX_POINTS];       /* EGO_LINK_* | EGO_POINT_* */
    /* Filled by ego_tfit_fit_scan (ego_tfit.h). */
    fx_bam32_t tangent[EGO_MAX_POINTS];  /* direction mod 180 deg: bit 31 is 0 */
} ego_scan_t;

/* The preparation thresholds. ego_prep_defaults() gives the values of
 * docs/estimator.md. */
typedef struct {
    fx_q16_16_t min_range;       /* shorter ranges give no point, m */
    fx_q16_16_t max_range;       /* longer ranges give no point, m */
    fx_q16_16_t jump_min;        /* range jump that always breaks, m */
    uint16_t jump_factor;        /* ... or jump_factor * r * dphi */
    fx_q2_30_t occlusion_sin;    /* sin of the occlusion angle */
    fx_bam32_t beam_spacing;     /* thin the beams to at least this spacing (0, the
                                    default: every beam; the bounded profile thins
                                    0.5- and 0.25-deg scans to 1 deg) */
} ego_prep_params_t;

void ego_prep_defaults(ego_prep_params_t *params);

typedef enum {
    EGO_PREP_OK = 0,
    EGO_PREP_ERR_ARG = -1,    /* NULL pointer */
    EGO_PREP_ERR_LAYOUT = -2  /* the range scan fails ego_range_check */
} ego_prep_status_t;

/* Prepares scan from a range scan, as measured at once. */
ego_prep_status_t ego_scan_prepare(const ego_range_scan_t *in, const ego_prep_params_t *params,
                                   ego_scan_t *scan);

/* The motion a scan is de-skewed with: the vehicle moved by motion (in
 * its frame at the start) over dt_us, at a constant rate. */
typedef struct {
    ego_pose_t motion;
    uint32_t dt_us; /* 0: no de-skewing */
} ego_skew_t;

/* Prepares scan from a range scan whose beams were measured at their own
 * times (ego_range.h): each point is moved to where the vehicle frame was
 * at the scan's time, by skew's motion scaled to its beam's offset from
 * it (the rotation exact, the translation and the sensor's offset to
 * first order in the turn). A point's bearing is then its direction from
 * the sensor at the scan's time, the points are in its order (an
 * interlaced scan's two passes, 0.4 m apart at 30 m/s, cross over), and
 * the links are tested on where the points are: a point that would land
 * more than EGO_SCAN_REORDER_MAX places back (a near one, from the other
 * pass) is left out. Without beam times, or skew NULL or dt_us 0:
 * ego_scan_prepare. */
#define EGO_SCAN_REORDER_MAX 8u /* 4 deg at 0.5 deg: 0.2 m of skew seen from 2.9 m */
ego_prep_status_t ego_scan_prepare_deskewed(const ego_range_scan_t *in, const ego_prep_params_t *params,
                                            const ego_skew_t *skew, ego_scan_t *scan);

/* True when points i and i + 1 (i + 1 < count) are in the same segment. */
static inline bool ego_scan_linked(const ego_scan_t *scan, uint16_t i)
{
    return (scan->flags[i] & EGO_LINK_BREAK) == 0u;
}

#endif /* EGO_SCAN_H */
