/* ego_itcp.h - ITCP: iterative tangent-weighted closest point (paper section
 * 5, eqs. 8-12), and plain ICP as a selectable mode.
 *
 * Each iteration matches every current point P (in the first run, with
 * max_points, a spread subset) moved by the pose guess to Q = R P + T, to
 * the closest point on the last scan's segments (eq. 8), then solves the
 * weighted closed form (eq. 12) for a new pose.
 *
 * Correspondences through the scan order, not all pairs: the last scan's
 * points are sorted by bearing from its scanner. Q's bearing finds its
 * place by binary search (in the iterations a bearing from a table, within
 * 0.022 deg, the cone below widened by as much; fx_atan2 wherever the
 * exact place matters: free space, the coarse search's probes); the search
 * then walks outwards along the scan
 * and stops on each side once a point's bearing leaves the cone that the
 * disc of the search radius around Q subtends (a segment between two
 * points outside the cone on the same side cannot reach the disc), or
 * after EGO_ITCP_MAX_WALK points.
 *
 * A match is kept when it lies within the search radius, which shrinks
 * from radius_start by radius_shrink per iteration down to radius_min, and
 * (ITCP with the gate on) when the current point's tangent, turned by
 * theta, is within `gate` of the tangent at the match (modulo 180 deg).
 * Segments that are breaks or occlusion edges are never matched; a point
 * without surface segments can be matched as a point.
 *
 * Weights (eq. 10): a match is on the main direction when its turned
 * tangent is within main_tolerance of main_direction; the n_main main
 * matches share half the weight and the n_non others the other half. With
 * lambda_g = m / (2 n_g) the weighted sums reduce to averages of the two
 * groups' own sums, which is how they are computed: per group, raw int64
 * sums in one pass, no match arrays (docs/fixed-point.md gives the bounds).
 * Plain ICP weighs every match equally (one group). An empty group leaves
 * the other alone.
 *
 * Iterations stop when the pose changes by less than converge_translation
 * and converge_rotation with the radius at its minimum, or after
 * max_iterations. A converged result is refined by a second run with the
 * radius fixed at radius_fine (beyond the paper: within radius_min, wrong
 * partners on nearby surfaces bias the pose towards no motion); it is kept
 * when it converges with at least half of the matches. hold_rotation keeps theta at the initial value (the
 * paper's translation-only first stage). Aperture: n_non / n_main below
 * aperture_ratio (a corridor: translation along the main direction is not
 * observable).
 */
#ifndef EGO_ITCP_H
#define EGO_ITCP_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_cov.h"
#include "ego_pose.h"
#include "ego_scan.h"
#include "ego_fx.h"
#include "ego_work.h"

/* Most last-scan points looked at on each side of a current point. */
#ifndef EGO_ITCP_MAX_WALK
#define EGO_ITCP_MAX_WALK 96u
#endif

typedef struct {
    bool weighted;                   /* true: ITCP weights (eq. 10); false: plain ICP */
    bool tangent_gate;               /* reject matches with inconsistent tangents */
    fx_bam32_t gate;                 /* default 25 deg */
    fx_bam32_t main_tolerance;       /* default 10 deg */
    fx_q16_16_t radius_start;        /* default 0.6 m */
    fx_q16_16_t radius_min;          /* default 0.15 m */
    fx_q16_16_t radius_fine;         /* after converging: a second run with only
                                        matches this close; default 0.05 m
                                        (>= radius_min: no second run) */
    fx_q2_30_t radius_shrink;        /* per iteration, default 0.75 */
    uint8_t max_iterations;          /* default 30 */
    uint8_t fine_iterations;         /* of the second run (0: max_iterations, the default) */
    fx_q16_16_t converge_translation;/* default 0.0001 m */
    fx_bam32_t converge_rotation;    /* default 0.001 deg */
    fx_q16_16_t inlier_distance;     /* for the inlier count, default 0.10 m */
    fx_q2_30_t aperture_ratio;       /* default 0.2 */
    uint16_t min_matches;            /* fewer: the registration fails; default 10 */
    uint16_t max_points;             /* the first run (shrinking radius) matches at most
                                        this many current points, evenly spread over
                                        the scan order (0: all, the default); the
                                        fine run and the statistics pass always match
                                        every point: coarse points first, every
                                        point last */
} itcp_params_t;

void ego_itcp_defaults(itcp_params_t *params);

/* The step between the current points the first run matches: 1, or with
 * max_points the smallest that takes at most max_points of count; the
 * first is stride / 2. (The fine run and the statistics pass: 1.) */
uint16_t ego_itcp_sample_stride(uint16_t count, uint16_t max_points);

typedef struct {
    ego_pose_t pose;
    uint8_t iterations;      /* closed-form solutions computed, both runs */
    bool converged;
    bool aperture;
    bool weak_rotation;      /* tracking: the scans barely tell the rotation */
    uint16_t matches;        /* in the last iteration */
    uint16_t n_main;
    uint16_t n_non_main;
    uint16_t inliers;        /* matches within inlier_distance at the final pose */
    uint16_t group_points[2];  /* current points on the main direction [0] and
                                  the others [1], matched or not */
    fx_q2_30_t group_fit[2];   /* their soft inlier share: mean over the group's points
                                  of max(0, 1 - d^2 / inlier_distance^2), 0..1 */
    fx_q16_16_t residual;    /* RMS match distance at the final pose, m */
    ego_cov_t cov;           /* of the pose (ego_cov.h; unknown until a registration
                                finished with enough matches) */
    ego_weak_t weak;         /* tracking: the direction the matches barely constrain
                                (ego_cov_weakest), if any */
} ego_itcp_result_t;

typedef enum {
    EGO_ITCP_OK = 0,
    EGO_ITCP_ERR_ARG = -1,
    EGO_ITCP_ERR_FEW_MATCHES = -2, /* fewer than min_matches: result holds the last pose */
    EGO_ITCP_ERR_UNFINISHED = -3   /* ego_itcp_run_result of a run not finished yet */
} ego_itcp_status_t;

/* The closed form on its own (for tests and the coarse search): matched
 * pairs (x, y) -> (u, v) accumulated per group. |coordinates| < 2^24
 * (256 m) and at most EGO_MAX_POINTS (<= 2^14) pairs keep every sum below 2^62. */
typedef struct {
    int64_t n;
    int64_t sx, sy, su, sv;
    int64_t sxu, sxv, syu, syv;
} ego_itcp_group_sums_t;

typedef struct {
    ego_itcp_group_sums_t group[2]; /* [0] on the main direction, [1] the others */
} ego_itcp_sums_t;

void ego_itcp_sums_clear(ego_itcp_sums_t *sums);
void ego_itcp_sums_add(ego_itcp_sums_t *sums, bool on_main, fx_q16_16_t x, fx_q16_16_t y, fx_q16_16_t u,
                   fx_q16_16_t v);

/* Eq. 12: the pose minimising the weighted squared distances, lambda by
 * eq. 10 when weighted, all equal otherwise; hold_theta keeps pose->theta
 * and solves the translation only. No pairs: *pose is left alone. */
void ego_itcp_solve(const ego_itcp_sums_t *sums, bool weighted, bool hold_theta, ego_pose_t *pose);

/* Squared distance (Q32.32) from (qx, qy) to the nearest surface of last
 * (segment, or a lone point) within radius, found through the scan order
 * like the matches: false when there is none. For the coarse search. */
bool ego_itcp_nearest(const ego_scan_t *last, fx_q16_16_t qx, fx_q16_16_t qy, fx_q16_16_t radius,
                  uint64_t *dist_sq);

/* Did the last scan see empty space more than margin beyond (qx, qy)
 * (its beams on both sides of that bearing reach further)? */
bool ego_itcp_seen_through(const ego_scan_t *last, fx_q16_16_t qx, fx_q16_16_t qy,
                       fx_q16_16_t margin);

/* ego_itcp_nearest and then, unless a surface lies closer than radius,
 * ego_itcp_seen_through, for one point at a time (its place in the scan order
 * found once, starting where the last point's was). *dist_sq as
 * ego_itcp_nearest's. For the coarse search: prepare once per last scan with
 * ego_itcp_prober_init. */
typedef enum {
    EGO_ITCP_PROBE_NOTHING = 0,     /* no surface closer than radius, no free space */
    EGO_ITCP_PROBE_SURFACE = 1,     /* a surface closer than radius: *dist_sq < radius^2 */
    EGO_ITCP_PROBE_SEEN_THROUGH = 2 /* none, and the last scan saw margin beyond the point */
} ego_itcp_probe_t;

typedef struct {
    /* Private. */
    const ego_scan_t *last;
    fx_bam32_t ref;
    fx_q16_16_t radius;
    fx_q16_16_t margin;
    uint64_t radius_sq;
    uint16_t hint;
    uint32_t units;
} ego_itcp_prober_t;

void ego_itcp_prober_init(ego_itcp_prober_t *p, const ego_scan_t *last, fx_q16_16_t radius,
                      fx_q16_16_t margin);
ego_itcp_probe_t ego_itcp_probe(ego_itcp_prober_t *p, fx_q16_16_t qx, fx_q16_16_t qy, uint64_t *dist_sq);
/* The work (ego_work.h units) of the probes since init or the last call;
 * at most EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK) per probe. */
uint32_t ego_itcp_prober_take_units(ego_itcp_prober_t *p);

/* Registers current against last from *initial. main_direction is the
 * dominant line direction in the last scan's frame (ego_hist_main_direction).
 * The whole run at once: ego_itcp_run_start, ego_itcp_run_step with an
 * unlimited meter, ego_itcp_run_result. */
ego_itcp_status_t ego_itcp_register(const ego_scan_t *last, const ego_scan_t *current,
                            fx_bam32_t main_direction, const ego_pose_t *initial,
                            bool hold_rotation, const itcp_params_t *params,
                            ego_itcp_result_t *result);

/* A registration that can be paused between any two steps, for a hard
 * per-scan work budget (ego_work.h). Its phases: the first run (iterations
 * with a shrinking radius, accelerated), the fine run (radius_fine), the
 * statistics pass at the final pose (free space too). Each phase is made
 * of matching passes, and each pass of steps:
 *   - one current point located and matched: it costs what its search
 *     counted (EGO_COST_MATCH_POINT, _STEP, _SEGMENT), at most
 *     EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK), which the meter must
 *     allow before the point is started;
 *   - after the pass's last point, one closing step of EGO_COST_SOLVE: the
 *     closed form and the convergence bookkeeping (iterations), or the
 *     result's arithmetic (statistics pass; done by ego_itcp_run_result);
 *     charged even when the pass had too few matches to solve with.
 * A pass keeps its sums in the run, so an interrupted pass goes on at its
 * next point. The counts are the same on every machine: a run gives the
 * same result and the same total spend however it is cut up.
 *
 * RAM: 328 bytes on the Cortex-M3 (336 on x86-64), 192 of them the
 * pass's sums; no per-point arrays. */
typedef struct {
    /* Private: what a matching pass has summed so far. */
    ego_itcp_sums_t sums;
    uint32_t inliers;
    uint32_t group_points[2];       /* current points per group, matched or not */
    uint64_t group_fit[2];          /* sum of (inlier_distance^2 - d^2), inliers only, Q32.32 */
    uint32_t group_seen_through[2]; /* points where the last scan saw empty space */
    uint64_t sum_sq;                /* of match distances, Q32.32 */
} ego_itcp_pass_t;

typedef struct {
    /* Private: a pose step as a 3-vector in metres (Q16.16, the rotation
     * as its arc at 8 m). */
    int64_t v[3];
} ego_itcp_step_t;

typedef struct {
    /* Private: everything ego_itcp_register keeps between passes. */
    const ego_scan_t *last;
    const ego_scan_t *current;
    const itcp_params_t *params;
    ego_itcp_pass_t pass;        /* the pass in progress, or the last one */
    ego_itcp_step_t last_step;   /* acceleration: the previous pose step */
    ego_itcp_step_t jump;        /* ... and the last jump */
    ego_pose_t pose;             /* the pose the pass matches at */
    ego_pose_t coarse_pose;      /* the first run's pose while the fine run tries */
    fx_q2_30_t sin_theta;        /* of pose.theta, for the pass */
    fx_q2_30_t cos_theta;
    fx_bam32_t ref;              /* middle bearing of the last scan */
    fx_bam32_t main_direction;
    fx_q16_16_t radius;          /* of the pass */
    uint32_t coarse_matches;     /* of the first run's last pass */
    uint16_t next_point;         /* the current point the pass takes next */
    uint16_t stride;             /* between the points of the pass */
    uint16_t hint;               /* where the next bearing search starts */
    uint16_t iterations;         /* closed-form solutions, both runs */
    uint8_t iteration;           /* of the run in progress */
    uint8_t max_iteration;       /* of the run in progress */
    uint8_t phase;
    int8_t status;               /* ego_itcp_status_t of the first run */
    bool hold_rotation;
    bool converged;              /* the first run */
    bool have_last_step;
    bool may_accelerate;
    bool jumped;
} ego_itcp_run_t;

/* Starts a registration of current against last from *initial (as
 * ego_itcp_register). The run keeps pointers to last, current and params:
 * they must stay where they are, unchanged, until the run is finished.
 * Invalid arguments or scans too small give a run that is already
 * finished (its result says why). */
void ego_itcp_run_start(ego_itcp_run_t *run, const ego_scan_t *last, const ego_scan_t *current,
                        fx_bam32_t main_direction, const ego_pose_t *initial, bool hold_rotation,
                        const itcp_params_t *params);

/* Works on the run until it is finished or the meter cannot pay for the
 * next step (see above); returns true when finished. Every step is
 * allowed by the meter before it starts, so work->used never exceeds
 * work->limit; a meter of at least EGO_COST_MATCH_POINT_MAX(
 * EGO_ITCP_MAX_WALK) units left always makes progress, one smaller may
 * make none. A finished run (or run/work NULL) returns true at once. */
bool ego_itcp_run_step(ego_itcp_run_t *run, ego_work_t *work);

/* The result of a finished run (what ego_itcp_register gives);
 * EGO_ITCP_ERR_UNFINISHED (result zeroed) before. */
ego_itcp_status_t ego_itcp_run_result(const ego_itcp_run_t *run, ego_itcp_result_t *result);

#endif /* EGO_ITCP_H */
