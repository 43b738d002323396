/* ego_tfit.h - robust tangent of every scan point (paper section 3, eqs. 1-3).
 *
 * For point i, the 2n + 1 neighbours P[i-n] .. P[i+n] that lie in i's own
 * segment (never across a break of ego_scan.h) are fitted with the line
 * x cos(phi) + y sin(phi) = d by weighted least squares; the closed form is
 *
 *   phi = 1/2 atan2(-2 Sxy, Syy - Sxx)   (S.. weighted central moments)
 *
 * A plain fit (all weights 1) is followed by `passes` M-estimator passes
 * whose weights come from the residuals e_k of the previous fit and their
 * scale sigma:
 *
 *   w_k = 1 if |e_k| <= sigma;  sigma / |e_k| if |e_k| <= 3 sigma;  else 0.
 *
 * The paper's sigma (garbled in the text) is read as the spread of the
 * residuals. The standard deviation lets one gross outlier in seven points
 * inflate sigma enough to keep itself (a 0.25 m outlier still tilted the
 * tangent by 5 deg in test_tfit), so sigma here is the robust
 * 1.4826 x median |e_k| (equal to the standard deviation for Gaussian
 * noise), floored at sigma_min, the scanner's own range noise.
 *
 * The tangent direction is phi + 90 deg modulo 180 deg (a binary angle
 * with bit 31 clear). The quality figure is the weighted RMS residual of
 * the last fit. A point whose segment offers fewer than min_points
 * neighbours (itself included) in the window gets no tangent.
 *
 * Fixed point: coordinates relative to P[i] in Q16.16, weights Q16.16,
 * moments in int64 (Q32.32; at most 11 terms of < 2^42 each, see
 * docs/fixed-point.md), angles from fx_atan2. Bounded: at most
 * 2 * EGO_TFIT_MAX_HALF_WINDOW + 1 points, passes + 1 fits per point.
 */
#ifndef EGO_TFIT_H
#define EGO_TFIT_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_scan.h"
#include "ego_fx.h"

typedef struct {
    uint8_t half_window; /* n, 1 .. EGO_TFIT_MAX_HALF_WINDOW; default 3 */
    uint8_t passes;      /* M-estimator passes after the plain fit; default 2 */
    uint8_t min_points;  /* smallest usable window, >= 2; default 3 */
    fx_q16_16_t sigma_min; /* floor of the residual scale, m; default 0.005 */
} ego_tfit_params_t;

void ego_tfit_defaults(ego_tfit_params_t *params);

/* One fit over count points (x[k], y[k]), count <= 2 * EGO_TFIT_MAX_HALF_WINDOW
 * + 1, coordinates relative to any nearby origin (|x|, |y| < 2^26, i.e.
 * 1024 m). Returns false (and leaves *tangent, *rms alone) when count < 2
 * or the weights leave fewer than two points. */
bool ego_tfit_fit(const fx_q16_16_t *x, const fx_q16_16_t *y, uint16_t count, uint8_t passes,
              fx_q16_16_t sigma_min, fx_bam32_t *tangent, fx_q16_16_t *rms);

/* Fits every point of scan: sets tangent[] and the EGO_POINT_HAS_TANGENT
 * flag. */
void ego_tfit_fit_scan(ego_scan_t *scan, const ego_tfit_params_t *params);

/* The cheap tangent of every point: the direction of the chord between
 * its linked neighbours, widened on both sides (up to 4 each) until it
 * spans 0.2 m (one side at a segment's end; none for a lone point),
 * modulo 180 deg. For tracking, where a tangent
 * only sorts a point into ITCP's two groups (10 deg apart at least): about
 * a fifth of a plain fit's work. */
void ego_tfit_chord_scan(ego_scan_t *scan);

/* Fits point i alone (its tangent and flag): the work of one
 * point, for a caller that spreads the fits over a budget (ego.c). */
void ego_tfit_fit_point(ego_scan_t *scan, const ego_tfit_params_t *params, uint16_t i);

#endif /* EGO_TFIT_H */
