/* ego_moving.h - moving clusters of a range scan, in fixed point: the
 * compact objects the firmware loop reports (issue 17 item 3; the host's
 * fuller detector in doubles is firmware/host/objects.h).
 *
 * After ego_process has measured a scan's motion, the scan is compared
 * with a reference scan 0.2-0.3 s older (EGO_MOVING_REF_MIN_US; one is
 * taken every EGO_MOVING_REF_EVERY_US, 0.1 s): at 75 Hz consecutive
 * scans are 13 ms apart, and a car keeping pace moves 5 cm in that time,
 * less than the range noise; over 0.2-0.3 s a pedestrian walks 0.28-0.42
 * m, a car 1-3 m. (An older reference sees slower bodies, but the
 * ego-motion's error grows with its age: 0.2-0.4 s doubled the false
 * objects of the busy streets at 181 values.) The references' poses are
 * chained from the estimator's motions; a line without a measured motion
 * (first, predicted, recovering, recovered; an interval of 0 or over
 * EGO_MOVING_MAX_DT_US) starts everything over.
 *
 * The chained motion's error moves the static world against a reference:
 * every margin below widens by twice its standard deviation at the
 * point's range, sqrt(sum var_xy) + r sqrt(sum var_theta) over the lines
 * since the reference (the covariance the estimator gives each line;
 * var_xy = cov_xx + cov_yy, but 0 on an aperture line, whose weak
 * direction is the prediction's and whose variance says nothing of it;
 * at most EGO_MOVING_MAX_SLACK, 2 m). A line whose motion has no
 * covariance to trust (flagged suspect or on objects, or a variance
 * saturated at 2 m^2 or 2 rad^2, or an aperture line slower than
 * EGO_MOVING_START_SPEED: a vehicle starting off along a corridor, whose
 * speed along it is the prediction's, a standstill's; stopgo's queue
 * driving off with us made 0.22 false objects a scan of the posts across
 * the street) starts the references over; the tracks
 * go on, predicted through it, and the hold may report a vehicle on it
 * (a variance saturates on measured lines too: an aperture's weak
 * direction on objects, stopgo's last lines; restarting the tracks there
 * cost stopgo at 361 values 91.1 -> 86.8 % of its vehicles). Without this the estimator's
 * errors made 0.4-1.3 false objects a scan on the busy streets at 181
 * values; dropping the references on every line with sigma over 1 cm
 * cost stopgo 40 % of its vehicles.
 *
 * Segments: neighbouring beams whose ranges differ by at most
 * EGO_MOVING_GAP (1 m), within EGO_MOVING_MAX_RANGE (35 m). A segment of
 * at least EGO_MOVING_MIN_POINTS (3) points whose ends are at most
 * EGO_MOVING_MAX_EXTENT (16 m) apart (walls are longer) is a candidate;
 * its points are evidence of motion when no reference point lies within
 * EGO_MOVING_NEAR (0.2 m, or the reference's beam spacing at the point's
 * range if more, widened by the slack below; looked for over the beams
 * that reach spans, at most EGO_MOVING_NEAR_BEAMS on either side) and
 * either
 *   - entered: the reference beams on both sides of the point's bearing
 *     reached EGO_MOVING_FREE_MARGIN (0.3 m) beyond it, or had no return
 *     (it stands where the sensor saw free space: a static surface newly
 *     revealed lies behind the old ranges, so it is never evidence), or
 *   - left behind: a reference point on one of those beams lay 0.15 m to
 *     EGO_MOVING_RECEDE (4 m) in front of it and is gone now (the current
 *     beams on both sides of its bearing reach 0.15 m beyond it, and no
 *     current point is near it): a body moving away from the sensor;
 *     unless a current point within EGO_MOVING_REVEAL_BEAMS (8) beams of
 *     it lies nearer it than half its distance to the point: then it more
 *     likely moved there (a walker stepping aside reveals the wall behind
 *     it, which is no body receding).
 * A candidate with at least two evidence points and at least 30 % of its
 * points evidence (or EGO_MOVING_EVIDENCE_MIN, 6: a long side sliding
 * along itself gives evidence only at its front) is a moving cluster: its
 * box is the bounding box of its points along its chord (end to end) and
 * across it; centre, length and width are the box's.
 *
 * Tracks (EGO_MOVING_TRACKS): each cluster goes to the nearest predicted
 * track (constant velocity over ground) within EGO_MOVING_GATE (2 m),
 * nearest pairs first; a cluster left over starts a track. A track is
 * reported from its EGO_MOVING_CONFIRM-th (3rd) sighting on, on the scans
 * it is seen in. Its velocity is a displacement from an anchor sighting
 * EGO_MOVING_VEL_MIN_US (0.1 s) or more before, over that time: of the
 * cluster's ends that were its own edges then and now (the neighbouring
 * beam outside reaches beyond, or has no return: a convex body's extreme
 * points move with it), their mean; else of the box centre (the centre
 * of the visible part slides while something cuts the body). The first
 * such measurement sets it, later ones move it a quarter of the way; the
 * anchor moves on after EGO_MOVING_VEL_WINDOW_US (0.3 s). A track
 * missed EGO_MOVING_MAX_MISSES (8) scans in a row is dropped; a cluster
 * that finds no free track takes the slot of the track missed longest,
 * or is dropped when every track was seen.
 *
 * Hold: a body sliding along itself whose front is out of view (an
 * oncoming car passing alongside) gives no evidence, and neither does a
 * car ahead pulling away slowly against a young reference. A confirmed
 * track of a vehicle (one of its moving clusters was
 * EGO_MOVING_HOLD_TRACK_LENGTH, 1.4 m, long: a car's back; not a
 * pedestrian, who walks along shop fronts) whose velocity, measured from
 * its ends, is at least EGO_MOVING_HOLD_MIN_SPEED (0.5 m/s), matched to no
 * moving cluster, takes the nearest other segment across its predicted
 * centre's bearing (at most two: a box centre lies within its segment's
 * bearings; no sweep over the scan), at least EGO_MOVING_HOLD_MIN_LENGTH
 * (1 m) long, whose box centre lies within EGO_MOVING_HOLD_GATE (1 m) of
 * that prediction, for at most
 * EGO_MOVING_MAX_HELD (150) scans in a row; on a static segment its
 * velocity falls below the hold speed, which ends the hold.
 *
 * Everything is kept in the current vehicle frame (turned by
 * each motion), so no world coordinate grows without bound.
 *
 * What the host's detector does and this does not: a second, older
 * reference for slow bodies, a wall revealed behind a walker reported
 * once the track has evidence of its own (here such a point is simply no
 * evidence), ends that were uncut over only part of the window. Measured
 * against it in docs/experiments.md ("Moving objects").
 *
 * Static memory: ego_moving_t (EGO_MOVING_REFS references of at most
 * EGO_MOVING_REF_POINTS beams, a longer scan decimated to fit; the
 * tracks), owned by the caller. Work per scan: bounded by the scan's
 * beams (each candidate point: a handful of binary searches over at most
 * EGO_MAX_BEAMS beams and at most ten sines), the clusters
 * (EGO_MOVING_CLUSTERS a scan, in scan order) and the tracks. No float.
 */
#ifndef EGO_MOVING_H
#define EGO_MOVING_H

#include <stdbool.h>
#include <stdint.h>

#include "ego.h"
#include "ego_range.h"

#define EGO_MOVING_REF_POINTS 192u
#define EGO_MOVING_REFS 3u
#define EGO_MOVING_TRACKS 8u
#define EGO_MOVING_CLUSTERS 16u
#define EGO_MOVING_MAX_OBJECTS EGO_MOVING_TRACKS

/* Times, us: the age a reference needs, and how often one is taken (with
 * three, the oldest is 0.2-0.3 s old). */
#define EGO_MOVING_REF_MIN_US 200000u
#define EGO_MOVING_REF_EVERY_US 100000u
#define EGO_MOVING_VEL_MIN_US 100000u
#define EGO_MOVING_VEL_WINDOW_US 300000u
/* A longer interval between scans starts everything over, as does a line
 * without a measured motion (and keeps the predictions' products in
 * range). */
#define EGO_MOVING_MAX_DT_US 1000000u
/* An aperture line (its motion along the corridor the prediction's) of a
 * vehicle slower than this starts the references over: starting off, it
 * may double its speed within the references' 0.2 s (ego.c's hold speed). */
#define EGO_MOVING_START_SPEED FX_Q16_16_C(0.75) /* m/s */
#define EGO_MOVING_CONFIRM 3u
#define EGO_MOVING_MAX_MISSES 8u
#define EGO_MOVING_MIN_POINTS 3u
#define EGO_MOVING_EVIDENCE_MIN 6u
#define EGO_MOVING_REVEAL_BEAMS 8u
/* Distances, Q16.16 m. */
#define EGO_MOVING_MAX_RANGE FX_Q16_16_C(35.0)
#define EGO_MOVING_GAP FX_Q16_16_C(1.0)
#define EGO_MOVING_MAX_EXTENT FX_Q16_16_C(16.0)
#define EGO_MOVING_NEAR FX_Q16_16_C(0.2)
#define EGO_MOVING_FREE_MARGIN FX_Q16_16_C(0.3)
#define EGO_MOVING_BEYOND FX_Q16_16_C(0.15)
#define EGO_MOVING_RECEDE FX_Q16_16_C(4.0)
#define EGO_MOVING_GATE FX_Q16_16_C(2.0)
#define EGO_MOVING_HOLD_GATE FX_Q16_16_C(1.0)
#define EGO_MOVING_HOLD_MIN_LENGTH FX_Q16_16_C(1.0)
#define EGO_MOVING_HOLD_TRACK_LENGTH FX_Q16_16_C(1.4)
#define EGO_MOVING_HOLD_MIN_SPEED FX_Q16_16_C(0.5) /* m/s */
#define EGO_MOVING_MAX_HELD 150u

/* The most the chained motion's uncertainty widens the margins, Q16.16 m. */
#define EGO_MOVING_MAX_SLACK FX_Q16_16_C(2.0)

/* Work units, each about a sine and a few products (150 instructions on
 * a Cortex-M3): a point tested for evidence, EGO_MOVING_UNITS_POINT (its
 * transform, bearing and lookup); each point a near test or a vanished
 * point's tests look at, one (the near tests span the beams the margin
 * reaches, at most EGO_MOVING_NEAR_BEAMS on either side); a point of a
 * box, one. A scan stops testing for evidence at EGO_MOVING_UNITS_PER_BEAM
 * units per beam of the scan (its remaining segments are not moving
 * clusters; the tracks and the hold go on), so its work is bounded on any
 * input (docs/firmware.md measures the instructions a unit costs). The
 * busy streets took at most 6.2 a beam (the platoon at 361 values), most
 * scans 1.5 to 4. */
#define EGO_MOVING_NEAR_BEAMS 16u
#define EGO_MOVING_UNITS_POINT 4u
/* The most one point's test costs: itself, a near test over the
 * reference, and two vanished points' tests (each: itself, a near test
 * over the scan, the reveal window). 144. */
#define EGO_MOVING_UNITS_TEST_MAX                                               \
    (EGO_MOVING_UNITS_POINT + (2u * EGO_MOVING_NEAR_BEAMS + 2u) +               \
     2u * (1u + (2u * EGO_MOVING_NEAR_BEAMS + 2u) + (2u * EGO_MOVING_REVEAL_BEAMS + 2u)))
#define EGO_MOVING_UNITS_PER_BEAM 8u

/* A velocity not known yet (the track is younger than
 * EGO_MOVING_VEL_MIN_US). */
#define EGO_MOVING_UNKNOWN INT16_MIN

/* One reported object, current vehicle frame: 16 bytes. Lengths in cm
 * and velocities in cm/s saturate at the int16/uint16 range (327 m,
 * 327 m/s). */
typedef struct {
    uint16_t id;       /* the track's, from 1, wrapping past 65535 to 1 */
    uint16_t points;   /* of the cluster */
    int16_t cx_cm;     /* box centre */
    int16_t cy_cm;
    uint16_t length_cm; /* along the cluster's chord */
    uint16_t width_cm;  /* across it */
    int16_t vx_cms;    /* over ground; EGO_MOVING_UNKNOWN: not known yet */
    int16_t vy_cms;
} ego_moving_object_t;

typedef struct {
    /* Private. */
    ego_pose_t pose;       /* the current vehicle frame in this reference's */
    fx_q16_16_t slack_xy;  /* the chained lines' translation deviations, summed, m */
    fx_q16_16_t slack_theta; /* and their rotation deviations, rad */
    uint64_t var_xy;
    uint64_t var_theta;
    uint32_t time_us;
    fx_bam32_t first;      /* bearing of point 0, vehicle frame */
    fx_q16_16_t origin_x;  /* the sensor's origin, vehicle frame */
    fx_q16_16_t origin_y;
    uint16_t count;
    uint16_t offset[EGO_MOVING_REF_POINTS];   /* bearing - first, 2^-16 turn */
    uint16_t range_cm[EGO_MOVING_REF_POINTS]; /* 0: no return */
} ego_moving_ref_t;

typedef struct {
    /* Private. */
    fx_q16_16_t x;         /* box centre last seen, predicted to now */
    fx_q16_16_t y;
    fx_q16_16_t vx;        /* m/s over ground (when known) */
    fx_q16_16_t vy;
    fx_q16_16_t anchor_x[3]; /* the anchor sighting's box centre, first and last point */
    fx_q16_16_t anchor_y[3];
    uint32_t anchor_age_us;
    bool anchor_uncut[3];  /* each end the body's own edge then */
    uint16_t id;
    fx_q16_16_t length;    /* the longest of its moving clusters */
    uint8_t hits;          /* saturating */
    uint8_t misses;
    uint8_t held;          /* scans in a row on a held segment (saturating) */
    bool from_ends;        /* the last velocity measured was its ends' */
    bool used;
    bool known;            /* the velocity */
    bool seen;             /* in this scan */
} ego_moving_track_t;

typedef struct {
    /* Private: ego_moving_reset, ego_moving_scan. */
    ego_moving_ref_t ref[EGO_MOVING_REFS];
    ego_moving_track_t track[EGO_MOVING_TRACKS];
    uint32_t time_us;      /* of the last scan */
    uint32_t units;        /* public: the last scan's work: its evidence tests stop
                              at EGO_MOVING_UNITS_PER_BEAM units a beam (the last
                              one may cross it by up to EGO_MOVING_UNITS_TEST_MAX),
                              plus a unit per point of each box */
    uint16_t next_id;
    uint8_t refs;          /* references held */
    uint8_t newest;        /* the slot of the newest */
} ego_moving_t;

/* Forgets everything (init; a gap in the stream). */
void ego_moving_reset(ego_moving_t *m);

/* One scan, after ego_process accepted it (it passed ego_range_check)
 * and gave out for it at time_us (the time it was given): writes the
 * confirmed objects seen in it to objects (at most cap) and returns how
 * many. Nothing (and everything starts over) when out carries no measured
 * motion. Reads scan and out only. */
uint8_t ego_moving_scan(ego_moving_t *m, const ego_range_scan_t *scan, uint32_t time_us,
                        const ego_output_t *out, ego_moving_object_t *objects, uint8_t cap);

#endif /* EGO_MOVING_H */
