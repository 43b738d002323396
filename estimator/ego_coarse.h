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

#include "ego_pose.h"
#include "ego_scan.h"

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

/* Searches around *centre; *best gets the best pose, *score its score
 * (0: nothing matched anywhere; *best is then *centre). */
void ego_coarse_search(const ego_scan_t *last, const ego_scan_t *current, fx_bam32_t main_direction,
                   const ego_pose_t *centre, const ego_coarse_params_t *params, ego_pose_t *best,
                   uint64_t *score);

#endif /* EGO_COARSE_H */
