/* ego_cov.c - see ego_cov.h. */
#include "ego_cov.h"

#include <stddef.h>

#include "ego_fx_math.h"

/* A 3x3 matrix of integer mantissas m with one power of two: m * 2^e. */
typedef struct {
    int64_t m[9];
    int32_t e;
} scaled3_t;

/* Mantissas of products: each at most 2^PRODUCT_BITS, so a row times a
 * column (three products) stays below 2^62. */
#define PRODUCT_BITS 30u
/* Of an inverse's input: its cofactors stay below 2^41, its determinant
 * below 3 2^61. */
#define INVERSE_BITS 20u
/* The residuals' scatter counts the range noise once; the errors of the
 * associations and of the chords the normals come from (a curve seen as
 * segments, 1 cm range steps), which pull alike over a scan, add about as
 * much again. Measured (docs/estimator.md, "The covariance"): with 1 the
 * mean NEES of the noisy synthetic sequences was 4.2-6.7 with 6-17 % of
 * the pairs outside the 99 % ellipse; with 2, 2.1-3.4 and 0.3-3.4 %. */
#define MODEL_FACTOR 2
/* A group's variance is pulled towards the pool's as if by this many
 * matches of it: the non-main group of a corridor may hold two, and the
 * groups weigh equally. */
#define PRIOR_MATCHES 4
/* The variance a rounding to Q2.30 may hide: three entries of a row each
 * half an LSB off shift an eigenvalue by at most 1.5 LSB. */
#define ROUNDING_GUARD 2

/* 1 / sqrt(kappa) (ego_cov.h) in Q15 at r = i / 64, i = 0 .. 20: the
 * normal noise cut at a (a from 8 down to 0.6) has r = (1 - t / P) / a^2,
 * 1 / sqrt(kappa) = 1 - t / P, with P = erf(a / sqrt 2) its share inside
 * and t = 2 a phi(a) (host_tests/unit/test_cov.c checks each entry against
 * that). Linear between entries, within 0.6 % of kappa; beyond r = 20/64,
 * and wherever below 1/4 (kappa 16), 1/4. */
static const uint16_t cut_root[21] = {32768, 32768, 32768, 32765, 32733, 32608, 32328, 31849,
                                      31150, 30220, 29056, 27660, 26032, 24176, 22094, 19788,
                                      17259, 14508, 11534, 8337,  4916};
#define CUT_ROOT_MIN 8192 /* 1/4 in Q15 */

/* An axis's unit is at most 2^14 times or below its SI one (each
 * entry of A below 2^56 in Q32, ego_track.c). */
#define MAX_AXIS_SHIFT 14

static uint64_t magnitude(int64_t v)
{
    return (v < 0) ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
}

/* Significant bits of v (0 for 0). */
static unsigned bits_u64(uint64_t v)
{
    const uint32_t high = (uint32_t)(v >> 32);
    if (high != 0u) {
        return 32u + fx_bits_u32(high);
    }
    return (v == 0u) ? 0u : fx_bits_u32((uint32_t)v);
}

/* v / 2^s rounded (s >= 0; 0 beyond 62 places). */
static int64_t shr_round(int64_t v, unsigned s)
{
    if (s == 0u) {
        return v;
    }
    return (s > 62u) ? 0 : fx_shr_round_s64(v, s);
}

/* Rescales the mantissas so that the largest has exactly `bits`
 * significant bits (none changes when all are 0). */
static void fit(scaled3_t *a, unsigned bits)
{
    uint64_t most = 0u;
    for (unsigned k = 0u; k < 9u; k++) {
        const uint64_t v = magnitude(a->m[k]);
        most = (v > most) ? v : most;
    }
    const unsigned have = bits_u64(most);
    if (have == 0u) {
        return;
    }
    if (have > bits) {
        const unsigned s = have - bits;
        for (unsigned k = 0u; k < 9u; k++) {
            a->m[k] = shr_round(a->m[k], s);
        }
        a->e += (int32_t)s;
    } else if (have < bits) {
        const unsigned s = bits - have;
        for (unsigned k = 0u; k < 9u; k++) {
            a->m[k] *= (int64_t)1 << s; /* |m| < 2^bits afterwards: no overflow */
        }
        a->e -= (int32_t)s;
    }
}

/* c = a b, both rescaled to PRODUCT_BITS first (c may be a or b). A
 * matrix times a diagonal one scales its columns. */
static void product(const scaled3_t *a, const scaled3_t *b, scaled3_t *c)
{
    scaled3_t x = *a;
    scaled3_t y = *b;
    fit(&x, PRODUCT_BITS);
    fit(&y, PRODUCT_BITS);
    for (unsigned i = 0u; i < 3u; i++) {
        for (unsigned j = 0u; j < 3u; j++) {
            c->m[3u * i + j] = x.m[3u * i] * y.m[j] + x.m[3u * i + 1u] * y.m[3u + j] +
                               x.m[3u * i + 2u] * y.m[6u + j];
        }
    }
    c->e = x.e + y.e;
}

static void transpose(const scaled3_t *a, scaled3_t *t)
{
    for (unsigned i = 0u; i < 3u; i++) {
        for (unsigned j = 0u; j < 3u; j++) {
            t->m[3u * i + j] = a->m[3u * j + i];
        }
    }
    t->e = a->e;
}

/* v * 2^s (s < 0: rounded; s > 0: saturated). */
static int64_t times_pow2(int64_t v, int32_t s)
{
    if (s <= 0) {
        return shr_round(v, (unsigned)-s);
    }
    if (bits_u64(magnitude(v)) + (unsigned)s > 62u) {
        return (v < 0) ? -INT64_MAX : INT64_MAX;
    }
    return v * ((int64_t)1 << s);
}

/* a += b, both rescaled to 60 bits (b too) and to the larger power of two. */
static void add(scaled3_t *a, scaled3_t *b)
{
    fit(a, 60u);
    fit(b, 60u);
    const int32_t e = (a->e > b->e) ? a->e : b->e;
    for (unsigned k = 0u; k < 9u; k++) {
        a->m[k] = shr_round(a->m[k], (unsigned)(e - a->e)) +
                  shr_round(b->m[k], (unsigned)(e - b->e));
    }
    a->e = e;
}

/* diag(d0, d1, d2) * 2^e. */
static void set_diagonal(scaled3_t *d, int64_t d0, int64_t d1, int64_t d2, int32_t e)
{
    *d = (scaled3_t){{d0, 0, 0, 0, d1, 0, 0, 0, d2}, e};
}

/* The cofactors of a symmetric m into c (c = adj(m), symmetric too);
 * returns the determinant. */
static int64_t cofactors(const int64_t m[9], int64_t c[9])
{
    c[0] = m[4] * m[8] - m[5] * m[7];
    c[1] = m[2] * m[7] - m[1] * m[8];
    c[2] = m[1] * m[5] - m[2] * m[4];
    c[4] = m[0] * m[8] - m[2] * m[6];
    c[5] = m[2] * m[3] - m[0] * m[5];
    c[8] = m[0] * m[4] - m[1] * m[3];
    c[3] = c[1];
    c[6] = c[2];
    c[7] = c[5];
    return m[0] * c[0] + m[1] * c[3] + m[2] * c[6];
}

/* The inverse of a symmetric positive definite a by its cofactors (a is
 * rescaled); false when its determinant is not positive. */
static bool inverse(scaled3_t *a, scaled3_t *inv)
{
    fit(a, INVERSE_BITS);
    int64_t c[9];
    const int64_t det = cofactors(a->m, c);
    if (det <= 0) {
        return false;
    }
    /* cofactor / det in mantissas of about 20 bits: det cut to 42. */
    const unsigned have = bits_u64((uint64_t)det);
    const unsigned s = (have > 42u) ? have - 42u : 0u;
    const int64_t d = shr_round(det, s);
    if (d <= 0) {
        return false; /* not reached: 42 significant bits are left */
    }
    for (unsigned k = 0u; k < 9u; k++) {
        inv->m[k] = (c[k] * ((int64_t)1 << 21)) / d; /* |c| < 2^41 */
    }
    inv->e = -21 - (int32_t)s - a->e;
    return true;
}

/* m * 2^(e + 30) rounded to Q2.30, saturated. */
static fx_q2_30_t to_q30(int64_t m, int32_t e)
{
    const int32_t up = e + 30;
    if (up >= 0) {
        if (up > 62 || bits_u64(magnitude(m)) + (unsigned)up > 62u) {
            return (m < 0) ? INT32_MIN : INT32_MAX;
        }
        return fx_sat_s32(m * ((int64_t)1 << up));
    }
    return fx_sat_s32(shr_round(m, (unsigned)-up));
}

void ego_cov_unknown(ego_cov_t *cov)
{
    cov->xx = EGO_COV_SATURATED;
    cov->xy = 0;
    cov->xt = 0;
    cov->yy = EGO_COV_SATURATED;
    cov->yt = 0;
    cov->tt = EGO_COV_SATURATED;
}

/* A variance that saturated is unknown: its covariances are 0 (else the
 * saturated diagonal and the unsaturated rest could make the matrix
 * indefinite: a negative NEES on the plaza). */
static void unknown_where_saturated(ego_cov_t *cov)
{
    if (cov->xx == EGO_COV_SATURATED) {
        cov->xy = 0;
        cov->xt = 0;
    }
    if (cov->yy == EGO_COV_SATURATED) {
        cov->xy = 0;
        cov->yt = 0;
    }
    if (cov->tt == EGO_COV_SATURATED) {
        cov->xt = 0;
        cov->yt = 0;
    }
}

/* Each variance that is known carries ROUNDING_GUARD LSB more: the
 * rounded matrix stays positive definite (its covariances within half an
 * LSB of their value each), and a consumer can invert it. */
static void guard_rounding(ego_cov_t *cov)
{
    fx_q2_30_t *variance[3] = {&cov->xx, &cov->yy, &cov->tt};
    for (unsigned i = 0u; i < 3u; i++) {
        if (*variance[i] != EGO_COV_SATURATED) {
            *variance[i] = fx_sat_s32((int64_t)*variance[i] + ROUNDING_GUARD);
        }
    }
    unknown_where_saturated(cov);
}

/* *entry + a b (a, b Q2.30 in the int32 range), rounded, saturated. */
static void add_product(fx_q2_30_t *entry, int64_t a, int64_t b)
{
    *entry = fx_sat_s32((int64_t)*entry + fx_shr_round_s64(a * b, 30u));
}

void ego_cov_unmeasured_along(ego_cov_t *cov, fx_q2_30_t c, fx_q2_30_t s)
{
    add_product(&cov->xx, c, c);
    add_product(&cov->xy, c, s);
    add_product(&cov->yy, s, s);
    guard_rounding(cov);
}

void ego_cov_unmeasured_rotation(ego_cov_t *cov)
{
    cov->tt = fx_sat_s32((int64_t)cov->tt + ((int64_t)1 << 30));
    unknown_where_saturated(cov);
}

/* Row and column of xx, xy, xt, yy, yt, tt in a 3x3 matrix. */
static const uint8_t row_of[6] = {0u, 0u, 0u, 1u, 1u, 2u};
static const uint8_t col_of[6] = {0u, 1u, 2u, 1u, 2u, 2u};

/* Symmetric 3x3 from xx, xy, xt, yy, yt, tt. */
static void set_symmetric(scaled3_t *a, const int64_t s[6], int32_t e)
{
    static const uint8_t entry[9] = {0u, 1u, 2u, 1u, 3u, 4u, 2u, 4u, 5u};
    for (unsigned k = 0u; k < 9u; k++) {
        a->m[k] = s[entry[k]];
    }
    a->e = e;
}

uint32_t ego_cov_cut_factor(uint32_t r_q16)
{
    const uint32_t last = (uint32_t)(sizeof cut_root / sizeof cut_root[0]) - 1u;
    const uint32_t i = r_q16 >> 10; /* steps of 1/64 */
    int64_t root = CUT_ROOT_MIN;
    if (i < last) {
        const int64_t frac = (int64_t)(r_q16 & 1023u);
        root = ((int64_t)cut_root[i] * (1024 - frac) + (int64_t)cut_root[i + 1u] * frac + 512) / 1024;
    }
    root = (root > CUT_ROOT_MIN) ? root : CUT_ROOT_MIN;
    return (uint32_t)((((int64_t)1 << 46) + root * root / 2) / (root * root));
}

/* v times a Q16 factor f (0 <= f <= 2^16) without overflow for any v. */
static int64_t times_q16(int64_t v, int64_t f)
{
    return (v / 65536) * f + fx_shr_round_s64((v % 65536) * f, 16u);
}

/* The variance of each group's residuals (Q32 m^2, ego_cov.h), into var. */
static void group_variances(const int64_t n[2], const uint64_t sum_sq[2], fx_q16_16_t cut,
                            int64_t var[2])
{
    const int64_t total = n[0] + n[1];
    const int64_t all = (int64_t)(sum_sq[0] + sum_sq[1]); /* below 2^46 (|d| < 4 m) */
    const int64_t cut_sq = (int64_t)cut * cut;
    for (unsigned k = 0u; k < 2u; k++) {
        /* (sum_k + PRIOR all / total) / (n_k + PRIOR), then times
         * MODEL_FACTOR total / (total - 3): one division each, exact to
         * an LSB of a millimetre's square. */
        const int64_t pulled = (int64_t)sum_sq[k] * total + PRIOR_MATCHES * all;
        const int64_t mean_sq = pulled / (total * (n[k] + PRIOR_MATCHES));
        int64_t v = pulled * MODEL_FACTOR / ((n[k] + PRIOR_MATCHES) * (total - 3));
        if (cut > 0) {
            const int64_t r = (mean_sq * 65536) / cut_sq;
            v = fx_shr_round_s64(v * (int64_t)ego_cov_cut_factor((uint32_t)((r < 65536) ? r : 65536)), 16u);
        }
        var[k] = v;
    }
}

void ego_cov_estimate(const ego_cov_group_t group[2], fx_q16_16_t cut, bool weighted,
                      ego_cov_t *cov)
{
    ego_cov_unknown(cov);
    /* The groups' sums in Q32 of their units (the normals' Q28 and the
     * arms' Q30 up to the lever arms' Q32 m^2). */
    int64_t g[2][6];
    int64_t n[2];
    uint64_t sum_sq[2];
    for (unsigned k = 0u; k < 2u; k++) {
        static const unsigned up[6] = {4u, 4u, 2u, 4u, 2u, 0u};
        for (unsigned i = 0u; i < 6u; i++) {
            g[k][i] = group[k].a[i] * ((int64_t)1 << up[i]); /* below 2^56 (ego_track.c) */
        }
        n[k] = group[k].n;
        sum_sq[k] = group[k].sum_sq;
    }
    if (!weighted) { /* one pool of matches */
        for (unsigned i = 0u; i < 6u; i++) {
            g[0][i] += g[1][i];
            g[1][i] = 0;
        }
        n[0] += n[1];
        n[1] = 0;
        sum_sq[0] += sum_sq[1];
        sum_sq[1] = 0u;
    }
    const int64_t total = n[0] + n[1];
    if (total <= 3) {
        return;
    }
    int64_t var[2];
    group_variances(n, sum_sq, cut, var);
    /* The covariance is scaled by the larger variance at the end, each
     * group's part of S by its share of it (Q16). */
    const int64_t variance = (var[0] > var[1]) ? var[0] : var[1];
    /* A = sum A_g / n_g and S = sum share_g A_g / n_g^2 (Q32). */
    int64_t a[6] = {0, 0, 0, 0, 0, 0};
    int64_t s[6] = {0, 0, 0, 0, 0, 0};
    for (unsigned k = 0u; k < 2u; k++) {
        if (n[k] <= 0) {
            continue;
        }
        const int64_t share = (variance > 0) ? (var[k] * 65536) / variance : 65536;
        for (unsigned i = 0u; i < 6u; i++) {
            const int64_t mean = g[k][i] / n[k];
            a[i] += mean;
            s[i] += times_q16(mean / n[k], share);
        }
    }
    /* The registration's damping (ego_track.c, solve): a thousandth of the
     * translation's and the rotation's own information. */
    const int64_t damp[3] = {(a[0] + a[3]) / 1000, (a[0] + a[3]) / 1000, a[5] / 1000};
    a[0] += damp[0];
    a[3] += damp[1];
    a[5] += damp[2];
    /* Each axis in its own power-of-two unit, 2^k_i, so that the diagonal
     * of A is near 1 (a corridor's length has a thousandth of the
     * information of its width, a heading a lever arm's square more):
     * every entry then keeps its bits through the inverse. Entry ij is
     * scaled by 2^-(k_i + k_j), the covariance back by the same. */
    static const unsigned diag[3] = {0u, 3u, 5u};
    int32_t k[3];
    for (unsigned i = 0u; i < 3u; i++) {
        const unsigned b = bits_u64((uint64_t)((a[diag[i]] > 0) ? a[diag[i]] : 1));
        k[i] = ((int32_t)b - 33) / 2;
        k[i] = (k[i] > MAX_AXIS_SHIFT) ? MAX_AXIS_SHIFT : (k[i] < -MAX_AXIS_SHIFT) ? -MAX_AXIS_SHIFT : k[i];
    }
    for (unsigned i = 0u; i < 6u; i++) {
        const int32_t by = -(k[row_of[i]] + k[col_of[i]]);
        a[i] = times_pow2(a[i], by);
        s[i] = times_pow2(s[i], by);
    }
    scaled3_t am;
    scaled3_t sm;
    set_symmetric(&am, a, -32);
    set_symmetric(&sm, s, -32);
    scaled3_t inv;
    if (!inverse(&am, &inv)) {
        return;
    }
    /* The residuals' part: A^-1 S A^-1 times the variance (Q32). */
    scaled3_t c;
    scaled3_t d;
    product(&inv, &sm, &c);
    product(&c, &inv, &c);
    set_diagonal(&d, variance, variance, variance, -32);
    product(&c, &d, &c);
    /* The start's part: where the equations barely constrain the pose the
     * damping keeps it at the start (the prediction), whose error is not
     * the residuals'. Each pass leaves R = A^-1 E of it (E the damping);
     * after two passes, with 1 m and 1 rad for the start's error, R^2 P
     * R^2^T: about 1 along a corridor's length, under 10^-10 where
     * surfaces constrain the pose. In the axes' units E_i 2^-2k_i and P_i
     * 2^2k_i. */
    const int32_t least = (k[0] < k[1]) ? ((k[0] < k[2]) ? k[0] : k[2]) : ((k[1] < k[2]) ? k[1] : k[2]);
    scaled3_t r2;
    scaled3_t start;
    set_diagonal(&d, times_pow2(damp[0], -2 * k[0]), times_pow2(damp[1], -2 * k[1]),
                 times_pow2(damp[2], -2 * k[2]), -32);
    product(&inv, &d, &r2);
    product(&r2, &r2, &r2);
    set_diagonal(&d, (int64_t)1 << (2 * (k[0] - least)), (int64_t)1 << (2 * (k[1] - least)),
                 (int64_t)1 << (2 * (k[2] - least)), 2 * least);
    product(&r2, &d, &start);
    transpose(&r2, &d);
    product(&start, &d, &start);
    add(&c, &start);
    /* Back to SI units: entry ij times 2^-(k_i + k_j); a variance below 0
     * is 0. */
    fx_q2_30_t *const entry[6] = {&cov->xx, &cov->xy, &cov->xt, &cov->yy, &cov->yt, &cov->tt};
    for (unsigned i = 0u; i < 6u; i++) {
        const unsigned r = row_of[i];
        const unsigned q = col_of[i];
        const fx_q2_30_t v = to_q30(c.m[3u * r + q], c.e - k[r] - k[q]);
        *entry[i] = (r == q && v < 0) ? 0 : v;
    }
    guard_rounding(cov);
}

/* Lever arms below this are taken as this: a scan of a small room still
 * turns its points by centimetres a degree. */
#define MIN_LEVER ((int64_t)1 << 15) /* 0.5 m in Q16.16 */
/* sin 20 deg and cos 20 deg in Q1.14: the weak direction's turn part
 * below the one is a translation, above the other a rotation. */
#define SIN_20_Q14 5604
#define COS_20_Q14 15396

fx_q16_16_t ego_cov_lever(fx_q16_16_t lever)
{
    return ((int64_t)lever > MIN_LEVER) ? lever : (fx_q16_16_t)MIN_LEVER;
}

/* v times a Q16 factor, rounded (|v| below 2^46, |f| at most 2^16). */
static int64_t mul_q16(int64_t v, int64_t f)
{
    return fx_shr_round_s64(v * f, 16u);
}

void ego_cov_weakest(const ego_cov_group_t group[2], fx_bam32_t main_direction, fx_q16_16_t lever,
                     fx_q2_30_t min_share, ego_weak_t *weak)
{
    weak->kind = EGO_WEAK_NONE;
    weak->dir[0] = 0;
    weak->dir[1] = 0;
    weak->dir[2] = 0;
    const int64_t n = group[0].n + group[1].n;
    if (n <= 3) {
        return;
    }
    /* The means of J J^T over every match, the turn in lever units, all
     * Q28: normals' products below 2^28, a normal times an arm below
     * 2^37 (Q30, 128 m) and an arm squared below 2^46 (Q32) before the
     * lever's division. */
    int64_t g[2][6] = {{0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0}};
    for (unsigned k = 0u; k < 2u; k++) {
        for (unsigned i = 0u; (i < 6u) && (group[k].n > 0); i++) {
            g[k][i] = group[k].a[i] / group[k].n;
        }
    }
    /* The main group's normals as the main direction's (n0 = (-s, c)):
     * their scatter about it is the normals' noise, not a constraint
     * along the main direction (noise gave a corridor's length a tenth of
     * its width's information). Its translation rows and columns are
     * projected on n0: P A P and P a_t with P = n0 n0^T. */
    fx_q2_30_t sin_q30;
    fx_q2_30_t cos_q30;
    fx_sincos(main_direction, &sin_q30, &cos_q30);
    const int64_t sn = fx_shr_round_s64(sin_q30, 14u); /* Q16: a product with an arm's
                                                         2^37 stays below 2^54 */
    const int64_t cs = fx_shr_round_s64(cos_q30, 14u);
    const int64_t across = mul_q16(mul_q16(g[0][0], sn), sn) - 2 * mul_q16(mul_q16(g[0][1], sn), cs) +
                           mul_q16(mul_q16(g[0][3], cs), cs);
    const int64_t arm = mul_q16(g[0][4], cs) - mul_q16(g[0][2], sn);
    g[0][0] = mul_q16(mul_q16(across, sn), sn);
    g[0][1] = -mul_q16(mul_q16(across, sn), cs);
    g[0][3] = mul_q16(mul_q16(across, cs), cs);
    g[0][2] = -mul_q16(arm, sn);
    g[0][4] = mul_q16(arm, cs);
    int64_t m[6];
    for (unsigned i = 0u; i < 6u; i++) {
        m[i] = (g[0][i] * group[0].n + g[1][i] * group[1].n) / n;
    }
    /* The turn in lever units: xt and yt divided by the lever, tt twice. */
    const int64_t l = ego_cov_lever(lever);
    m[2] = m[2] * ((int64_t)1 << 14) / l;
    m[4] = m[4] * ((int64_t)1 << 14) / l;
    m[5] = (m[5] * ((int64_t)1 << 14) / l) * ((int64_t)1 << 14) / l;
    const int64_t trace = m[0] + m[3] + m[5];
    if (trace <= 0) {
        return;
    }
    /* Scaled by a power of two so that the trace is in [2^18, 2^19)
     * (every entry below 2^19 in magnitude; cofactors below 2^38, the
     * determinant below 2^59). */
    const int32_t up = 18 - ((int32_t)bits_u64((uint64_t)trace) - 1);
    for (unsigned i = 0u; i < 6u; i++) {
        m[i] = times_pow2(m[i], up);
    }
    const int64_t scaled_trace = m[0] + m[3] + m[5];
    scaled3_t a;
    set_symmetric(&a, m, 0);
    int64_t c[9];
    const int64_t det = cofactors(a.m, c);
    const int64_t minors = c[0] + c[4] + c[8];
    /* The smallest eigenvalue is det / minors when it is well below the
     * others (the minors sum to the products of eigenvalue pairs), as it
     * is wherever the test matters; its share of the trace in Q30. */
    const int64_t smallest = (minors > 0 && det > 0) ? det / minors : 0;
    if (scaled_trace <= 0 || smallest * ((int64_t)1 << 30) / scaled_trace >= (int64_t)min_share) {
        return;
    }
    /* The adjugate is about minors v v^T: its column with the largest
     * diagonal entry is v's direction (rescaled to 30 bits to square it). */
    unsigned j = 0u;
    for (unsigned k = 1u; k < 3u; k++) {
        j = (c[4u * k] > c[4u * j]) ? k : j;
    }
    const int64_t col[3] = {c[j], c[3u + j], c[6u + j]};
    uint64_t most = 0u;
    for (unsigned k = 0u; k < 3u; k++) {
        most = (magnitude(col[k]) > most) ? magnitude(col[k]) : most;
    }
    const int32_t down = (bits_u64(most) > 30u) ? (int32_t)bits_u64(most) - 30 : 0;
    int64_t v[3];
    uint64_t norm_sq = 0u;
    for (unsigned k = 0u; k < 3u; k++) {
        v[k] = times_pow2(col[k], -down);
        norm_sq += (uint64_t)(v[k] * v[k]);
    }
    const uint64_t norm = fx_sqrt_u64(norm_sq);
    if (norm == 0u) {
        /* No direction stands out (every entry 0): all of it is weak;
         * call it the turn and the translation together. */
        weak->kind = EGO_WEAK_COUPLED;
        weak->dir[2] = 127;
        return;
    }
    int64_t unit[3];
    for (unsigned k = 0u; k < 3u; k++) {
        unit[k] = v[k] * ((int64_t)1 << 14) / (int64_t)norm;
        const int64_t q = fx_shr_round_s64(unit[k], 7u); /* Q1.14 -> Q0.7 */
        weak->dir[k] = (int8_t)((q > 127) ? 127 : (q < -127) ? -127 : q);
    }
    const int64_t turn = (unit[2] < 0) ? -unit[2] : unit[2];
    weak->kind = (turn < SIN_20_Q14)   ? (uint8_t)EGO_WEAK_TRANSLATION
                 : (turn > COS_20_Q14) ? (uint8_t)EGO_WEAK_ROTATION
                                       : (uint8_t)EGO_WEAK_COUPLED;
}

void ego_cov_unmeasured_direction(ego_cov_t *cov, const ego_weak_t *weak, fx_q16_16_t lever)
{
    /* u = (dir_x, dir_y, dir_t / lever) in Q30 of SI units; u u^T added. */
    const int64_t l = ego_cov_lever(lever);
    const int64_t u[3] = {(int64_t)weak->dir[0] * ((int64_t)1 << 23), (int64_t)weak->dir[1] * ((int64_t)1 << 23),
                          (int64_t)weak->dir[2] * ((int64_t)1 << 39) / l};
    fx_q2_30_t *const entry[6] = {&cov->xx, &cov->xy, &cov->xt, &cov->yy, &cov->yt, &cov->tt};
    for (unsigned i = 0u; i < 6u; i++) {
        /* Each factor below 2^31 + lever's 2^31 / 0.5 m: clamp the turn's. */
        add_product(entry[i], fx_sat_s32(u[row_of[i]]), fx_sat_s32(u[col_of[i]]));
    }
    guard_rounding(cov);
}
