/* project_ref.c - see project_ref.h. */
#include "project_ref.h"

#include <math.h>
#include <string.h>

#include "fx_host.h"

#define SIDE_MAX EGO_PROJECT_MAX_SIDE
#define SHIFT_MAX EGO_PROJECT_MAX_SHIFT

static double bam_rad(fx_bam32_t a)
{
    return (double)a * 2.0 * FX_HOST_PI / 4294967296.0;
}

/* The angle between two lines (modulo pi), in [0, pi/2]. */
static double line_diff(double a, double b)
{
    double d = fmod(fabs(a - b), FX_HOST_PI);
    return (d > FX_HOST_PI / 2.0) ? FX_HOST_PI - d : d;
}

static bool faces(const ego_scan_t *s, unsigned i, double turn, double dir, bool tangent_needed)
{
    if ((s->flags[i] & EGO_POINT_HAS_TANGENT) == 0u) {
        return !tangent_needed;
    }
    return line_diff(bam_rad(s->tangent[i]) + turn, dir) >= 30.0 * FX_HOST_PI / 180.0;
}

static unsigned wrap(long b)
{
    return (unsigned)(((b % (long)EGO_PROJECT_BINS) + (long)EGO_PROJECT_BINS) % (long)EGO_PROJECT_BINS);
}

/* Direction dir's correlation over shifts -m..m around the centre's bin,
 * scaled to 1 at its maximum (all 0 when nothing faces it); the centre's
 * bin in *centre. */
static void correlate_dir(const ego_scan_t *last, const ego_scan_t *current, double dir,
                          double theta_rad, double cx, double cy, double bin, int m,
                          bool tangent_needed, double *corr, double *centre)
{
    const double c = cos(dir);
    const double s = sin(dir);
    double hl[EGO_PROJECT_BINS];
    double hc[EGO_PROJECT_BINS];
    memset(hl, 0, sizeof hl);
    memset(hc, 0, sizeof hc);
    for (unsigned i = 0u; i < last->count; i++) {
        if (faces(last, i, 0.0, dir, tangent_needed)) {
            const double p = fx_q16_16_to_double(last->x[i]) * c + fx_q16_16_to_double(last->y[i]) * s;
            const long b = (long)floor(p / bin);
            hl[wrap(b)] += 2.0;
            hl[wrap(b - 1)] += 1.0;
            hl[wrap(b + 1)] += 1.0;
        }
    }
    for (unsigned i = 0u; i < current->count; i++) {
        if (faces(current, i, theta_rad, dir, tangent_needed)) {
            const double x = fx_q16_16_to_double(current->x[i]);
            const double y = fx_q16_16_to_double(current->y[i]);
            const double qx = x * cos(theta_rad) - y * sin(theta_rad);
            const double qy = x * sin(theta_rad) + y * cos(theta_rad);
            hc[wrap((long)floor((qx * c + qy * s) / bin))] += 1.0;
        }
    }
    for (unsigned b = 0u; b < EGO_PROJECT_BINS; b++) { /* as the saturating bins */
        hl[b] = (hl[b] > 255.0) ? 255.0 : hl[b];
        hc[b] = (hc[b] > 255.0) ? 255.0 : hc[b];
    }
    *centre = floor((cx * c + cy * s) / bin + 0.5);
    double top = 0.0;
    for (int j = -m; j <= m; j++) {
        double sum = 0.0;
        for (unsigned b = 0u; b < EGO_PROJECT_BINS; b++) {
            sum += hc[b] * hl[wrap((long)b + (long)*centre + j)];
        }
        corr[j + m] = sum;
        top = (sum > top) ? sum : top;
    }
    for (int j = -m; j <= m; j++) {
        corr[j + m] = (top > 0.0) ? corr[j + m] / top : 0.0;
    }
}

int project_ref_scores(const ego_scan_t *last, const ego_scan_t *current, double main_dir_rad,
                       double theta_rad, double cx, double cy, double window, double bin,
                       double *score)
{
    int n = (int)floor(window / bin + 0.5);
    n = (n > SIDE_MAX) ? SIDE_MAX : n;
    const int m = n + (7 * n + 15) / 16 + 1;
    static double corr[EGO_PROJECT_DIRS][2 * SHIFT_MAX + 1];
    static double centre[EGO_PROJECT_DIRS];
    for (unsigned k = 0u; k < EGO_PROJECT_DIRS; k++) {
        const double dir = main_dir_rad + (double)k * FX_HOST_PI / EGO_PROJECT_DIRS;
        correlate_dir(last, current, dir, theta_rad, cx, cy, bin, m, false, corr[k], &centre[k]);
    }
    unsigned at = 0u;
    for (int ix = -n; ix <= n; ix++) {
        for (int iy = -n; iy <= n; iy++) {
            double v = 0.0;
            for (unsigned k = 0u; k < EGO_PROJECT_DIRS; k++) {
                const double dir = main_dir_rad + (double)k * FX_HOST_PI / EGO_PROJECT_DIRS;
                const double p = ((cx + ix * bin) * cos(dir) + (cy + iy * bin) * sin(dir)) / bin;
                const long j = (long)floor(p + 0.5) - (long)centre[k];
                if (j >= -m && j <= m) {
                    v += corr[k][j + m];
                }
            }
            score[at++] = v;
        }
    }
    return n;
}

int project_ref_along(const ego_scan_t *last, const ego_scan_t *current, double dir_rad,
                      double theta_rad, double cx, double cy, double window, double bin,
                      double *corr, double *centre_bin)
{
    int n = (int)floor(window / bin + 0.5);
    n = (n > SIDE_MAX) ? SIDE_MAX : n;
    correlate_dir(last, current, dir_rad, theta_rad, cx, cy, bin, n, true, corr, centre_bin);
    return n;
}
