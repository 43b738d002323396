/* ego.h - the whole estimator: one range scan (ego_range.h) in, the
 * vehicle's ego-motion since the previous scan out (paper section 2.2, with
 * the additions of docs/estimator.md), within a hard work budget per scan.
 *
 * Per scan, every step charged to the scan's work meter (ego_work.h), whose
 * limit is the scan interval times work_per_s:
 *  1. prepare the points (ego_scan.h), a chord tangent per point
 *     (ego_tfit.h) and the AH histogram, for the main direction;
 *  2. track (ego_track.h) from the prediction (a prior, or the last motion
 *     scaled) over scans at most 0.2 s apart: it stands when converged with
 *     at least accept_fraction of each group as inliers, or close to a
 *     trusted prediction with half that share over both groups. A failed
 *     tracking is tried again from the turn that best aligns the two
 *     scans' direction histograms (ego_hist_turn_guess), then from the
 *     shift along the direction of travel that best aligns the two scans'
 *     projections on it (ego_project_along: a speed the prediction
 *     missed). Without a prediction, a start that fits loosely answers
 *     when the along start's shift agrees with it, or when a start 0.25 m
 *     ahead of it comes back to it. The last start,
 *     when the budget cuts it before a pass over
 *     every point, goes on in the next scan's budget (the scan is
 *     recovering); its answer is a tracked motion. Along a corridor
 *     tracked with nothing to predict the motion along it, the motion
 *     stays unknown;
 *  3. otherwise search, anytime, against the last scan: robust tangents
 *     and HTAH for both scans, the histogram correlation's rotation
 *     candidates, for each candidate the tracking registration from the
 *     prediction, then the coarse translation search (ego_coarse.h) over
 *     the wide window (the first window when no motion is known; around a
 *     prior its small window), ranked by projections (ego_project.h), and
 *     the registration from its best; a rotation sweep when no candidate
 *     fits even loosely. The candidate with the largest balanced inlier
 *     share wins (a candidate replacing the prior's rotation needs
 *     prior_margin more). When the scan's budget ends, a best with half
 *     the accept share answers (anytime).
 *     Inlier share: per current point max(0, 1 - d^2 / inlier_distance^2),
 *     averaged per group (tangent on the main direction, or not), and the
 *     two groups weighted equally as in eq. 10. A group under a fifth of
 *     the points is pooled with the other.
 *     The search works in steps; when the scan's budget ends first, it
 *     goes on in the next scans' budgets against the same two scans. The
 *     scans in between are not prepared: they claim no motion (flag
 *     EGO_FLAG_RECOVERING). When it ends, the output is the motion from
 *     the last trusted scan to the scan the search started from (flag
 *     EGO_FLAG_RECOVERED, dt_us the time between them), and the next scan
 *     is tracked against that one (over the long interval, from the
 *     search's motion, then from the other starts and, last, from the
 *     motion before the search; when all fail, the prediction bridges
 *     it, flag EGO_FLAG_PREDICTED): summed, the poses leave no hole. A
 *     search that found nothing leaves the next one its first window
 *     (coarse_window_first). A search still
 *     running after max_search_scans starts over. Under a small budget the
 *     search is light (ego.c, docs/estimator.md "The work budget").
 * A scan whose preparation does not fit its budget is skipped in the same
 * way (EGO_FLAG_RECOVERING, no motion; the next motion spans it).
 *
 * The prepared scans live in two slots of the caller's state that swap
 * roles each scan; nothing is copied.
 *
 * Failure is reported, not hidden: too few points, no usable histogram
 * correlation or a failed registration give a flag, and the output then
 * carries the prediction instead of a jump. The first scan, a reset and
 * a scan at the time of the last one start over: flag EGO_FLAG_FIRST, no
 * motion. A long interval is not a gap: it only allows more work.
 *
 * Static memory: ego_state_t holds two prepared scans, two histograms and
 * the search in progress; see docs/estimator.md for the figures. Not
 * reentrant per state.
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
#include "ego_track.h"
#include "ego_work.h"

/* Output flags. */
#define EGO_FLAG_FIRST 0x01u           /* first scan, reset or gap: no motion */
#define EGO_FLAG_APERTURE 0x02u        /* n_non / n_main small: a corridor */
#define EGO_FLAG_NOT_CONVERGED 0x04u   /* the registration hit its iteration cap or budget */
#define EGO_FLAG_LOW_CORRELATION 0x08u /* histogram correlation below min */
#define EGO_FLAG_TOO_FEW_POINTS 0x10u  /* scan or matches too sparse: motion predicted */
#define EGO_FLAG_PREDICTED 0x20u       /* the output is the last motion, not a match */
#define EGO_FLAG_RECOVERING 0x40u      /* a search is running (or the scan did not fit its
                                          budget): no motion claimed, a later line covers it */
#define EGO_FLAG_RECOVERED 0x80u       /* the search ended: the motion from the last trusted
                                          scan to the scan it started from (dt_us apart) */
#define EGO_FLAG_WEAK_ROTATION 0x100u /* every surface faces the scanner (a ring around
                                          it): the rotation is not measured */
#define EGO_FLAG_WEAK_TRANSLATION 0x200u /* the matches barely constrain a translation (a
                                             corridor's length): the motion along it is
                                             the prediction's; the covariance's largest
                                             axis says which */
#define EGO_FLAG_WEAK_COUPLED 0x400u     /* ... a translation with a turn (sliding along a
                                             ring seen off its centre while turning) */
#define EGO_FLAG_SUSPECT 0x800u          /* the match may be wrong: its velocity is
                                             beyond the gate of the dynamics filter (a
                                             vehicle's acceleration, ego_config.h) and no
                                             measured line has come back within it since,
                                             or it is faster than any vehicle
                                             (EGO_MAX_SPEED), or a search's answer fits
                                             under half the scan (under 0.7 with a turn
                                             no histogram proposed) */
#define EGO_FLAG_ON_OBJECTS 0x1000u      /* the translation along a direction rests on
                                             objects that may be moving: short segments
                                             standing in front (the backs of vehicles,
                                             people, posts) give nearly all of its
                                             information (ego_cov_on_objects); measured,
                                             1 m^2 more variance in x and in y */

typedef struct {
    ego_prep_params_t prep;
    ego_tfit_params_t tfit;      /* the search's robust tangents (tracking fits plainly) */
    ego_hist_params_t hist;      /* the search's histogram (tracking's main direction: AH) */
    ego_track_params_t track;    /* tracking: point-to-line from the prediction */
    ego_coarse_params_t coarse;  /* its window is centred on the prediction */
    fx_q16_16_t coarse_window_first; /* window when no motion is known yet, default 4 m */
    fx_q16_16_t coarse_window_wide;  /* window when the prediction did not hold, 1.6 m */
    fx_q2_30_t accept_fraction;  /* converged with at least this share of each group as
                                    inliers: good enough, no more searching; 0.6 */
    fx_q2_30_t stop_fraction;    /* a candidate this good ends the candidate loop; 0.8 */
    uint16_t max_rotation_bins;  /* correlation search, default 225 (45 deg) */
    uint16_t merge_bins;         /* candidates closer merge, default 15 (3 deg) */
    fx_q2_30_t min_correlation;  /* below: EGO_FLAG_LOW_CORRELATION, default 0.3 */
    uint16_t min_points;         /* fewer: EGO_FLAG_TOO_FEW_POINTS, default 20 */
    fx_q16_16_t trust_translation; /* the last motion predicts the next only when it was */
    fx_bam32_t trust_rotation;     /* itself this close to its prediction; 0.1 m, 3 deg
                                      (the distance times the horizon capped at 32 768 m) */
    fx_q2_30_t prior_margin;       /* another rotation candidate replaces the prior's only
                                      with a balanced inlier share this much larger; 0.1 */
    uint8_t sweep_steps;           /* without a prior, when no candidate fits: coarse search */
    fx_bam32_t sweep_step;         /* over rotations sweep_steps * sweep_step each side of
                                      the prediction, then halfway between; default
                                      7 x 6 deg (0: off) */
    uint32_t work_per_s;           /* the budget of a scan: this many work units
                                      (ego_work.h) per second of its interval; 0:
                                      unlimited (offline analysis) */
    uint32_t work_min;             /* and at least this many units */
    uint8_t max_search_scans;      /* a search not done after this many scans starts over */
} ego_params_t;

/* The default budget follows the time a scan leaves until the next one
 * (issue 15): 35.62 M units per second of scan interval, 950 k for a
 * 361-value scan at 37.5 Hz, and at least 550 k, what a 181-value scan at
 * 75 Hz gets; each leaves the firmware loop (framing, decoding, the output
 * line: under 50 k) room within 1.0 M and 0.6 M Cortex-M3 instructions
 * (docs/firmware.md). A scan 0.4 s after the last may spend 14.2 M, one
 * of a keyframe log 2.92 s after it 104 M. */
#define EGO_DEFAULT_WORK_PER_S 35620000u
#define EGO_DEFAULT_WORK_MIN 550000u

/* The defaults, unbounded (work_per_s 0): every scan gets the work it
 * needs, tracked when it can be, searched when not (offline analysis, and
 * keyframe logs, whose searches still need more than a sensor-rate budget
 * gives: docs/estimator.md, "The work budget"). */
void ego_defaults(ego_params_t *params);

/* The budget on top of ego_defaults (work_per_s EGO_DEFAULT_WORK_PER_S,
 * work_min EGO_DEFAULT_WORK_MIN): what the
 * live core runs (ego_live_defaults). Every scan keeps its budget; tracked
 * scans keep every beam; a search that needs more runs over the next
 * scans (EGO_FLAG_RECOVERING, then EGO_FLAG_RECOVERED). */
void ego_budget_defaults(ego_params_t *params);

/* The search in progress (ego.c). Private. */
typedef struct {
    bool active;
    bool light;              /* under a budget: no refinement, tracking registrations */
    bool stage_tracked;      /* the unfinished tracking stood: that is the answer */
    uint8_t stage;
    uint8_t step;            /* within a candidate's attempt */
    uint8_t scans;           /* scans it has worked in */
    uint16_t cursor;         /* point of the stage */
    uint32_t time_us;        /* of the scan it started from */
    uint32_t dt_us;          /* from the last trusted scan to it */
    ego_pose_t predicted;
    ego_pose_t track_predicted; /* what the unfinished tracking is judged against:
                                   its start's prediction (a turned start's turn) */
    bool have_prior;
    bool have_prediction;
    bool known_motion;
    fx_bam32_t main_direction;
    uint8_t n;               /* rotation candidates */
    uint8_t k;               /* the candidate being tried */
    uint8_t pass;            /* its coarse passes: next, end */
    uint8_t pass_end;
    uint8_t tried;
    uint8_t sweeps;          /* rotation sweeps run: the coarse one, then the one between */
    uint8_t sweep_scans;     /* the scan (of scans) the last sweep started in ... */
    uint64_t sweep_mark;     /* ... and the meter's count then */
    uint8_t best_k;
    uint16_t flags;
    fx_bam32_t rotation[EGO_HIST_MAX_CANDIDATES + 2u];
    fx_q2_30_t correlation[EGO_HIST_MAX_CANDIDATES + 2u];
    ego_pose_t start;        /* of the attempt */
    ego_coarse_params_t cp;  /* its coarse search, if any */
    bool with_coarse;
    bool static_only;        /* the attempt leaves the points on objects out */
    bool best_static;        /* the best is such an attempt's */
    ego_itcp_status_t attempt_status;
    ego_itcp_result_t attempt;
    ego_itcp_status_t candidate_status;
    ego_itcp_result_t candidate;
    ego_itcp_status_t best_status;
    ego_itcp_result_t best;
    union { /* one at a time: the correlation, then the candidates' searches */
        ego_hist_correlation_t correlation_run;
        ego_coarse_run_t coarse;
    };
} ego_search_t;

/* The dynamics check's reference (ego.c, judge_dynamics): the velocity of
 * the translation, filtered over the lines that passed the check. */
typedef struct {
    fx_q16_16_t vx;   /* m/s, in the frame of the last scan of its last line */
    fx_q16_16_t vy;
    uint32_t var;     /* its variance, x and y together, (m/s)^2 in Q16.16 */
    uint32_t time_us; /* of the scan its last line ended at */
} ego_velocity_ref_t;

typedef struct {
    /* Private. */
    ego_scan_t slot[2];
    ego_hist_t hist[2];
    uint32_t last_time_us;
    ego_pose_t motion;       /* the motion that predicts the next, over motion_dt_us */
    uint32_t motion_dt_us;
    ego_pose_t held;         /* while a standstill holds the last scan kept (slot last) as
                                the reference: the last scan processed in its frame */
    uint32_t held_time_us;   /* that scan's time; last_time_us when none is held */
    ego_pose_t before;       /* the motion before the last search, over before_dt_us
                                (0: none): a start of the bridge after it */
    uint32_t before_dt_us;
    ego_velocity_ref_t reference; /* of the dynamics check, when have_reference */
    fx_bam32_t main_direction[2]; /* of each slot's histogram: its fullest bin */
    uint32_t previous_time_us;
    /* The small ones together (no padding between them: RAM is short). */
    uint8_t last;            /* slot of the last scan */
    bool have_last;
    bool predictable;        /* it came out close to its own prediction */
    uint8_t misses;          /* searches in a row whose result the prediction missed */
    uint8_t tight;           /* scans left that size tracking for a pass more: the
                                meter cut a tracking run short (ego.c, TIGHT_SCANS) */
    bool bridge;             /* a search that took several scans just ended: the next
                                interval is long, its prediction the search's motion */
    bool along_predicted;    /* the last motion along the main direction was the
                                prediction's (a corridor): the next scan looks
                                for the speed first */
    bool lost;               /* the last search found nothing: the next one's first
                                window is the widest, whatever the motion was */
    bool refined[2];         /* the slot has robust tangents and the search's histogram */
    uint8_t skew_100us;      /* the last prepared scan's beams' RMS offset from its time
                                when it was de-skewed, 0.1 ms (0: it was not) */
    uint8_t lead_100us[2];   /* the slot's points are this much ahead of its scan's time,
                                0.1 ms: one pass of an interlaced sweep, kept at a cold
                                start (0: de-skewed or cast at once) */
    bool have_previous;      /* the time of the previous scan, for the budget */
    bool weak;               /* the last motion had a weak translation (its part the
                                prediction's): tracking holds it weak (ego_track.h) */
    bool on_objects;         /* the last measured motion rested on objects: tracking
                                holds the test's share doubled (ego_track.h) */
    bool static_next;        /* the last answer was the static structure's own (the
                                points on objects left out): so is the next tracking */
    bool have_reference;     /* a measured line within the last second */
    bool suspect;            /* the last measured motion was beyond the dynamics
                                check's reach (EGO_FLAG_SUSPECT until one is back) */
    uint8_t slow_lines;      /* slow lines in a row, up to 255: a standstill's hold
                                begins after some (ego.c, holds) */
    ego_work_t work;         /* this scan's meter */
    union { /* one at a time */
        ego_track_run_t tracking;         /* the registration, or the coarse search's prober */
        ego_project_scratch_t projection; /* the coarse search's ranking (ego_project.h) */
    };
    ego_search_t search;
} ego_state_t;

typedef struct {
    ego_pose_t pose;          /* this scan in the frame of the last one */
    uint32_t dt_us;           /* time since the last scan */
    fx_q16_16_t vx;           /* m/s, vehicle frame of the last scan */
    fx_q16_16_t vy;
    fx_q16_16_t omega;        /* rad/s */
    uint16_t flags;           /* EGO_FLAG_* */
    uint8_t iterations;       /* registration iterations of the chosen candidate */
    uint8_t candidates;       /* rotation candidates tried */
    uint16_t points;          /* prepared points of this scan */
    uint16_t matches;
    uint16_t n_main;
    uint16_t n_non_main;
    uint16_t inliers;
    fx_q16_16_t residual;     /* RMS match distance, m */
    fx_q2_30_t correlation;   /* histogram correlation of the chosen rotation */
    uint32_t work;            /* units (ego_work.h) this scan spent */
    uint32_t work_limit;      /* and its budget (UINT32_MAX: unlimited or more) */
    ego_cov_t cov;            /* of pose (ego_cov.h); the velocities' is cov / dt^2.
                                 Unknown (EGO_COV_SATURATED variances) on a line
                                 without a measured motion: first, predicted,
                                 recovering */
} ego_output_t;

/* Starts over: the next scan is a first scan, and every line from there is
 * what a state that never ran gives (the whole state is zeroed). */
void ego_reset(ego_state_t *state);

/* The stages of ego_process, for profiling where the work goes. Built with
 * EGO_PROFILE defined, ego_process calls ego_profile_stage (which the
 * platform provides) as each stage begins, with the work units the scan
 * has been charged so far (ego_work.h; the meter starts at 0 each scan);
 * the work between two calls belongs to the first one's stage, so a
 * profile can set the instructions of each stage against its units.
 * Without EGO_PROFILE nothing is called (the firmware's profile images use
 * it: docs/firmware.md). */
typedef enum {
    EGO_STAGE_PREPARE = 0, /* polar -> points, segments */
    EGO_STAGE_TANGENTS,    /* robust tangents */
    EGO_STAGE_HISTOGRAM,   /* the tangent-angle histogram */
    EGO_STAGE_CORRELATE,   /* histogram correlation: rotation candidates */
    EGO_STAGE_REGISTER,    /* the registrations (tracking and search) */
    EGO_STAGE_COARSE,      /* the coarse translation (and rotation) search */
    EGO_STAGE_OTHER,       /* the rest: choosing, prediction, bookkeeping */
    EGO_STAGE_COUNT
} ego_stage_t;

#if defined(EGO_PROFILE)
void ego_profile_stage(ego_stage_t stage, uint64_t units);
#endif

typedef enum {
    EGO_OK = 0,
    EGO_ERR_ARG = -1,   /* NULL pointer */
    EGO_ERR_SCAN = -2   /* the range scan fails ego_range_check: state unchanged */
} ego_status_t;

/* Processes one scan taken at time_us (a free-running microsecond clock;
 * wrap-around is fine; scans less than 2^32 us apart). */
ego_status_t ego_process(ego_state_t *state, const ego_params_t *params, const ego_range_scan_t *scan,
                         uint32_t time_us, ego_output_t *out);

/* The same with an optional motion prior for this scan (for example wheel
 * odometry: the pose of this scan in the frame of the last one), or NULL.
 * A prior replaces the prediction from the last motion: tracking starts
 * from it within its own error first (twice a tenth of its length, at
 * least 3 cm; a prior over half a metre starts with the usual reach), so
 * that vehicles moving with us, a scan's motion off it, stay out of the
 * fit (a platoon ahead at our speed: docs/estimator.md, "A motion
 * prior"); its rotation is tried first among the rotation candidates and
 * its translation centres the searches. Where tracking from it fails, the
 * histogram's candidates are tried and the one with the most inliers
 * wins, so a bad prior cannot override a good match. When matching fails,
 * the output is the prior (flag EGO_FLAG_PREDICTED). */
ego_status_t ego_process_with_prior(ego_state_t *state, const ego_params_t *params,
                                    const ego_range_scan_t *scan, uint32_t time_us,
                                    const ego_pose_t *prior, ego_output_t *out);

#endif /* EGO_H */
