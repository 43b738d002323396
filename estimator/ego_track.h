/* ego_track.h - tracking: the cheap local registration of a scan against the
 * last one from a good prediction (issue 15's "track, then search").
 *
 * Each iteration moves every current point by the pose guess into the last
 * scan's frame, finds the last scan's segment on its bearing from the last
 * scanner (projective association: a short walk from the previous point's
 * place, no search of the neighbourhood) and measures its signed distance d
 * to the line through the segment's nearer end, along that end's tangent.
 * Matches with |d| under the radius enter the normal equations of the
 * point-to-line least squares (Gauss-Newton in (x, y, theta)), per group as
 * ITCP's eq. 10: points whose turned tangent lies along the main direction,
 * and the others, each group with half the weight. A small damping of the
 * diagonal keeps a direction the scans do not constrain (along a corridor)
 * at the prediction instead of letting it drift. Point-to-line converges in
 * a few iterations from a prediction good to centimetres, where ITCP's
 * point-to-point needs a dozen. The search (ego.h) registers its
 * candidates with it too: from a coarse search's pose it is as accurate as
 * ITCP on the real logs for a fortieth of the work (docs/estimator.md).
 *
 * The result is an ego_itcp_result_t, so the estimator judges both alike:
 * the inlier shares per group (max(0, 1 - d^2 / inlier_distance^2) per
 * point within the inlier distance, minus one for each point lying where
 * the last scan saw empty space, at the last pass), matches, RMS
 * distance, aperture.
 *
 * Resumable: a run works point by point within a work meter (ego_work.h)
 * and goes on at the next point on the next call; the scans and params must
 * stay where they are, unchanged, until it is finished.
 *
 * Fixed point: normals Q1.14, lever arms Q16.16 m, normal-equation sums in
 * int64 (each term below 2^45, at most 2^14 points), solved by Cramer's
 * rule on Q14 means (products below 2^56); docs/fixed-point.md.
 */
#ifndef EGO_TRACK_H
#define EGO_TRACK_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_itcp.h"
#include "ego_pose.h"
#include "ego_scan.h"
#include "ego_work.h"

typedef struct {
    fx_q16_16_t radius_start;         /* |d| accepted in the first iteration, m; 0.3 */
    fx_q16_16_t radius;               /* ... then a third of the last, down to this, m;
                                         0.05 */
    fx_q16_16_t radius_min;           /* tracking goes on down to 3 RMS distances of its
                                         last pass, not below this, m; 0.015 (below:
                                         1 cm range steps) */
    uint8_t max_iterations;           /* 10 */
    fx_q16_16_t converge_translation; /* a step this small has converged, m; 0.0002 */
    fx_bam32_t converge_rotation;     /* ... and this, 0.002 deg */
    fx_q16_16_t inlier_distance;      /* of the inlier shares, m; 0.10 (as ITCP's) */
    fx_bam32_t main_tolerance;        /* tangent this close to the main direction:
                                         main group; 10 deg (as ITCP's) */
    fx_q2_30_t aperture_ratio;        /* n_non / n_main below: aperture; 0.2 */
    fx_q2_30_t weak_share;            /* the weakest direction's share of the
                                         information below: weak (ego_cov_weakest);
                                         0.02 */
    fx_q2_30_t objects_share;         /* the share of the information along some
                                         translation that is not the objects' below:
                                         it rests on objects (ego_cov_on_objects);
                                         0.2 */
    uint16_t min_matches;             /* fewer: the registration fails; 10 */
    bool weighted;                    /* the groups weigh equally (eq. 10); false: every
                                         match alike, plain ICP for comparison; true */
} ego_track_params_t;

void ego_track_defaults(ego_track_params_t *params);

/* The work of a typical point of a pass (a short walk, one segment tried,
 * its normal known): what a caller sizes its points by, and what a run
 * checks its meter for before another pass. A pass whose points cost more
 * leaves the run unfinished. */
#define EGO_TRACK_TYPICAL_POINT \
    (EGO_COST_TRACK_POINT + 4u * EGO_COST_MATCH_STEP + EGO_COST_TRACK_FIT)

/* One group's sums (ego_track.c). Private. */
typedef struct {
    int64_t n;
    int64_t a[6]; /* J^T J: xx, xy, xt, yy, yt, tt */
    int64_t b[3]; /* J^T d */
    uint64_t sum_sq;
    uint64_t fit;
    uint32_t inliers;
    uint32_t seen_through; /* points where the last scan saw empty space */
    uint32_t points; /* current points in the group, matched or not */
} ego_track_sums_t;

typedef struct {
    /* Private. */
    const ego_scan_t *last;
    const ego_scan_t *current;
    const ego_track_params_t *params;
    fx_bam32_t main_direction;
    fx_bam32_t ref;   /* middle bearing of the last scan */
    ego_pose_t pose;
    fx_q2_30_t sn;
    fx_q2_30_t cs;
    fx_q16_16_t radius;
    uint16_t next;    /* next current point of the pass */
    uint16_t hint;    /* where the last point was found */
    uint8_t iteration;
    uint8_t stride;   /* every how many current points the pass matches */
    uint32_t pass_units; /* the work of the pass's points so far */
    bool tracking;
    bool finished;
    bool converged;
    bool failed;
    bool weak_rotation; /* the last pass's rotation was barely observed */
    bool cut;           /* ended by the meter before it settled (ego_track_resume) */
    bool wary;          /* a pass begins only if an eighth more than its estimate is
                           left (ego_track_wary) */
    bool weak_held;     /* the last motion had a weak direction: it stays weak until
                           its share is twice the threshold (ego_track_hold_weak) */
    bool objects_held;  /* the last motion rested on objects: its test's share is
                           doubled (ego_track_hold_objects) */
    uint8_t skip;       /* current points with these flags are left out:
                           EGO_POINT_OBJECT (ego_track_static_only) or none */
    ego_track_sums_t group[2];
    int32_t object_info[3]; /* the translation part (xx, xy, yy, Q14) of J J^T over
                               the matches of current points on objects
                               (EGO_POINT_OBJECT): at most 2^14 a match */
    /* The unit normals of the last scan's segments (a -> a + 1), Q1.14,
     * each computed at its first use in the run and kept: (0, 0) not yet. */
    int16_t normal[EGO_MAX_POINTS][2];
} ego_track_run_t;

/* tracking: a run from a prediction whose answer is due with this meter.
 * It ends where the meter cannot pay for another pass at the last one's
 * cost per point (a typical point's at least; converged when its last
 * full pass's step was small), or, failed, at a pass with under a quarter
 * of its points matched (the first within its radius, a later one within
 * the inlier distance); and its radius shrinks on to 3 RMS
 * distances of the last pass (radius_min at least): within centimetres of
 * the truth, what lies further is no longer noise but a corner cut by the
 * chord between two far beams (2-5 cm at 20-40 m), and those all pull the
 * same way. Otherwise (the search's registrations, whose starts are only
 * as good as a coarse step and whose statistics rank the candidates) it
 * waits for more work (ego_track_step returns false). */
void ego_track_start(ego_track_run_t *run, const ego_scan_t *last, const ego_scan_t *current,
                     fx_bam32_t main_direction, const ego_pose_t *initial, bool tracking,
                     const ego_track_params_t *params);

/* Works until finished (true) or the meter cannot pay for the next step:
 * a point (at its most) or a solution. */
bool ego_track_step(ego_track_run_t *run, ego_work_t *work);

/* A tracking run the meter ended before it settled (in its coarse passes,
 * ego_track_start, or still stepping) goes on with the next pass, within
 * the next meter, and true. False for any other run, which stays as it
 * is. */
bool ego_track_resume(ego_track_run_t *run);

/* Narrows a run just started to radius for its first pass (the next
 * passes narrow from there as usual). */
void ego_track_narrow(ego_track_run_t *run, fx_q16_16_t radius);

/* The run's passes each begin only where the meter holds an eighth more
 * than the pass's estimate (its last pass's mean per point): against a
 * scan held at a standstill (ego.c) a full pass's points, their
 * segments' normals new to the run, cost more than the half pass's, and
 * a pass that ran dry halfway left the standstill to a search. */
static inline void ego_track_wary(ego_track_run_t *run)
{
    run->wary = true;
}

/* The run starts from a motion whose weak direction was the prediction's:
 * a direction stays weak until its share of the information is twice the
 * threshold (hysteresis: a corridor's length measured by its noise on one
 * line, between two lines that said it was not measured, was 0.17 m off
 * with a millimetre's covariance). */
static inline void ego_track_hold_weak(ego_track_run_t *run)
{
    run->weak_held = true;
}

/* The run starts from a motion that rested on objects (ego_cov_on_objects
 * said so): the test's share is twice the threshold (hysteresis, as
 * ego_track_hold_weak). */
static inline void ego_track_hold_objects(ego_track_run_t *run)
{
    run->objects_held = true;
}

/* The run matches only the current points that are not on objects
 * (EGO_POINT_OBJECT): the static structure's own registration. */
static inline void ego_track_static_only(ego_track_run_t *run)
{
    run->skip = EGO_POINT_OBJECT;
}

/* The result of a finished run (EGO_ITCP_ERR_FEW_MATCHES: too few
 * matches, or the equations were singular; the pose is then the last). */
ego_itcp_status_t ego_track_result(const ego_track_run_t *run, ego_itcp_result_t *result);

/* The coarse search's probe along the bearing (ego_coarse.h), matched as
 * tracking matches a point: the last scan's segments at the bearing of
 * (qx, qy) from its origin and their neighbours, the distance to their
 * lines by the run's cached normals. A surface closer than sigma:
 * EGO_ITCP_PROBE_SURFACE, *dist_sq its square (Q32.32); none, and the last
 * scan's beams on both sides reach 2 sigma beyond the point:
 * EGO_ITCP_PROBE_SEEN_THROUGH. About a third of the work of ITCP's probe
 * (which searches every surface within sigma); *units is this probe's, at
 * most EGO_TRACK_PROBE_MAX. A run started with ego_track_probe_start
 * serves any number of probes against one last scan (it registers
 * nothing). */
#define EGO_TRACK_PROBE_MAX                                                                 \
    (EGO_COST_TRACK_PROBE + 32u * EGO_COST_MATCH_STEP +                                     \
     3u * (EGO_COST_TRACK_FIT + EGO_COST_TRACK_NORMAL) + EGO_COST_TRACK_NORMAL)

void ego_track_probe_start(ego_track_run_t *run, const ego_scan_t *last,
                           const ego_track_params_t *params);
ego_itcp_probe_t ego_track_probe(ego_track_run_t *run, fx_q16_16_t qx, fx_q16_16_t qy,
                                 fx_q16_16_t sigma, uint64_t *dist_sq, uint32_t *units);

#endif /* EGO_TRACK_H */
