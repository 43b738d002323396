/* ego_coarse.h - bounded coarse search for the translation (and optionally a
 * small rotation correction) before ITCP: beyond the paper, because ITCP
 * started from zero translation does not reach motions of 0.7 m or more
 * (../shared/reference/algorithm-notes.md section 6).
 *
 * Each candidate pose moves a sample of the current scan's points (half
 * on the main direction, half not, evenly spaced within each: ego_coarse.c)
 * into the last scan's frame and scores them by their distance d to the
 * last scan's surfaces (segments, through the scan order as in ITCP):
 * sum of max(0, sigma^2 - d^2), minus sigma^2 for each point matching
 * nothing where the last scan saw 2 sigma further (empty space), the two
 * groups weighed equally. Candidates: the translations of a square
 * window of half-width `window` around the centre at `step`, for the
 * centre's rotation and rotation_steps rotations on each side of it
 * rotation_step apart, scored with sigma = max(sigma, step); then, for
 * each rotation, a fine pass of fine_step around its best within one
 * coarse step, scored with sigma. The best fine-scored pose is returned.
 *
 * Worst case per call: (2 rotation_steps + 1) ((2 window / step + 1)^2
 * + (2 step / fine_step + 1)^2) candidates, each sample_points distance
 * queries of at most 2 EGO_ITCP_MAX_WALK segments. With the defaults
 * (window 0.6 m around a prediction, steps 0.2 / 0.05 m, one 2-degree
 * rotation step each side, 48 points): 3 x (49 + 81) = 390 candidates,
 * 18 720 queries; with the 4 m window used when there is no prediction yet
 * (ego.h): 3 x (1681 + 81) = 5286 candidates. All integer.
 */
#ifndef EGO_COARSE_H
#define EGO_COARSE_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_itcp.h"
#include "ego_pose.h"
#include "ego_project.h"
#include "ego_scan.h"
#include "ego_track.h"
#include "ego_work.h"

/* Largest sample; the defaults use 48 (24 under a budget). */
#define EGO_COARSE_MAX_SAMPLE 64u

typedef struct {
    fx_q16_16_t window;        /* half-width of the translation window, m */
    fx_q16_16_t step;          /* coarse step, m */
    fx_q16_16_t fine_step;     /* fine step, m */
    fx_q16_16_t sigma;         /* distance scale of the fine score, m (coarse: step) */
    uint8_t rotation_steps;    /* rotations tried on each side of the centre's */
    fx_bam32_t rotation_step;
    uint16_t sample_points;    /* current points scored per candidate */
    fx_bam32_t main_tolerance; /* tangent this close to the main direction: main group */
} ego_coarse_params_t;

void ego_coarse_defaults(ego_coarse_params_t *params);

/* The search in steps, for a caller with a work budget (ego_work.h): a
 * run started with ego_coarse_start goes on with each ego_coarse_step
 * until it returns true; then ego_coarse_result gives what
 * ego_coarse_search would. A step is one sample point's probe (at most
 * EGO_COST_MATCH_POINT_MAX(EGO_ITCP_MAX_WALK) units and a little), and the
 * meter is never asked for more than it has left. The scans must stay
 * where they are, unchanged, until the run is finished. Private fields. */
typedef struct {
    uint16_t count[2];
    uint16_t index[2][EGO_COARSE_MAX_SAMPLE];
} ego_coarse_sample_t;

typedef struct {
    uint64_t score;
    uint64_t penalty;
} ego_coarse_tally_t;

typedef struct {
    bool active;
    ego_pose_t pose;
    fx_q2_30_t sn;
    fx_q2_30_t cs;
    fx_q16_16_t sigma;
    uint64_t sigma_sq;
    uint64_t must_beat;
    bool ties_win;
    ego_itcp_prober_t prober;
    ego_coarse_tally_t tally[2]; /* per group */
    uint8_t group;
    uint16_t next;
    uint64_t value;
} ego_coarse_score_t;

typedef struct {
    ego_pose_t around;
    fx_q16_16_t step;
    fx_q16_16_t sigma;
    int32_t n;          /* steps on each side */
    ego_pose_t best;
    uint64_t best_score;
    int32_t best_rank;  /* the best's place in row order, -1: it came from outside */
    int32_t ring;       /* the next point: ring and place in it */
    int32_t at;
} ego_coarse_grid_t;

typedef struct {
    const ego_scan_t *last;
    const ego_scan_t *current;
    ego_coarse_params_t params;
    fx_bam32_t main_direction;
    ego_pose_t centre;
    ego_pose_t around;
    ego_pose_t best;
    uint64_t score;
    int32_t rotation;
    uint8_t phase;
    ego_coarse_sample_t sample;
    ego_coarse_score_t scoring;
    ego_coarse_grid_t grid;
    ego_track_run_t *along; /* probes along the bearing (or NULL: ITCP's) */
    const ego_track_params_t *along_params;
    ego_project_scratch_t *scratch; /* projected (ego_coarse_projected), or NULL */
    ego_project_cells_t cells;
    uint8_t direction;      /* projected: the next direction to correlate */
    uint8_t cell;           /* the next of cells' 3 x 3 neighbourhoods to score */
    uint64_t cells_best;    /* projected: the best cell score of the rotations so far */
} ego_coarse_run_t;

void ego_coarse_start(ego_coarse_run_t *run, const ego_scan_t *last, const ego_scan_t *current,
                      fx_bam32_t main_direction, const ego_pose_t *centre,
                      const ego_coarse_params_t *params);
bool ego_coarse_step(ego_coarse_run_t *run, ego_work_t *work);

/* After ego_coarse_start: score with tracking's probe along the bearing
 * (ego_track_probe, about a third of the work of ITCP's, which searches
 * every surface within sigma), its normals cached in `prober`, which must
 * stay untouched until the run is finished. */
void ego_coarse_along_bearing(ego_coarse_run_t *run, ego_track_run_t *prober,
                              const ego_track_params_t *params);
/* After ego_coarse_along_bearing: rank each rotation's window by
 * projections (ego_project.h) and score exactly only the 3 x 3
 * neighbourhoods (at step) of its best EGO_PROJECT_CELLS cells, then the
 * fine grid around the best as before, instead of every cell of the
 * window (window up to EGO_PROJECT_MAX_SIDE steps each side; the centre is
 * not scored on its own). scratch is the prober's memory (a union,
 * ego.h): the run starts the prober again after each ranking. */
void ego_coarse_projected(ego_coarse_run_t *run, ego_project_scratch_t *scratch);
void ego_coarse_result(const ego_coarse_run_t *run, ego_pose_t *best, uint64_t *score);

/* Searches around *centre; *best gets the best pose, *score its score
 * (0: nothing matched anywhere; *best is then *centre). */
void ego_coarse_search(const ego_scan_t *last, const ego_scan_t *current, fx_bam32_t main_direction,
                   const ego_pose_t *centre, const ego_coarse_params_t *params, ego_pose_t *best,
                   uint64_t *score);

#endif /* EGO_COARSE_H */
