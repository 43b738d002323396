/* project_ref.h - double-precision oracle of the projection ranking
 * (estimator/ego_project.h): the same histograms, correlations and cell
 * scores in doubles. Host tests only. */
#ifndef PROJECT_REF_H
#define PROJECT_REF_H

#include "ego_project.h"

/* The score of every cell of the window (row order: ix, then iy, from -n),
 * each direction's correlation scaled to 1 at its maximum, so a cell
 * scores 0..EGO_PROJECT_DIRS; returns n (cells on each side). score must
 * hold (2 EGO_PROJECT_MAX_SIDE + 1)^2 values. */
int project_ref_scores(const ego_scan_t *last, const ego_scan_t *current, double main_dir_rad,
                       double theta_rad, double cx, double cy, double window, double bin,
                       double *score);

/* The correlation along one direction (ego_project_along): corr[j + n]
 * for shifts j = -n..n of the translation's projection from the centre's
 * bin (*centre_bin, in bins), scaled to 1 at its maximum, all 0 when no
 * point faces the direction; returns n. corr must hold 2 n + 1 values. */
int project_ref_along(const ego_scan_t *last, const ego_scan_t *current, double dir_rad,
                      double theta_rad, double cx, double cy, double window, double bin,
                      double *corr, double *centre_bin);

#endif /* PROJECT_REF_H */
