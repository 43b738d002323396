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
    double sum_sq; /* the squared residuals, m^2 */
} cov_ref_group_t;

/* cov[3][3] over (dx m, dy m, dtheta rad) from the groups, whose residuals
 * were those within cut_m (0: no cut), and with the output's rounding
 * guard; false when ego_cov_estimate says "unknown" (three matches or
 * fewer, or a singular system). */
bool cov_ref_estimate(const cov_ref_group_t group[2], double cut_m, bool weighted,
                      double cov[3][3]);

/* kappa of ego_cov.h exactly (at most 16) for residuals whose mean square
 * is r times their cut's square: the cut a of a unit normal noise with
 * (1 - t / P) / a^2 = r by bisection, t = 2 a phi(a), P = erf(a / sqrt 2),
 * kappa = (P / (P - t))^2. */
double cov_ref_cut_factor(double r);

/* The weakest direction of ego_cov_weakest in doubles, exactly: the main
 * group's normals projected on the main direction's normal (main_rad: the
 * main direction, the tangent), every match alike, the turn times lever_m
 * (at least 0.5 m); the eigenvector of the smallest eigenvalue (Jacobi
 * rotations), that eigenvalue over the trace and the next one's. False
 * with three matches or fewer. */
bool cov_ref_weakest(const cov_ref_group_t group[2], double main_rad, double lever_m,
                     double *share, double *next_share, double dir[3]);

/* The objects test of ego_cov_on_objects in doubles. all = T and objects =
 * O as (xx, xy, yy), any common unit. mu: the least generalized
 * eigenvalue of T - O against T, min over u of u^T (T - O) u / u^T T u
 * (the smaller root of det(T - O - mu T) = 0); the test holds when mu <
 * share. eig[0] <= eig[1]: the eigenvalues of M = (1 - share) T - O (M is
 * not positive definite exactly when mu <= share). False (nothing
 * written) when T is not positive definite. */
bool cov_ref_on_objects(const double all[3], const double objects[3], double share, double *mu,
                        double eig[2]);

#endif /* COV_REF_H */
