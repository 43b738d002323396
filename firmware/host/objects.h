/* objects.h - moving objects in a replayed scan stream (host only: the
 * output of `lmsego replay --objects FILE`, issue 17 item 3). Doubles and
 * libm are fine here; nothing of this runs on the target.
 *
 * Per scan with a measured motion the scans are chained into a local
 * world frame (the integrated ego-motion, reset whenever a line claims no
 * measured motion). The current scan is compared with a reference scan
 * OBJ_REF_S (0.2 s) or more older: at 75 Hz consecutive scans are 13 ms
 * apart, and a car keeping pace moves 5 cm in that time, less than the
 * range noise; over 0.2 s a pedestrian walks 0.28 m, a car 1-4 m.
 *
 * A current point (within OBJ_MAX_RANGE_M) is evidence of motion when no
 * surface of the reference scan lies within OBJ_NEAR_M, or one beam
 * spacing at its range if more (0.52 m at 30 m at 1 deg: a far surface's
 * points land that far apart from scan to scan), of it (the reference's
 * points and the segments between neighbouring beams that are not a
 * depth jump) and either
 *   - entered: the reference beams on both sides of its bearing reached
 *     more than OBJ_FREE_MARGIN_M beyond it (it stands where the sensor
 *     saw free space: a static surface newly revealed lies behind the old
 *     ranges instead, so it is never evidence), or
 *   - left behind: a reference point on a neighbouring beam lay 0.15 to
 *     OBJ_RECEDE_M in front of it and is gone now (the current beam at
 *     its bearing reaches beyond it, and no current surface is near it):
 *     a body moving away from the sensor.
 * The scan is cut into segments (neighbouring beams with ranges no more
 * than OBJ_GAP_M apart); a segment of at least OBJ_MIN_POINTS points,
 * no longer than OBJ_MAX_EXTENT_M (walls are longer), with at least two
 * evidence points and at least OBJ_EVIDENCE_SHARE of its points evidence
 * (or OBJ_EVIDENCE_MIN: a long side sliding along itself gives evidence
 * only at its front), is a moving cluster. Its centre is the centre of the bounding box of
 * its points along their principal axes, and its length and width that
 * box's sides (only the visible sides: a car seen from behind is as long
 * as the part of its side the beams reach).
 *
 * Slow bodies: a pedestrian walking 1-1.5 m/s moves 0.2-0.3 m in
 * OBJ_REF_S, at the thresholds above, and was found about half the time.
 * A segment that is not a moving cluster, at most OBJ_SLOW_MAX_M long (a
 * person, not a car: vehicle rows stay as they were) and of at least
 * OBJ_SLOW_MIN_POINTS points (a 3-point piece of a facade newly seen
 * at a grazing angle is the usual impostor), is checked again against a
 * reference OBJ_SLOW_REF_S back, where such a body has moved twice as far.
 * There a body receding counts only up to OBJ_SLOW_MAX_SPEED times that
 * age (faster bodies are caught at OBJ_REF_S already): behind a person
 * crossing the line of sight a wall 1-2 m further back is revealed, and
 * that is no body receding. Such a slow cluster continues a track but
 * starts none: the longer reference doubles the ego-motion's error too
 * (stopgo's estimate a few cm a scan short made posts move, 31 false
 * reports in a row), and a real walker gives evidence against OBJ_REF_S
 * now and then.
 *
 * Revealed, not receding: a wall behind a walker is newly seen when the
 * walker steps aside, and by the receding rule it seemed a body that had
 * moved back to it (the pedestrians' street's false objects, 0.08-0.11 a
 * scan, all such tracks). When some current point outside the segment
 * lies nearer the vanished reference point than OBJ_REVEAL_SHARE of its
 * distance to the segment's point, what stood there more likely moved to
 * that body: the evidence still makes the cluster moving (it may continue
 * or start a track), but a track is reported, or holds a segment, only
 * once one of its clusters had enough evidence of its own (entered free
 * space, or receded with nothing nearer), against either reference.
 *
 * Tracks: each cluster is associated with the nearest predicted track
 * (constant velocity in the world frame) within OBJ_GATE_M, greedily by
 * distance; an unmatched cluster starts a track with a new id. A track
 * is reported from its OBJ_CONFIRM-th cluster on; its velocity is a
 * least-squares slope over the last OBJ_VEL_WINDOW_S (at least
 * OBJ_VEL_MIN_S of sightings, else unknown: NaN), turned into the current
 * vehicle frame: the velocity over ground, as lmsworld's truth gives it.
 * The slope is that of the cluster's ends where they are the body's own
 * silhouette (the extreme bearings of a convex body are its corners, which
 * move with it) throughout the window: the mean of both ends' slopes, or
 * the one end's; else, of the ends over the sightings where they were
 * uncut (a car coming out from behind one thing and going behind the next
 * is cut at one end, then at the other; by its centre it seemed to stand,
 * and the hold let go: most of the crossing street's misses); else of the
 * box centre. (The centre of the visible part slides when the field
 * of view or an occluder cuts the body: a truck overtaking alongside grows
 * into view at the edge of the field.) An end uncut throughout comes first:
 * a side seen at a grazing angle breaks where its points lie more than
 * OBJ_GAP_M apart, an end that looks uncut now and then but is no corner.
 * A track not seen for OBJ_MAX_MISSES scans is dropped.
 *
 * Hold: a body sliding along itself whose front is out of view (an
 * oncoming car passing alongside) gives no evidence, and neither does a
 * car ahead pulling away at under 1.5 m/s (0.3 m in 0.2 s, under the
 * margins); a confirmed track of a vehicle (a moving cluster of it was
 * OBJ_HOLD_TRACK_LENGTH_M long, as a car's back is: not a pedestrian, who
 * walks along shop fronts whose pieces it would hold on to) whose speed,
 * from an uncut end (a centre sliding out of the field of view makes a
 * static wall seem to move), is at least OBJ_HOLD_MIN_SPEED, matched to no
 * moving cluster, takes the nearest other segment at least OBJ_HOLD_MIN_LENGTH_M
 * long within OBJ_HOLD_GATE_M of its prediction, for at most OBJ_MAX_HELD scans in a row. On a static
 * segment its velocity falls below the hold speed within a window, which
 * ends the hold.
 *
 * Memory: static, in obj_tracker_t (about 0.59 MB: OBJ_HISTORY scans of
 * OBJ_MAX_BEAMS ranges, OBJ_MAX_TRACKS tracks of OBJ_TRACK_POINTS
 * sightings), plus 24 KB of segments (OBJ_MAX_SEGMENTS a scan) static in
 * obj_scan: one tracker at a time, not reentrant. At most OBJ_MAX_OBJECTS
 * objects a scan are reported, OBJ_MAX_TRACKS tracked (more are dropped). */
#ifndef LMSEGO_OBJECTS_H
#define LMSEGO_OBJECTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define OBJ_MAX_BEAMS 720u
#define OBJ_HISTORY 80u     /* scans kept: OBJ_SLOW_REF_S at up to 190 Hz */
#define OBJ_MAX_OBJECTS 64u
#define OBJ_MAX_TRACKS 64u
#define OBJ_TRACK_POINTS 32u

#define OBJ_REF_S 0.2
#define OBJ_SLOW_REF_S 0.4      /* s: 1 m/s moves 0.4 m, beyond both margins */
#define OBJ_SLOW_MAX_M 1.0      /* m: a person's box, its diagonal 0.7 m */
#define OBJ_SLOW_MIN_POINTS 4u  /* one more than OBJ_MIN_POINTS */
#define OBJ_SLOW_MAX_SPEED 2.5  /* m/s: faster is evidence at OBJ_REF_S */
#define OBJ_REVEAL_SHARE 0.5    /* a body nearer than half the way back took it */
#define OBJ_MAX_RANGE_M 35.0
#define OBJ_NEAR_M 0.2
#define OBJ_FREE_MARGIN_M 0.3
#define OBJ_RECEDE_M 4.0
#define OBJ_GAP_M 1.0
#define OBJ_MIN_POINTS 3u
#define OBJ_MAX_EXTENT_M 16.0
#define OBJ_EVIDENCE_SHARE 0.3
#define OBJ_EVIDENCE_MIN 6u
#define OBJ_GATE_M 2.0
#define OBJ_CONFIRM 3u
#define OBJ_VEL_WINDOW_S 0.3
#define OBJ_VEL_MIN_S 0.1
#define OBJ_MAX_MISSES 8u
#define OBJ_MAX_SEGMENTS 256u
#define OBJ_HOLD_GATE_M 1.0
#define OBJ_HOLD_MIN_SPEED 0.5
#define OBJ_HOLD_MIN_LENGTH_M 1.0
#define OBJ_HOLD_TRACK_LENGTH_M 1.4
#define OBJ_MAX_HELD 150u

/* The header line of `lmsego replay --objects`. */
#define OBJ_CSV_HEADER "scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points\n"

/* One scan: count beams at bearings first_bearing + k * bearing_step (rad,
 * vehicle frame, increasing), from the sensor's origin (m, vehicle
 * frame); range[k] in m, 0 for no return. */
typedef struct {
    uint16_t count;
    double first_bearing;
    double bearing_step;
    double origin_x;
    double origin_y;
    const double *range;
} obj_scan_t;

/* One reported object, in the current vehicle frame. */
typedef struct {
    double cx, cy;        /* m */
    double length, width; /* m */
    double vx, vy;        /* m/s over ground; NaN: not known yet */
    /* Private: the cluster's first and last points (world frame) and
     * whether each is the body's own silhouette edge (not cut by the
     * field of view or by something in front). */
    double end[2][2];
    uint32_t id;
    uint16_t points;
    bool end_ok[2];
    bool moving; /* a moving cluster (else a segment a track holds) */
    bool slow;   /* moving against the slow reference only */
    bool proven; /* moving by more than what others revealed (objects.h) */
} obj_object_t;

typedef struct {
    /* Private. */
    double time_s;
    double pose[3];        /* x, y, theta of the vehicle in the world frame */
    uint16_t count;
    double first_bearing, bearing_step, origin_x, origin_y;
    double range[OBJ_MAX_BEAMS];
} obj_frame_t;

typedef struct {
    uint32_t id;
    uint32_t hits;
    uint32_t misses;
    uint32_t held;         /* scans in a row on a segment without evidence */
    bool proven;           /* a cluster of it was proven moving: reported */
    double length;         /* the longest of its moving clusters, m */
    uint32_t n;            /* centres kept, at most OBJ_TRACK_POINTS */
    double t[OBJ_TRACK_POINTS];
    double x[OBJ_TRACK_POINTS]; /* world frame, oldest first */
    double y[OBJ_TRACK_POINTS];
    double ex[2][OBJ_TRACK_POINTS]; /* the cluster's ends, world frame */
    double ey[2][OBJ_TRACK_POINTS];
    bool ok[2][OBJ_TRACK_POINTS];
} obj_track_t;

typedef struct {
    /* Private: obj_init, obj_scan. */
    obj_frame_t frames[OBJ_HISTORY]; /* ring */
    uint32_t newest;
    uint32_t frames_used;
    uint32_t last_scan;
    obj_track_t tracks[OBJ_MAX_TRACKS];
    uint32_t tracks_used;
    uint32_t next_id;
} obj_tracker_t;

void obj_init(obj_tracker_t *t);

/* Scan number `scan` at time_s (s) with the motion since the previous
 * scan: its pose (dx, dy m, dtheta rad) in the previous scan's frame,
 * `measured` false when the line claims no measured motion (first scan,
 * predicted, recovering, recovered: the history starts over here). Fills
 * out (cap entries) with the confirmed objects of this scan; returns how
 * many. */
size_t obj_scan(obj_tracker_t *t, uint32_t scan, double time_s, bool measured, double dx,
                double dy, double dtheta, const obj_scan_t *in, obj_object_t *out, size_t cap);

#endif /* LMSEGO_OBJECTS_H */
