/* tfit_ref.c - see tfit_ref.h. Written straight from the equations, with
 * no attention to cost, as the oracle of estimator/ego_tfit.c. */
#include "tfit_ref.h"

#include <math.h>
#include <stdlib.h>

#define REF_MAX 64u
#define REF_PI 3.14159265358979323846

static bool fit_line(const double *x, const double *y, const double *w, unsigned n,
                     double *normal, double *residual, double *weight_sum)
{
    double sw = 0.0;
    double sx = 0.0;
    double sy = 0.0;
    unsigned used = 0u;
    for (unsigned k = 0u; k < n; k++) {
        sw += w[k];
        sx += w[k] * x[k];
        sy += w[k] * y[k];
        used += (w[k] > 0.0) ? 1u : 0u;
    }
    if (used < 2u) {
        return false;
    }
    const double xm = sx / sw;
    const double ym = sy / sw;
    double sxx = 0.0;
    double syy = 0.0;
    double sxy = 0.0;
    for (unsigned k = 0u; k < n; k++) {
        sxx += w[k] * (x[k] - xm) * (x[k] - xm);
        syy += w[k] * (y[k] - ym) * (y[k] - ym);
        sxy += w[k] * (x[k] - xm) * (y[k] - ym);
    }
    double phi = 0.5 * atan2(-2.0 * sxy, syy - sxx);
    if (phi < 0.0) {
        phi += REF_PI;
    }
    *normal = phi;
    *weight_sum = sw;
    for (unsigned k = 0u; k < n; k++) {
        residual[k] = (x[k] - xm) * cos(phi) + (y[k] - ym) * sin(phi);
    }
    return true;
}

static int cmp_double(const void *a, const void *b)
{
    const double da = *(const double *)a;
    const double db = *(const double *)b;
    return (da > db) - (da < db);
}

bool tfit_ref_fit(const double *x, const double *y, unsigned count, unsigned passes,
                  double sigma_min, double *tangent_rad, double *rms_m, double *margin)
{
    double closest = INFINITY;
    if (count < 2u || count > REF_MAX) {
        return false;
    }
    double w[REF_MAX];
    double e[REF_MAX];
    double normal = 0.0;
    double sw = 0.0;
    for (unsigned k = 0u; k < count; k++) {
        w[k] = 1.0;
    }
    if (!fit_line(x, y, w, count, &normal, e, &sw)) {
        return false;
    }
    for (unsigned pass = 0u; pass < passes; pass++) {
        double a_sorted[REF_MAX];
        for (unsigned k = 0u; k < count; k++) {
            a_sorted[k] = fabs(e[k]);
        }
        qsort(a_sorted, count, sizeof a_sorted[0], cmp_double);
        const double median = (count % 2u) ? a_sorted[count / 2u]
                                           : 0.5 * (a_sorted[count / 2u - 1u] + a_sorted[count / 2u]);
        const double sigma = fmax(1.4826 * median, sigma_min);
        for (unsigned k = 0u; k < count; k++) {
            const double a = fabs(e[k]);
            /* Distance of |e| / sigma from the weight function's jump at 3. */
            if (sigma > 0.0 && fabs(a / sigma - 3.0) < closest) {
                closest = fabs(a / sigma - 3.0);
            }
            if (sigma == 0.0 || a <= sigma) {
                w[k] = 1.0;
            } else if (a <= 3.0 * sigma) {
                w[k] = sigma / a;
            } else {
                w[k] = 0.0;
            }
        }
        if (!fit_line(x, y, w, count, &normal, e, &sw)) {
            return false;
        }
    }
    double sum = 0.0;
    for (unsigned k = 0u; k < count; k++) {
        sum += w[k] * e[k] * e[k];
    }
    *rms_m = sqrt(sum / sw);
    *tangent_rad = fmod(normal + REF_PI / 2.0, REF_PI);
    if (margin != NULL) {
        *margin = closest;
    }
    return true;
}
