/* ego_cov.h - how far to trust a registration's relative pose: the
 * covariance of (dx, dy, dtheta) from the normal equations of its last
 * pass, scaled by the residual (issue 16).
 *
 * The registration (ego_track.c) solves A x = b with the two tangent
 * groups weighing equally (eq. 10): A = sum_g A_g / n_g, b = sum_g b_g /
 * n_g, where A_g = sum J J^T and b_g = sum J d over the group's n_g
 * matches, J = (nx, ny, arm) (the match's unit normal and the lever arm of
 * the point about the scanner). Each residual d has the variance s^2 =
 * 2 sum d^2 / (n - 3) (n = n_0 + n_1, both groups pooled: one range noise;
 * the 2 for the errors the residuals do not show, ego_cov.c), so cov(b) =
 * s^2 sum_g A_g / n_g^2 and
 *
 *     cov(x) = s^2 A^-1 (sum_g A_g / n_g^2) A^-1,
 *
 * with A damped as the registration damps it (a direction no surface
 * constrains, a corridor's length, gets a large variance, not an
 * infinite one). Unweighted (plain ICP) the matches form one group. The
 * model counts the residual's scatter only: a wrong association that fits
 * well (a wrong minimum) is not in it.
 *
 * Fixed point throughout, no float: the arithmetic is a 3x3 product of
 * integer mantissas that share a power of two (each step rescales them to
 * 30 bits, so no product leaves int64), with the rotation scaled by a
 * power-of-two length near the lever arms first (so that the translation
 * and rotation entries carry as many bits). The result rounds to Q2.30 of
 * SI units and saturates at +-2 (EGO_COV_SATURATED): a variance of 2 m^2
 * or 2 rad^2 says "not measured". Resolution 2^-30 (9.3e-10: a standard
 * deviation of 30 um or 30 urad is the smallest that shows). Bit-identical
 * on every target. */
#ifndef EGO_COV_H
#define EGO_COV_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_fx.h"

typedef struct {
    fx_q2_30_t xx; /* m^2 */
    fx_q2_30_t xy; /* m^2 */
    fx_q2_30_t xt; /* m rad */
    fx_q2_30_t yy; /* m^2 */
    fx_q2_30_t yt; /* m rad */
    fx_q2_30_t tt; /* rad^2 */
} ego_cov_t;

/* A variance this large (the top of Q2.30, 2 m^2 or 2 rad^2): no
 * measurement (the first scan, a predicted line, a registration with too
 * few matches to say). */
#define EGO_COV_SATURATED INT32_MAX

/* One tangent group of a registration's last pass: n matches and the sums
 * of J J^T over them as ego_track accumulates them: xx, xy, yy (normals,
 * Q14 each) in Q28; xt, yt (normal times lever arm, Q16 m) in Q30 m; tt in
 * Q32 m^2. */
typedef struct {
    int64_t n;
    int64_t a[6]; /* xx, xy, xt, yy, yt, tt */
} ego_cov_group_t;

/* The covariance of the registration's pose (above) from its groups and
 * the sum of its squared residuals (Q32 m^2, both groups); weighted:
 * the groups weigh equally (eq. 10), else every match alike. With three
 * matches or fewer, or equations that do not determine a pose, every
 * variance is EGO_COV_SATURATED and the covariances 0. */
void ego_cov_estimate(const ego_cov_group_t group[2], uint64_t sum_sq, bool weighted,
                      ego_cov_t *cov);

/* The covariance that says nothing was measured. */
void ego_cov_unknown(ego_cov_t *cov);

/* A motion whose part along the unit direction (c, s) (Q2.30) is not
 * the measurement's (a corridor's length, taken from the prediction): 1
 * m^2 more variance along it, saturated. */
void ego_cov_unmeasured_along(ego_cov_t *cov, fx_q2_30_t c, fx_q2_30_t s);

/* A rotation that is not the measurement's (taken from the prediction):
 * 1 rad^2 more variance, saturated. */
void ego_cov_unmeasured_rotation(ego_cov_t *cov);

#endif /* EGO_COV_H */
