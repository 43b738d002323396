/* ego_cov.h - how far to trust a registration's relative pose: the
 * covariance of (dx, dy, dtheta) from the normal equations of its last
 * pass, scaled by the residual (issue 16).
 *
 * The registration (ego_track.c) solves A x = b with the two tangent
 * groups weighing equally (eq. 10): A = sum_g A_g / n_g, b = sum_g b_g /
 * n_g, where A_g = sum J J^T and b_g = sum J d over the group's n_g
 * matches, J = (nx, ny, arm) (the match's unit normal and the lever arm of
 * the point about the scanner). The residuals of group g have the
 * variance s_g^2, so cov(b) = sum_g s_g^2 A_g / n_g^2 and
 *
 *     cov(x) = A^-1 (sum_g s_g^2 A_g / n_g^2) A^-1,
 *
 * with A damped as the registration damps it (a direction no surface
 * constrains, a corridor's length, gets a large variance, not an
 * infinite one). Unweighted (plain ICP) the matches form one group.
 *
 * s_g^2 (ego_cov.c) is the group's mean squared residual (pulled towards
 * the pool's by a few pseudo-matches: a group of two says little about
 * its scatter), n / (n - 3) for the three unknowns, times 2 for the
 * errors the residuals do not show (associations and chords, which pull
 * alike over a scan), times the cut's factor: the registration used only
 * residuals within its last radius, so their scatter understates the
 * noise's and each one near the edge sways the fit more (a trimmed
 * least-squares fit, an M-estimator: kappa = P^2 / (P - 2 c f(c))^2 for
 * a normal noise cut at c, P the share inside; 1 for a cut at 3 sigma,
 * 4.5 at 1.35 sigma, what a 5 cm cut leaves of 3 cm of range noise).
 * The model counts the residuals' scatter only: a wrong association that
 * fits well (a wrong minimum) is not in it.
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
    int64_t a[6];    /* xx, xy, xt, yy, yt, tt */
    uint64_t sum_sq; /* the squared residuals, Q32 m^2 */
} ego_cov_group_t;

/* The covariance of the registration's pose (above) from its groups,
 * whose residuals were those within cut (Q16.16 m; 0: no cut); weighted:
 * the groups weigh equally (eq. 10), else every match alike. Each
 * variance carries 2 LSB more than it rounded to, so the rounded matrix
 * stays positive definite. With three matches or fewer, or equations
 * that do not determine a pose, every variance is EGO_COV_SATURATED and
 * the covariances 0. */
void ego_cov_estimate(const ego_cov_group_t group[2], fx_q16_16_t cut, bool weighted,
                      ego_cov_t *cov);

/* The factor kappa (above) of residuals whose mean square is r times
 * the square of their cut (r in Q16, r < 1/3 for any noise that is not
 * wider than the cut), Q16, at most 16 (a scatter that fills the window:
 * the noise may be any wider). */
uint32_t ego_cov_cut_factor(uint32_t r_q16);

/* Observability (issue 16): the direction of (dx, dy, dtheta) the
 * matches constrain least, from their information sum J J^T with every
 * match alike (the geometry, not eq. 10's weighting), the turn scaled by
 * a lever (the scan's RMS range: a turn of 1 rad moves a typical point
 * that far). Its share of the information, lambda_min / trace (1/3 for
 * a scene that constrains every direction alike, 0 for one that does not
 * constrain one at all), below min_share makes it weak. */
typedef enum {
    EGO_WEAK_NONE = 0,
    EGO_WEAK_TRANSLATION = 1, /* a translation: a corridor's length */
    EGO_WEAK_ROTATION = 2,    /* the turn: every surface faces the scanner */
    EGO_WEAK_COUPLED = 3,     /* a translation with a turn: sliding along a ring
                                 seen from off its centre while turning */
    EGO_WEAK_OBJECTS = 4      /* the translation measured on objects that may be
                                 moving (ego_cov_on_objects; no direction) */
} ego_weak_kind_t;

typedef struct {
    uint8_t kind;      /* ego_weak_kind_t */
    int8_t dir[3];     /* the weakest direction, a unit vector in Q0.7 of
                          (x m, y m, theta rad * lever m), sign arbitrary
                          (within 0.5 deg: RAM is short) */
} ego_weak_t;

/* The weakest direction of the groups' matches, group 0's normals taken
 * as the main direction's (a tangent within the main tolerance of it is
 * that direction, its scatter the normals' noise) (kind EGO_WEAK_NONE when
 * its share is at least min_share, or with three matches or fewer).
 * lever in Q16.16 m, at least 0.5 m is used. A direction within 20 deg
 * of the translation plane is a translation, within 20 deg of the turn's
 * axis a rotation, else coupled. Constant work (EGO_COST_COVARIANCE
 * counts it). */
/* The lever used: lever (Q16.16 m), at least 0.5 m. */
fx_q16_16_t ego_cov_lever(fx_q16_16_t lever);

void ego_cov_weakest(const ego_cov_group_t group[2], fx_bam32_t main_direction, fx_q16_16_t lever,
                     fx_q2_30_t min_share, ego_weak_t *weak);

/* Whether the translation rests on objects (issue 17: a platoon of trucks
 * ahead at our speed looks like a world in which we stand still): along
 * some direction u, the information of the matches that are not on
 * objects (EGO_POINT_OBJECT), u^T (T - O) u, is below `share` of all of
 * it, u^T T u. T and O are the translation parts (xx, xy, yy) of J J^T
 * over every match and over those on objects, Q14 each (one match adds at
 * most 2^14), up to 2^24. The test: (1 - share) T - O has a negative
 * eigenvalue (its entries below 2^25, their products in int64), no square
 * root. Without matches on objects it is positive semidefinite: a T that
 * constrains a direction not at all (a corridor's length: the weak test's
 * case) or none (no matches) does not rest on objects. Which direction
 * rests on them is not worked out (the flash of a 64 KiB part): the caller
 * takes the whole translation as unmeasured. Inline: its one caller is
 * tracking's result. */
FX_INLINE bool ego_cov_on_objects(const int32_t all[3], const int32_t objects[3], fx_q2_30_t share)
{
    int32_t m[3];
    for (unsigned k = 0u; k < 3u; k++) {
        m[k] = all[k] - objects[k] - (int32_t)(((int64_t)all[k] * share) / FX_Q2_30_ONE);
    }
    return m[0] < 0 || m[2] < 0 || (int64_t)m[0] * m[2] < (int64_t)m[1] * m[1];
}

/* A motion whose part along the weak direction is not the measurement's
 * (taken from the prediction): 1 m^2 (1 m of the lever in the turn) more
 * variance along it, saturated. */
void ego_cov_unmeasured_direction(ego_cov_t *cov, const ego_weak_t *weak, fx_q16_16_t lever);

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
