/* itcp_ref.c - see itcp_ref.h; the equations as written, in doubles. */
#include "itcp_ref.h"

#include <math.h>

void itcp_ref_solve(const double *x, const double *y, const double *u, const double *v,
                    const bool *main, unsigned n, bool weighted, bool hold_theta, double *theta,
                    double *tx, double *ty)
{
    unsigned n_main = 0u;
    for (unsigned k = 0u; k < n; k++) {
        n_main += main[k] ? 1u : 0u;
    }
    const unsigned n_non = n - n_main;
    double lam_main = 1.0;
    double lam_non = 1.0;
    if (weighted && n_main > 0u && n_non > 0u) {
        lam_main = (double)n / (2.0 * n_main);
        lam_non = (double)n / (2.0 * n_non);
    }
    double sw = 0.0;
    double xm = 0.0;
    double ym = 0.0;
    double um = 0.0;
    double vm = 0.0;
    for (unsigned k = 0u; k < n; k++) {
        const double w = main[k] ? lam_main : lam_non;
        sw += w;
        xm += w * x[k];
        ym += w * y[k];
        um += w * u[k];
        vm += w * v[k];
    }
    xm /= sw;
    ym /= sw;
    um /= sw;
    vm /= sw;
    if (!hold_theta) {
        double num = 0.0;
        double den = 0.0;
        for (unsigned k = 0u; k < n; k++) {
            const double w = main[k] ? lam_main : lam_non;
            num += w * ((x[k] - xm) * (v[k] - vm) - (y[k] - ym) * (u[k] - um));
            den += w * ((x[k] - xm) * (u[k] - um) + (y[k] - ym) * (v[k] - vm));
        }
        *theta = atan2(num, den);
    }
    *tx = um - (xm * cos(*theta) - ym * sin(*theta));
    *ty = vm - (xm * sin(*theta) + ym * cos(*theta));
}
