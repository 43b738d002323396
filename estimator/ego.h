/* ego.h - the whole estimator: one range scan (ego_range.h) in, the
 * vehicle's ego-motion since the previous scan out (paper section 2.2, with the additions of
 * docs/estimator.md).
 *
 * Per scan:
 *  1. prepare the points (ego_scan.h) and their robust tangents (ego_tfit.h);
 *  2. build the current scan's angle histogram (ego_hist.h, HTAH by default)
 *     and correlate it with the last scan's: up to EGO_HIST_MAX_CANDIDATES
 *     rotation candidates, best first;
 *  3. for each candidate, best first: ITCP with the rotation held
 *     (translation only) from the predicted motion (the prior if given,
 *     else the last motion), then full ITCP (ego_itcp.h). When that is not
 *     good enough (not converged, or a group below accept_fraction, see
 *     below), a bounded coarse search of the translation and a small
 *     rotation correction (ego_coarse.h) around the prediction, then the same
 *     ITCP; without a prior, if still not good enough, the coarse search
 *     over the wide window. The prediction is skipped (wide window at once)
 *     when the last motion did not itself come out within trust_* of its
 *     prediction: between keyframes, or after a turn. The candidate with the
 *     largest balanced inlier share wins (a candidate replacing the prior's
 *     rotation needs prior_margin more); one with stop_fraction ends the
 *     search early.
 *     Inlier share: per current point max(0, 1 - d^2 / inlier_distance^2),
 *     averaged per group (tangent on the main direction, or not), and the
 *     two groups weighted equally as in eq. 10: in a corridor a pose that
 *     fits the walls but not the few door frames and end walls is wrong,
 *     however many wall points fit. A group under a fifth of the points is
 *     pooled with the other (a handful of points is noise, not evidence);
 *  4. the relative pose of this scan in the frame of the last, and the
 *     velocities pose / dT.
 * The prepared scans live in two slots of the caller's state that swap
 * roles each scan; nothing is copied.
 *
 * Failure is reported, not hidden: too few points, no usable histogram
 * correlation or a failed registration give a flag, and the output then
 * carries the last motion (scaled to this scan's dT) instead of a jump.
 * A time gap longer than max_gap_us, a reset or the first scan start over:
 * flag EGO_FLAG_FIRST, no motion.
 *
 * Static memory: ego_state_t is about 2 x (ego_scan_t + ego_hist_t); see
 * docs/estimator.md for the figures. Not reentrant per state.
 */
#ifndef EGO_H
#define EGO_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_coarse.h"
#include "ego_pose.h"
#include "ego_scan.h"
#include "ego_hist.h"
#include "ego_itcp.h"
#include "ego_tfit.h"

/* Output flags. */
#define EGO_FLAG_FIRST 0x01u           /* first scan, reset or gap: no motion */
#define EGO_FLAG_APERTURE 0x02u        /* n_non / n_main small: a corridor */
#define EGO_FLAG_NOT_CONVERGED 0x04u   /* ITCP hit its iteration cap */
#define EGO_FLAG_LOW_CORRELATION 0x08u /* histogram correlation below min */
#define EGO_FLAG_TOO_FEW_POINTS 0x10u  /* scan or matches too sparse: motion predicted */
#define EGO_FLAG_PREDICTED 0x20u       /* the output is the last motion, not a match */

typedef struct {
    ego_prep_params_t prep;
    ego_tfit_params_t tfit;
    ego_hist_params_t hist;
    itcp_params_t itcp;
    bool use_coarse;             /* coarse translation search before ITCP; default on */
    ego_coarse_params_t coarse;      /* its window is centred on the prediction */
    fx_q16_16_t coarse_window_first; /* window when no motion is known yet (first pair, or
                                        after a failed match), default 4 m ... */
    fx_q16_16_t coarse_step_first;   /* ... searched at this step, default 0.2 m */
    fx_q16_16_t coarse_window_wide;  /* window when the last motion did not predict the
                                        last scan, default 1.6 m (at the coarse step) */
    fx_q2_30_t accept_fraction;  /* ITCP from the prediction with at least this share of
                                    the points as inliers (and converged) needs no coarse
                                    search; default 0.6 */
    fx_q2_30_t stop_fraction;    /* a candidate this good ends the candidate loop;
                                    default 0.8 */
    uint16_t max_rotation_bins;  /* correlation search, default 225 (45 deg) */
    uint16_t merge_bins;         /* candidates closer merge, default 15 (3 deg) */
    fx_q2_30_t min_correlation;  /* below: EGO_FLAG_LOW_CORRELATION, default 0.3 */
    uint16_t min_points;         /* fewer: EGO_FLAG_TOO_FEW_POINTS, default 20 */
    uint32_t max_gap_us;         /* longer between scans: start over, default 1 s */
    fx_q16_16_t trust_translation; /* the last motion predicts the next only when it was */
    fx_bam32_t trust_rotation;     /* itself this close to its prediction; default 0.1 m,
                                      3 deg (otherwise: the wide search) */
    fx_q2_30_t prior_margin;       /* another rotation candidate replaces the prior's only
                                      with a balanced inlier share this much larger;
                                      default 0.1 */
    uint8_t sweep_steps;           /* without a prior, when no candidate fits: coarse search */
    fx_bam32_t sweep_step;         /* over rotations sweep_steps * sweep_step each side of
                                      the prediction; default 11 x 4 deg (0: off) */
    bool hold_first;               /* ITCP with the rotation held first, then solved as
                                      well (the paper's two stages); default on */
    uint8_t max_candidates;        /* rotation candidates registered at most (0: all) */
    bool prediction_first;         /* without a prior, a trusted prediction's rotation is
                                      tried first, as a prior's is; default off */
} ego_params_t;

void ego_defaults(ego_params_t *params);

/* The bounded profile, for a microcontroller that must keep up with the
 * scanner: ego_defaults with the work per scan capped by construction
 * (docs/firmware.md, "The bounded profile"): 0.5-deg scans thinned to
 * 1 deg, plain tangent fits at ITCP's points only, the angle histogram
 * searched +-5 deg (only when the last motion did not predict its scan),
 * one rotation candidate, no coarse search, ITCP without the held stage,
 * at most 6 + 4 iterations over at most 40 points. It tracks motions its
 * prediction (the last motion, or a prior) brings within its 0.15 m first
 * search radius: sensor-rate streams, not keyframes. */
void ego_defaults_bounded(ego_params_t *params);

typedef struct {
    /* Private. */
    ego_scan_t slot[2];
    ego_hist_t hist[2];
    uint8_t last;            /* slot of the last scan */
    bool have_last;
    uint32_t last_time_us;
    ego_pose_t motion;       /* last relative pose, for the prediction */
    uint32_t motion_dt_us;
    bool predictable;        /* the last motion came out close to its prediction */
} ego_state_t;

typedef struct {
    ego_pose_t pose;          /* this scan in the frame of the last one */
    uint32_t dt_us;           /* time since the last scan */
    fx_q16_16_t vx;           /* m/s, vehicle frame of the last scan */
    fx_q16_16_t vy;
    fx_q16_16_t omega;        /* rad/s */
    uint16_t flags;           /* EGO_FLAG_* */
    uint8_t iterations;       /* ITCP iterations of the chosen candidate */
    uint8_t candidates;       /* rotation candidates tried */
    uint16_t points;          /* prepared points of this scan */
    uint16_t matches;
    uint16_t n_main;
    uint16_t n_non_main;
    uint16_t inliers;
    fx_q16_16_t residual;     /* RMS match distance, m */
    fx_q2_30_t correlation;   /* histogram correlation of the chosen rotation */
} ego_output_t;

/* Starts over: the next scan is a first scan. */
void ego_reset(ego_state_t *state);

/* The stages of ego_process, for profiling where the work goes. Built with
 * EGO_PROFILE defined, ego_process calls ego_profile_stage (which the
 * platform provides) as each stage begins; the work between two calls
 * belongs to the first one's stage. Without EGO_PROFILE nothing is
 * called (the firmware's profile images use it: docs/firmware.md). */
typedef enum {
    EGO_STAGE_PREPARE = 0, /* polar -> points, segments */
    EGO_STAGE_TANGENTS,    /* robust tangents */
    EGO_STAGE_HISTOGRAM,   /* the tangent-angle histogram */
    EGO_STAGE_CORRELATE,   /* histogram correlation: rotation candidates */
    EGO_STAGE_REGISTER,    /* ITCP */
    EGO_STAGE_COARSE,      /* the coarse translation (and rotation) search */
    EGO_STAGE_OTHER,       /* the rest: choosing, prediction, bookkeeping */
    EGO_STAGE_COUNT
} ego_stage_t;

#if defined(EGO_PROFILE)
void ego_profile_stage(ego_stage_t stage);
#endif

typedef enum {
    EGO_OK = 0,
    EGO_ERR_ARG = -1,   /* NULL pointer */
    EGO_ERR_SCAN = -2   /* the range scan fails ego_range_check: state unchanged */
} ego_status_t;

/* Processes one scan taken at time_us (a free-running microsecond clock;
 * wrap-around is fine). */
ego_status_t ego_process(ego_state_t *state, const ego_params_t *params, const ego_range_scan_t *scan,
                         uint32_t time_us, ego_output_t *out);

/* The same with an optional motion prior for this scan (for example wheel
 * odometry: the pose of this scan in the frame of the last one), or NULL.
 * A prior replaces the prediction from the last motion: its rotation is
 * tried first among the rotation candidates and its translation centres
 * the searches. It is only a starting point: the histogram's candidates
 * are still tried, and the candidate with the most inliers wins, so a bad
 * prior cannot override a good match. When matching fails, the output is
 * the prior (flag EGO_FLAG_PREDICTED). */
ego_status_t ego_process_with_prior(ego_state_t *state, const ego_params_t *params,
                                    const ego_range_scan_t *scan, uint32_t time_us,
                                    const ego_pose_t *prior, ego_output_t *out);

#endif /* EGO_H */
