/* cov_ref.c - see cov_ref.h. The model of ego_cov.h:
 *   cov = A^-1 S A^-1 + R^2 P R^2^T, A = sum A_g / n_g + E,
 *   S = sum s_g^2 A_g / n_g^2, R = A^-1 E,
 *   s_g^2 = 2 kappa(m_g / cut^2) m_g n / (n - 3), m_g = (sum_g d^2 + 4 m) / (n_g + 4),
 *   m = sum d^2 / n, E = diag(e_t, e_t, e_r) the registration's damping,
 *   P = I (1 m, 1 rad); then 2^-29 more on each variance (the guard). */
#include "cov_ref.h"

#include <math.h>

#include <string.h>

static void sym(const double s[6], double m[3][3])
{
    m[0][0] = s[0];
    m[0][1] = m[1][0] = s[1];
    m[0][2] = m[2][0] = s[2];
    m[1][1] = s[3];
    m[1][2] = m[2][1] = s[4];
    m[2][2] = s[5];
}

static void mul(double a[3][3], double b[3][3], double c[3][3])
{
    double t[3][3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            t[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    memcpy(c, t, sizeof t);
}

static bool invert(double a[3][3], double inv[3][3])
{
    const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    const double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    const double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    if (!(det > 0.0)) {
        return false;
    }
    inv[0][0] = c00 / det;
    inv[1][0] = c01 / det;
    inv[2][0] = c02 / det;
    inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
    inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
    inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
    inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
    inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
    inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
    return true;
}

static double cut_ratio(double a, double *kappa)
{
    const double p = erf(a / sqrt(2.0));
    const double t = 2.0 * a * exp(-0.5 * a * a) / sqrt(2.0 * 3.14159265358979323846);
    *kappa = (p / (p - t)) * (p / (p - t));
    return (1.0 - t / p) / (a * a);
}

double cov_ref_cut_factor(double r)
{
    double lo = 0.01;
    double hi = 40.0;
    double kappa = 1.0;
    for (int i = 0; i < 200; i++) {
        const double a = 0.5 * (lo + hi);
        if (cut_ratio(a, &kappa) > r) {
            lo = a;
        } else {
            hi = a;
        }
    }
    (void)cut_ratio(0.5 * (lo + hi), &kappa);
    return (kappa < 16.0) ? kappa : 16.0;
}

bool cov_ref_estimate(const cov_ref_group_t group[2], double cut_m, bool weighted,
                      double cov[3][3])
{
    cov_ref_group_t g[2];
    memcpy(g, group, sizeof g);
    if (!weighted) {
        for (int i = 0; i < 6; i++) {
            g[0].a[i] += g[1].a[i];
            g[1].a[i] = 0.0;
        }
        g[0].n += g[1].n;
        g[1].n = 0.0;
        g[0].sum_sq += g[1].sum_sq;
        g[1].sum_sq = 0.0;
    }
    const double total = g[0].n + g[1].n;
    if (total <= 3.0) {
        return false;
    }
    const double pool = (g[0].sum_sq + g[1].sum_sq) / total;
    double a[6] = {0};
    double s[6] = {0};
    for (int k = 0; k < 2; k++) {
        if (g[k].n <= 0.0) {
            continue;
        }
        const double mean_sq = (g[k].sum_sq + 4.0 * pool) / (g[k].n + 4.0);
        const double kappa = (cut_m > 0.0) ? cov_ref_cut_factor(mean_sq / (cut_m * cut_m)) : 1.0;
        const double variance = 2.0 * kappa * mean_sq * total / (total - 3.0);
        for (int i = 0; i < 6; i++) {
            a[i] += g[k].a[i] / g[k].n;
            s[i] += variance * g[k].a[i] / (g[k].n * g[k].n);
        }
    }
    const double et = (a[0] + a[3]) / 1000.0;
    const double er = a[5] / 1000.0;
    a[0] += et;
    a[3] += et;
    a[5] += er;
    double am[3][3];
    double sm[3][3];
    double inv[3][3];
    sym(a, am);
    sym(s, sm);
    if (!invert(am, inv)) {
        return false;
    }
    double c[3][3];
    mul(inv, sm, c);
    mul(c, inv, c);
    double r[3][3];
    const double e[3] = {et, et, er};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            r[i][j] = inv[i][j] * e[j];
        }
    }
    double r2[3][3];
    mul(r, r, r2);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            double start = 0.0;
            for (int k = 0; k < 3; k++) {
                start += r2[i][k] * r2[j][k];
            }
            cov[i][j] = c[i][j] + start + ((i == j) ? 2.0 / 1073741824.0 : 0.0);
        }
    }
    return true;
}

/* Eigenvalues (the diagonal after) and eigenvectors (columns of v) of the
 * symmetric a by cyclic Jacobi rotations. */
static void jacobi3(double a[3][3], double v[3][3])
{
    for (unsigned i = 0u; i < 3u; i++) {
        for (unsigned j = 0u; j < 3u; j++) {
            v[i][j] = (i == j) ? 1.0 : 0.0;
        }
    }
    for (unsigned sweep = 0u; sweep < 50u; sweep++) {
        for (unsigned p = 0u; p < 2u; p++) {
            for (unsigned q = p + 1u; q < 3u; q++) {
                if (fabs(a[p][q]) < 1e-300) {
                    continue;
                }
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = ((theta >= 0.0) ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                const double c = 1.0 / sqrt(t * t + 1.0);
                const double s = t * c;
                for (unsigned k = 0u; k < 3u; k++) { /* A <- A J */
                    const double akp = a[k][p];
                    const double akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (unsigned k = 0u; k < 3u; k++) { /* A <- J^T A */
                    const double apk = a[p][k];
                    const double aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (unsigned k = 0u; k < 3u; k++) {
                    const double vkp = v[k][p];
                    const double vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
}

bool cov_ref_weakest(const cov_ref_group_t group[2], double main_rad, double lever_m,
                     double *share, double *next_share, double dir[3])
{
    const double n = group[0].n + group[1].n;
    if (n <= 3.0) {
        return false;
    }
    const double l = (lever_m > 0.5) ? lever_m : 0.5;
    const double nx = -sin(main_rad);
    const double ny = cos(main_rad);
    double m[3][3] = {{0.0}};
    for (unsigned g = 0u; g < 2u; g++) {
        const double *a = group[g].a;
        double e[3][3] = {{a[0], a[1], a[2]}, {a[1], a[3], a[4]}, {a[2], a[4], a[5]}};
        if (g == 0u) { /* P A P on the translation, P a_t */
            const double across = nx * nx * e[0][0] + 2.0 * nx * ny * e[0][1] + ny * ny * e[1][1];
            const double arm = nx * e[0][2] + ny * e[1][2];
            e[0][0] = across * nx * nx;
            e[0][1] = e[1][0] = across * nx * ny;
            e[1][1] = across * ny * ny;
            e[0][2] = e[2][0] = arm * nx;
            e[1][2] = e[2][1] = arm * ny;
        }
        for (unsigned i = 0u; i < 3u; i++) {
            for (unsigned j = 0u; j < 3u; j++) {
                const double scale = ((i == 2u) ? 1.0 / l : 1.0) * ((j == 2u) ? 1.0 / l : 1.0);
                m[i][j] += e[i][j] * scale / n;
            }
        }
    }
    const double trace = m[0][0] + m[1][1] + m[2][2];
    if (trace <= 0.0) {
        return false;
    }
    double v[3][3];
    jacobi3(m, v);
    unsigned k = 0u;
    for (unsigned i = 1u; i < 3u; i++) {
        k = (m[i][i] < m[k][k]) ? i : k;
    }
    *share = m[k][k] / trace;
    double next = INFINITY;
    for (unsigned i = 0u; i < 3u; i++) {
        next = (i != k && m[i][i] < next) ? m[i][i] : next;
    }
    *next_share = next / trace;
    for (unsigned i = 0u; i < 3u; i++) {
        dir[i] = v[i][k];
    }
    return true;
}

bool cov_ref_on_objects(const double all[3], const double objects[3], double share, double *mu,
                        double eig[2])
{
    const double det_t = all[0] * all[2] - all[1] * all[1];
    if (!(all[0] > 0.0) || !(det_t > 0.0)) {
        return false;
    }
    /* det(A - mu T) = det_t mu^2 - b mu + det_a, A = T - O. */
    const double a[3] = {all[0] - objects[0], all[1] - objects[1], all[2] - objects[2]};
    const double b = a[0] * all[2] + a[2] * all[0] - 2.0 * a[1] * all[1];
    const double det_a = a[0] * a[2] - a[1] * a[1];
    const double disc = fmax(b * b - 4.0 * det_t * det_a, 0.0);
    /* The roots q / det_t and det_a / q, without cancellation. */
    const double q = 0.5 * (b + copysign(sqrt(disc), b));
    const double r0 = q / det_t;
    const double r1 = (q != 0.0) ? det_a / q : r0;
    *mu = fmin(r0, r1);
    const double m[3] = {(1.0 - share) * all[0] - objects[0], (1.0 - share) * all[1] - objects[1],
                         (1.0 - share) * all[2] - objects[2]};
    const double mid = 0.5 * (m[0] + m[2]);
    const double half = hypot(0.5 * (m[0] - m[2]), m[1]);
    eig[0] = mid - half;
    eig[1] = mid + half;
    return true;
}
