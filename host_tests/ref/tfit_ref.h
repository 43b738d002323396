/* tfit_ref.h - double-precision oracle of the robust tangent fit (eqs. 1-3
 * of the paper, as restated in ego_tfit.h). Host tests only. */
#ifndef TFIT_REF_H
#define TFIT_REF_H

#include <stdbool.h>

/* Same contract as ego_tfit_fit, in doubles: tangent direction in radians in
 * [0, pi), weighted RMS residual in metres. *margin (may be NULL) gets the
 * smallest distance of any |e| / sigma from 3, where eq. 2's weight jumps
 * from 1/3 to 0: near the jump, rounding alone can change the answer. */
bool tfit_ref_fit(const double *x, const double *y, unsigned count, unsigned passes,
                  double sigma_min, double *tangent_rad, double *rms_m, double *margin);

#endif /* TFIT_REF_H */
