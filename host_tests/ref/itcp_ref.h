/* itcp_ref.h - double-precision oracle of ITCP's closed form (eqs. 10-12). */
#ifndef ITCP_REF_H
#define ITCP_REF_H

#include <stdbool.h>

/* Pairs (x, y) -> (u, v), main[k] marks the main-direction group. Weighted:
 * lambda = m / (2 n_group) (eq. 10); else all 1. hold_theta: theta stays
 * at *theta. Writes theta (rad) and t (m). */
void itcp_ref_solve(const double *x, const double *y, const double *u, const double *v,
                    const bool *main, unsigned n, bool weighted, bool hold_theta, double *theta,
                    double *tx, double *ty);

#endif /* ITCP_REF_H */
