/* ego_tfit.c - see ego_tfit.h. */
#include "ego_tfit.h"

#include <stddef.h>

#include "ego_fx_math.h"

#define EGO_TFIT_WINDOW_MAX (2u * EGO_TFIT_MAX_HALF_WINDOW + 1u)
#define WEIGHT_ONE ((int64_t)FX_Q16_16_ONE)

_Static_assert(EGO_TFIT_WINDOW_MAX <= 64u, "moment sums assume a small window");

void ego_tfit_defaults(ego_tfit_params_t *params)
{
    params->half_window = 3u;
    params->passes = 2u;
    params->min_points = 3u;
    params->sigma_min = FX_Q16_16_C(0.005);
}

/* a / b rounded to nearest, b > 0. */
static int64_t div_round(int64_t a, int64_t b)
{
    return (a >= 0) ? (a + b / 2) / b : -((-a + b / 2) / b);
}

static int64_t abs64(int64_t v)
{
    return (v < 0) ? -v : v;
}

/* Line normal of the weighted points, and the residual of each point. */
typedef struct {
    fx_bam32_t normal; /* phi, mod 180 deg */
    fx_q16_16_t residual[EGO_TFIT_WINDOW_MAX];
    int64_t weight_sum; /* Q16.16 */
} line_fit_t;

static bool fit_line(const fx_q16_16_t *x, const fx_q16_16_t *y, const int32_t *w, uint16_t n,
                     line_fit_t *out)
{
    int64_t sw = 0;
    int64_t sx = 0;
    int64_t sy = 0;
    uint16_t used = 0u;
    for (uint16_t k = 0u; k < n; k++) {
        sw += w[k];
        sx += (int64_t)w[k] * x[k];
        sy += (int64_t)w[k] * y[k];
        used = (uint16_t)(used + (w[k] > 0 ? 1u : 0u));
    }
    if (used < 2u) {
        return false;
    }
    const int64_t xm = div_round(sx, sw); /* Q16.16 */
    const int64_t ym = div_round(sy, sw);

    /* Central moments, Q32.32: (w u >> 16) * u keeps every term < 2^43. */
    int64_t sxx = 0;
    int64_t syy = 0;
    int64_t sxy = 0;
    for (uint16_t k = 0u; k < n; k++) {
        const int64_t ux = x[k] - xm;
        const int64_t uy = y[k] - ym;
        const int64_t wux = fx_shr_round_s64(w[k] * ux, 16u);
        const int64_t wuy = fx_shr_round_s64(w[k] * uy, 16u);
        sxx += wux * ux;
        syy += wuy * uy;
        sxy += wux * uy;
    }
    /* 2 phi = atan2(-2 Sxy, Syy - Sxx); phi is a normal, mod 180 deg. */
    out->normal = fx_atan2(-2 * sxy, syy - sxx) >> 1;
    out->weight_sum = sw;

    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(out->normal, &s, &c);
    for (uint16_t k = 0u; k < n; k++) {
        const fx_q16_16_t ux = (fx_q16_16_t)(x[k] - xm);
        const fx_q16_16_t uy = (fx_q16_16_t)(y[k] - ym);
        out->residual[k] = fx_add_q16(fx_mul_q16_q30(ux, c), fx_mul_q16_q30(uy, s));
    }
    return true;
}

/* Median of the absolute residuals (n <= EGO_TFIT_WINDOW_MAX): insertion
 * sort of a copy. */
static int64_t median_abs(const fx_q16_16_t *residual, uint16_t n)
{
    int64_t a[EGO_TFIT_WINDOW_MAX]; /* a[0..k] filled by the insertion sort before any read */
    if (n == 0u || n > EGO_TFIT_WINDOW_MAX) {
        return 0;
    }
    for (uint16_t k = 0u; k < n; k++) {
        const int64_t v = abs64(residual[k]);
        uint16_t j = k;
        // cppcheck-suppress uninitvar ; a[0 .. k - 1] was written by the earlier rounds
        while (j > 0u && a[j - 1u] > v) {
            a[j] = a[j - 1u];
            j--;
        }
        a[j] = v;
    }
    return ((n % 2u) != 0u) ? a[n / 2u] : (a[n / 2u - 1u] + a[n / 2u] + 1) / 2;
}

/* Eq. 2: weights from the residuals and their scale sigma, taken robustly
 * as 1.4826 x the median absolute residual (the standard deviation for
 * Gaussian noise, but not inflated by the outliers it must reject), and
 * never below sigma_min (the range quantum and noise of the scanner). */
static void reweight(const fx_q16_16_t *residual, uint16_t n, fx_q16_16_t sigma_min, int32_t *w)
{
    /* 1.4826 in Q16.16 is 97163. */
    int64_t sigma = fx_shr_round_s64(median_abs(residual, n) * 97163, 16u);
    if (sigma < sigma_min) {
        sigma = sigma_min;
    }
    for (uint16_t k = 0u; k < n; k++) {
        const int64_t e = abs64(residual[k]);
        if (sigma == 0 || e <= sigma) {
            w[k] = (int32_t)WEIGHT_ONE;
        } else if (e <= 3 * sigma) {
            w[k] = (int32_t)div_round(sigma * WEIGHT_ONE, e);
        } else {
            w[k] = 0;
        }
    }
}

bool ego_tfit_fit(const fx_q16_16_t *x, const fx_q16_16_t *y, uint16_t count, uint8_t passes,
              fx_q16_16_t sigma_min, fx_bam32_t *tangent, fx_q16_16_t *rms)
{
    if (x == NULL || y == NULL || tangent == NULL || rms == NULL || count < 2u ||
        count > EGO_TFIT_WINDOW_MAX) {
        return false;
    }
    int32_t w[EGO_TFIT_WINDOW_MAX];
    for (uint16_t k = 0u; k < count; k++) {
        w[k] = (int32_t)WEIGHT_ONE;
    }
    line_fit_t fit;
    if (!fit_line(x, y, w, count, &fit)) {
        return false;
    }
    for (uint8_t pass = 0u; pass < passes; pass++) {
        reweight(fit.residual, count, sigma_min, w);
        if (!fit_line(x, y, w, count, &fit)) {
            return false;
        }
    }
    /* Weighted RMS residual of the last fit. */
    int64_t sum = 0;
    for (uint16_t k = 0u; k < count; k++) {
        const int64_t e = fit.residual[k];
        sum += fx_shr_round_s64(w[k] * e, 16u) * e;
    }
    /* Mean square, Q32.32: sum * 2^16 / weight_sum without overflowing. */
    const int64_t mean_sq = (sum < ((int64_t)1 << 46)) ? div_round(sum * WEIGHT_ONE, fit.weight_sum)
                                                       : (sum / fit.weight_sum) * WEIGHT_ONE;
    *rms = (fx_q16_16_t)fx_sqrt_u64((uint64_t)((mean_sq > 0) ? mean_sq : 0));
    *tangent = (fit.normal + FX_BAM32_QUARTER) & (FX_BAM32_HALF - 1u);
    return true;
}

void ego_tfit_fit_scan(ego_scan_t *scan, const ego_tfit_params_t *params)
{
    for (uint16_t i = 0u; i < scan->count; i++) {
        ego_tfit_fit_point(scan, params, i);
    }
}

void ego_tfit_fit_point(ego_scan_t *scan, const ego_tfit_params_t *params, uint16_t i)
{
    if (i >= scan->count) {
        return;
    }
    uint8_t n = params->half_window;
    if (n < 1u) {
        n = 1u;
    }
    if (n > EGO_TFIT_MAX_HALF_WINDOW) {
        n = EGO_TFIT_MAX_HALF_WINDOW;
    }
    const uint8_t min_points = (params->min_points < 2u) ? 2u : params->min_points;
    scan->flags[i] &= (uint8_t)~EGO_POINT_HAS_TANGENT;
    scan->tangent[i] = 0u;
    /* The window: up to n linked neighbours on each side. */
    uint16_t first = i;
    while (first > 0u && i - first < n && ego_scan_linked(scan, (uint16_t)(first - 1u))) {
        first--;
    }
    uint16_t last = i;
    while (last + 1u < scan->count && last - i < n && ego_scan_linked(scan, last)) {
        last++;
    }
    const uint16_t count = (uint16_t)(last - first + 1u);
    if (count < min_points) {
        return;
    }
    /* Relative to P[i]: small numbers, exact in Q16.16. */
    fx_q16_16_t rx[EGO_TFIT_WINDOW_MAX];
    fx_q16_16_t ry[EGO_TFIT_WINDOW_MAX];
    for (uint16_t k = 0u; k < count; k++) {
        rx[k] = fx_sub_q16(scan->x[first + k], scan->x[i]);
        ry[k] = fx_sub_q16(scan->y[first + k], scan->y[i]);
    }
    fx_bam32_t tangent = 0u;
    fx_q16_16_t rms = 0;
    if (ego_tfit_fit(rx, ry, count, params->passes, params->sigma_min, &tangent, &rms)) {
        scan->tangent[i] = tangent;
        scan->flags[i] |= EGO_POINT_HAS_TANGENT;
    }
}

/* A chord tangent spans at least CHORD_MIN (Q16.16 m), over up to
 * CHORD_REACH neighbours on each side: its direction's noise is about
 * sqrt(2) sigma / length, 4 deg for 1 cm range noise over 0.2 m, inside
 * the main direction's 10 deg. Between the neighbours at a 0.5-deg
 * spacing (3-9 cm at 3-10 m) it was 10-25 deg: a corridor's wall points
 * fell into the other group and it was no longer seen as one (1 cm noise:
 * 483 of 699 pairs failed within the budget, unflagged). */
#define CHORD_MIN FX_Q16_16_C(0.2)
#define CHORD_REACH 4u

void ego_tfit_chord_scan(ego_scan_t *scan)
{
    for (uint16_t i = 0u; i < scan->count; i++) {
        scan->flags[i] &= (uint8_t)~EGO_POINT_HAS_TANGENT;
        scan->tangent[i] = 0u;
        /* Linked neighbours on each side, widened one at a time on both
         * while the chord is under CHORD_MIN (the point itself where there
         * are none). */
        uint16_t a = i;
        uint16_t b = i;
        int64_t dx = 0;
        int64_t dy = 0;
        for (uint32_t k = 0u; k < CHORD_REACH; k++) {
            if (a > 0u && ego_scan_linked(scan, (uint16_t)(a - 1u))) {
                a--;
            }
            if (b + 1u < scan->count && ego_scan_linked(scan, b)) {
                b++;
            }
            dx = (int64_t)scan->x[b] - scan->x[a];
            dy = (int64_t)scan->y[b] - scan->y[a];
            if (dx * dx + dy * dy >= (int64_t)CHORD_MIN * CHORD_MIN) {
                break;
            }
        }
        if (a == b) {
            continue;
        }
        /* The quick arctangent: a group is 10 deg wide, its error 0.02. */
        scan->tangent[i] = fx_atan2_quick(dy, dx) & (FX_BAM32_HALF - 1u);
        scan->flags[i] |= EGO_POINT_HAS_TANGENT;
    }
}

