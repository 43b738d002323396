/* ego_project.h - translation candidates from projections: the coarse
 * search's prescreen over a wide window (beyond the paper; ego_coarse.h).
 *
 * For a rotation theta, a translation t shifts every current point's
 * projection on a direction u by t.u. Along each of EGO_PROJECT_DIRS
 * directions (the last scan's main direction and every 45 deg from it),
 * the histograms of both scans' projections, in bins of `bin` m, are
 * correlated over the shifts the window reaches. A translation's score is
 * the sum over the directions of the correlation at its shift, each
 * direction scaled to its own maximum: a cheap stand-in for the 2-D
 * correlation of the two scans, with no 2-D memory. Only points whose
 * surface faces the direction count (tangent at least 30 deg from it;
 * points without a tangent always): a wall along u says nothing about a
 * motion along u and would only blur its histogram. The window's cells
 * (every `bin` m) are ranked by score and the best EGO_PROJECT_CELLS, at
 * least 3 cells apart, returned for the exact score (ego_coarse.c).
 *
 * Cost: per direction, a pass over both scans' points and the products of
 * the current histogram's filled bins with each shift; then 4 look-ups per
 * cell. A window of 1.6 m at 0.1 m (33 x 33 cells) costs about 0.3-0.7 M
 * units where the exact score of every cell costs 10-30 M. Memory: 1.5 KB
 * of scratch, no more than the tracking run it shares a union with.
 *
 * Fixed point: projections Q16.16 m, bin indices int32 (wrapping modulo
 * EGO_PROJECT_BINS: points a multiple of 51.2 m apart at 0.1 m share bins,
 * noise the exact score removes), histograms uint8 saturating at 255,
 * correlations uint32 (at most 255 x 255 x 512 < 2^25), scaled to Q0.16
 * per direction; cell projections Q2.30 bins in int64. Integer only.
 */
#ifndef EGO_PROJECT_H
#define EGO_PROJECT_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_pose.h"
#include "ego_scan.h"

#define EGO_PROJECT_DIRS 4u
#define EGO_PROJECT_BINS 512u       /* a power of two: bins wrap with a mask */
#define EGO_PROJECT_MAX_SIDE 20     /* cells on each side of the centre: 4 m at 0.2 m
                                       (as the coarse grid's own cap) */
#define EGO_PROJECT_MAX_SHIFT 30    /* >= sqrt(2) EGO_PROJECT_MAX_SIDE + 1 */
#define EGO_PROJECT_CELLS 6u

/* Working memory of one call, owned by the caller (ego.h keeps it where
 * the registration's run lives: the two are never needed at once). */
typedef struct {
    uint8_t last[EGO_PROJECT_BINS];
    uint8_t current[EGO_PROJECT_BINS];
    uint16_t corr[EGO_PROJECT_DIRS][2 * EGO_PROJECT_MAX_SHIFT + 1]; /* Q0.16 of the maximum */
    int32_t centre[EGO_PROJECT_DIRS]; /* bin of the window centre's projection */
} ego_project_scratch_t;

typedef struct {
    uint8_t count;
    ego_pose_t cell[EGO_PROJECT_CELLS]; /* best first; theta is the rotation tried */
} ego_project_cells_t;

/* Cells on each side of the centre for a window of half-width `window`
 * at `bin` (at most EGO_PROJECT_MAX_SIDE). */
int32_t ego_project_side(fx_q16_16_t window, fx_q16_16_t bin);

/* The most ego_project_cells can cost for these scans and window (units,
 * ego_work.h): what a caller checks its meter for. */
uint32_t ego_project_cost_max(const ego_scan_t *last, const ego_scan_t *current,
                              fx_q16_16_t window, fx_q16_16_t bin);

/* The best cells of the window of half-width `window` around
 * (around->x, around->y) for the rotation around->theta (bin > 0, in
 * metres; main_direction in the last scan's frame). Returns the units it
 * cost (at most ego_project_cost_max). */
uint32_t ego_project_cells(const ego_scan_t *last, const ego_scan_t *current,
                           fx_bam32_t main_direction, const ego_pose_t *around,
                           fx_q16_16_t window, fx_q16_16_t bin, ego_project_scratch_t *scratch,
                           ego_project_cells_t *out);

/* ego_project_cells in steps, for a caller whose meter may not hold it
 * all at once (a sensor-rate budget: on a 361-value scan the whole costs
 * about one): the correlation of direction k (0 .. EGO_PROJECT_DIRS - 1,
 * each into scratch, at most ego_project_direction_cost_max units), then,
 * with every direction's in scratch, the ranking (ego_project_rank_cost
 * units). The same arguments each step; the scratch untouched between. */
uint32_t ego_project_direction_cost_max(const ego_scan_t *last, const ego_scan_t *current,
                                        fx_q16_16_t window, fx_q16_16_t bin);
uint32_t ego_project_direction(const ego_scan_t *last, const ego_scan_t *current,
                               fx_bam32_t main_direction, const ego_pose_t *around,
                               fx_q16_16_t window, fx_q16_16_t bin, unsigned k,
                               ego_project_scratch_t *scratch);
uint32_t ego_project_rank_cost(fx_q16_16_t window, fx_q16_16_t bin);
uint32_t ego_project_rank(fx_bam32_t main_direction, const ego_pose_t *around, fx_q16_16_t window,
                          fx_q16_16_t bin, const ego_project_scratch_t *scratch,
                          ego_project_cells_t *out);

/* The shift along one direction that best aligns the two scans (a speed
 * the prediction missed, ego.c): the correlation of both scans'
 * projections on `direction` (points whose tangent faces it only: not
 * those without a tangent, unlike above) over the
 * shifts within `window` of around's projection, at `bin`. On success
 * *shift is the best shift's offset from around along direction (Q16.16
 * m; ties go to the smaller offset). False when no point faces the
 * direction in either scan. Units in *units (at most
 * ego_project_along_cost_max). */
uint32_t ego_project_along_cost_max(const ego_scan_t *last, const ego_scan_t *current,
                                    fx_q16_16_t window, fx_q16_16_t bin);
bool ego_project_along(const ego_scan_t *last, const ego_scan_t *current, fx_bam32_t direction,
                       const ego_pose_t *around, fx_q16_16_t window, fx_q16_16_t bin,
                       ego_project_scratch_t *scratch, fx_q16_16_t *shift, uint32_t *units);

#endif /* EGO_PROJECT_H */
