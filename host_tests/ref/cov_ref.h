/* cov_ref.h - double-precision oracle of a registration's covariance
 * (estimator/ego_cov.h): the same model in doubles and SI units. Host
 * tests only. */
#ifndef COV_REF_H
#define COV_REF_H

#include <stdbool.h>

/* One group's matches: n, and the sums of J J^T (J = (nx, ny, arm m)):
 * xx, xy, xt, yy, yt, tt. */
typedef struct {
    double n;
    double a[6];
} cov_ref_group_t;

/* cov[3][3] over (dx m, dy m, dtheta rad) from the groups and the sum of
 * squared residuals (m^2); false when ego_cov_estimate says "unknown"
 * (three matches or fewer, or a singular system). */
bool cov_ref_estimate(const cov_ref_group_t group[2], double sum_sq, bool weighted,
                      double cov[3][3]);

/* The weakest direction of ego_cov_weakest in doubles, exactly: the main
 * group's normals projected on the main direction's normal (main_rad: the
 * main direction, the tangent), every match alike, the turn times lever_m
 * (at least 0.5 m); the eigenvector of the smallest eigenvalue (Jacobi
 * rotations), that eigenvalue over the trace and the next one's. False
 * with three matches or fewer. */
bool cov_ref_weakest(const cov_ref_group_t group[2], double main_rad, double lever_m,
                     double *share, double *next_share, double dir[3]);

#endif /* COV_REF_H */
