/* test_cov.c - the covariance of a registration (estimator/ego_cov.h)
 * against its double oracle (host_tests/ref/cov_ref.c) on random normal
 * equations, the cut's factor against its formula and against a
 * simulated trimmed fit, and its limits: a corridor's length, too few
 * matches, a singular system, saturation, a rounded matrix that stays
 * positive definite. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cov_ref.h"
#include "ego_cov.h"
#include "fx_host.h"
#include "lms_test_util.h"
#include "test_rng.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* Both forms of the same matches: the fixed-point sums as ego_track
 * accumulates them (normals Q14, arms Q16 m, residuals Q16 m) and the
 * double sums of the same quantised values. */
typedef struct {
    ego_cov_group_t fx[2];
    cov_ref_group_t ref[2];
} matches_t;

static void add_match(matches_t *m, unsigned g, double normal_rad, double arm_m, double d_m)
{
    const int64_t nx = (int64_t)lround(cos(normal_rad) * 16384.0);
    const int64_t ny = (int64_t)lround(sin(normal_rad) * 16384.0);
    const int64_t arm = (int64_t)lround(arm_m * 65536.0);
    const int64_t d = (int64_t)lround(d_m * 65536.0);
    const int64_t j[3] = {nx, ny, arm};
    const double jd[3] = {(double)nx / 16384.0, (double)ny / 16384.0, (double)arm / 65536.0};
    static const unsigned pairs[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (unsigned k = 0u; k < 6u; k++) {
        m->fx[g].a[k] += j[pairs[k][0]] * j[pairs[k][1]];
        m->ref[g].a[k] += jd[pairs[k][0]] * jd[pairs[k][1]];
    }
    m->fx[g].n++;
    m->ref[g].n += 1.0;
    m->fx[g].sum_sq += (uint64_t)(d * d);
    m->ref[g].sum_sq += ((double)d / 65536.0) * ((double)d / 65536.0);
}

static double worst; /* largest error seen, relative to its scale */

static double q30(fx_q2_30_t v)
{
    return (double)v / 1073741824.0;
}

static void fixed_matrix(const ego_cov_t *c, double m[3][3])
{
    m[0][0] = q30(c->xx);
    m[0][1] = m[1][0] = q30(c->xy);
    m[0][2] = m[2][0] = q30(c->xt);
    m[1][1] = q30(c->yy);
    m[1][2] = m[2][1] = q30(c->yt);
    m[2][2] = q30(c->tt);
}

/* Every entry within rel of the scale of its row and column
 * (sqrt(cov_ii cov_jj)) plus two LSB of Q2.30. */
static void assert_close_within(double want[3][3], const ego_cov_t *got, double rel, const char *what)
{
    double m[3][3];
    fixed_matrix(got, m);
    for (unsigned i = 0u; i < 3u; i++) {
        for (unsigned j = 0u; j < 3u; j++) {
            const double scale = sqrt(fabs(want[i][i] * want[j][j]));
            const double tol = rel * scale + 2.0 / 1073741824.0;
            char msg[160];
            (void)snprintf(msg, sizeof msg, "%s: cov[%u][%u] fixed %.6g, double %.6g", what, i, j,
                           m[i][j], want[i][j]);
            worst = fmax(worst, fmax(fabs(m[i][j] - want[i][j]) - 2.0 / 1073741824.0, 0.0) / (scale + 1e-30));
            TEST_ASSERT_TRUE_MESSAGE(fabs(m[i][j] - want[i][j]) <= tol, msg);
        }
    }
}

/* Within a thousandth: the arithmetic's own error. */
static void assert_close(double want[3][3], const ego_cov_t *got, const char *what)
{
    assert_close_within(want, got, 1e-3, what);
}

/* The cut factor's table is linear between steps of 1/64 (within 0.6 %
 * of kappa, ego_cov.c). */
#define CUT_TABLE_REL 7e-3

static void test_cov_matches_its_oracle_on_random_equations(void)
{
    uint32_t seed = 16u;
    uint32_t other = 61u; /* the scatters and cuts: a stream of their own */
    for (unsigned trial = 0u; trial < 400u; trial++) {
        matches_t m;
        memset(&m, 0, sizeof m);
        const unsigned n0 = tu_rand_range(&seed, 4u, 300u);
        const unsigned n1 = tu_rand_range(&seed, 0u, 200u);
        const double sigma = 0.001 * (double)tu_rand_range(&seed, 1u, 50u); /* 1-50 mm */
        /* The non-main group scatters 0.5-3 times as much; the cut lies
         * 1.8-6 of the main group's sigma out (none in every third). */
        const double scatter[2] = {sigma, sigma * 0.5 * (double)tu_rand_range(&other, 1u, 6u)};
        const double cut_m = (trial % 3u == 2u) ? 0.0 : sigma * (1.8 + 0.1 * (double)tu_rand_range(&other, 0u, 42u));
        const double reach = (double)tu_rand_range(&seed, 2u, 60u);           /* arms, m */
        const double main_rad = (double)tu_rand(&seed) / 4294967296.0 * 3.14159;
        for (unsigned i = 0u; i < n0 + n1; i++) {
            const unsigned g = (i < n0) ? 0u : 1u;
            const double spread = (g == 0u) ? 0.1 : 3.14159;
            const double normal = main_rad + ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * spread;
            const double arm = ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * 2.0 * reach;
            const double d = ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * 3.4641 * scatter[g];
            add_match(&m, g, normal, arm, d);
        }
        const bool weighted = (trial % 4u) != 3u;
        const fx_q16_16_t cut = (fx_q16_16_t)lround(cut_m * 65536.0);
        ego_cov_t got;
        ego_cov_estimate(m.fx, cut, weighted, &got);
        double want[3][3];
        TEST_ASSERT_TRUE(cov_ref_estimate(m.ref, (double)cut / 65536.0, weighted, want));
        if (want[0][0] >= 2.0 || want[1][1] >= 2.0 || want[2][2] >= 2.0) {
            continue; /* saturated: its own test */
        }
        char what[64];
        (void)snprintf(what, sizeof what, "trial %u (n %u + %u, %s, cut %.3f m)", trial, n0, n1,
                       weighted ? "weighted" : "plain", cut_m);
        assert_close_within(want, &got, (cut > 0) ? CUT_TABLE_REL : 1e-3, what);
    }
    char seen[80];
    (void)snprintf(seen, sizeof seen, "largest error %.2e of its scale", worst);
    TEST_MESSAGE(seen);
}

/* A corridor: every normal across it. Its length is the start's (1 m^2),
 * the width and the heading are measured. */
static void test_cov_corridor_length_is_not_measured(void)
{
    matches_t m;
    memset(&m, 0, sizeof m);
    uint32_t seed = 3u;
    for (unsigned i = 0u; i < 300u; i++) {
        const double side = (i % 2u == 0u) ? 1.5707963 : -1.5707963;
        const double arm = ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * 40.0;
        add_match(&m, 0u, side, arm, ((i % 3u) - 1.0) * 0.004);
    }
    ego_cov_t got;
    ego_cov_estimate(m.fx, 0, true, &got);
    char msg[96];
    (void)snprintf(msg, sizeof msg, "xx %.3g yy %.3g tt %.3g", q30(got.xx), q30(got.yy),
                   q30(got.tt));
    TEST_ASSERT_TRUE_MESSAGE(q30(got.xx) > 0.5, msg);   /* metres of doubt along */
    TEST_ASSERT_TRUE_MESSAGE(q30(got.yy) < 1e-6, msg);  /* a millimetre across */
    TEST_ASSERT_TRUE_MESSAGE(q30(got.tt) < 1e-6, msg);  /* a milliradian of heading */
    double want[3][3];
    TEST_ASSERT_TRUE(cov_ref_estimate(m.ref, 0.0, true, want));
    assert_close(want, &got, "corridor");
}

/* Scenes of the weak-direction test: 2 000; 400 under the emulator
 * (software doubles: the Jacobi oracle cost the CI half a minute there). */
#if defined(LMSEGO_UNIT_ON_TARGET)
#define WEAK_TRIALS 400u
#else
#define WEAK_TRIALS 2000u
#endif

/* The weak direction (ego_cov_weakest) against its oracle on random
 * scenes whose weakest direction stands out (the next eigenvalue at least
 * four times larger: where det / minors is the smallest eigenvalue): the
 * same direction within the Q0.7 resolution, the same kind, and weak
 * exactly when the share is below the threshold (away from it by a
 * factor of two). */
static void test_cov_weakest_matches_its_oracle(void)
{
    uint32_t seed = 77u;
    unsigned compared = 0u;
    for (unsigned trial = 0u; trial < WEAK_TRIALS; trial++) {
        matches_t m;
        memset(&m, 0, sizeof m);
        const unsigned n0 = tu_rand_range(&seed, 20u, 300u);
        const unsigned n1 = tu_rand_range(&seed, 0u, 60u);
        const double reach = (double)tu_rand_range(&seed, 1u, 40u);
        const double main_rad = (double)tu_rand(&seed) / 4294967296.0 * 3.14159;
        const double spread1 = (double)tu_rand_range(&seed, 1u, 100u) / 100.0 * 3.14159;
        for (unsigned i = 0u; i < n0 + n1; i++) {
            const unsigned g = (i < n0) ? 0u : 1u;
            const double spread = (g == 0u) ? 0.3 : spread1;
            const double normal = main_rad + 1.5707963 + ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * spread;
            const double arm = ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * 2.0 * reach;
            add_match(&m, g, normal, arm, 0.01);
        }
        const double lever = (double)tu_rand_range(&seed, 1u, 30u);
        double share = 0.0;
        double next = 0.0;
        double dir[3];
        TEST_ASSERT_TRUE(cov_ref_weakest(m.ref, main_rad, lever, &share, &next, dir));
        const fx_bam32_t main_bam = (fx_bam32_t)(uint32_t)lround(main_rad / 6.283185307179586 * 4294967296.0);
        ego_weak_t weak;
        ego_cov_weakest(m.fx, main_bam, (fx_q16_16_t)lround(lever * 65536.0), FX_Q2_30_ONE / 50, &weak);
        char msg[200];
        (void)snprintf(msg, sizeof msg, "trial %u: share %.4f dir %.3f %.3f %.3f, fixed kind %u dir %d %d %d",
                       trial, share, dir[0], dir[1], dir[2], weak.kind, weak.dir[0], weak.dir[1], weak.dir[2]);
        if (share > 0.04) {
            TEST_ASSERT_EQUAL_UINT8_MESSAGE(EGO_WEAK_NONE, weak.kind, msg);
        }
        if (share >= 0.01 || next < 4.0 * share) {
            continue;
        }
        TEST_ASSERT_TRUE_MESSAGE(weak.kind != EGO_WEAK_NONE, msg);
        const double dot = (dir[0] * weak.dir[0] + dir[1] * weak.dir[1] + dir[2] * weak.dir[2]) / 128.0;
        TEST_ASSERT_TRUE_MESSAGE(fabs(dot) > 0.99, msg);
        const double turn = fabs(dir[2]);
        if (fabs(turn - 0.342) > 0.02 && fabs(turn - 0.940) > 0.02) {
            const uint8_t kind = (turn < 0.342) ? EGO_WEAK_TRANSLATION : (turn > 0.940) ? EGO_WEAK_ROTATION
                                                                                         : EGO_WEAK_COUPLED;
            TEST_ASSERT_EQUAL_UINT8_MESSAGE(kind, weak.kind, msg);
        }
        compared++;
    }
    char seen[64];
    (void)snprintf(seen, sizeof seen, "%u weak scenes compared", compared);
    TEST_MESSAGE(seen);
    TEST_ASSERT_TRUE(compared > WEAK_TRIALS / 20u);
}

/* The three kinds from their scenes: a corridor's length (translation
 * along it), a ring around the scanner (the turn), a ring seen from off
 * its centre (the two together); a room constrains everything. */
static void test_cov_weakest_kinds(void)
{
    ego_weak_t weak;
    matches_t m;
    uint32_t seed = 5u;
    /* Corridor along x: every normal across it (main direction 0). */
    memset(&m, 0, sizeof m);
    for (unsigned i = 0u; i < 200u; i++) {
        const double arm = ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * 40.0;
        add_match(&m, 0u, (i % 2u == 0u) ? 1.5707963 : -1.5707963, arm, 0.01);
    }
    ego_cov_weakest(m.fx, 0u, FX_Q16_16_C(10.0), FX_Q2_30_ONE / 50, &weak);
    TEST_ASSERT_EQUAL_UINT8(EGO_WEAK_TRANSLATION, weak.kind);
    TEST_ASSERT_TRUE(weak.dir[0] > 125 || weak.dir[0] < -125); /* along x */
    /* Ring around the scanner: normals radial, no lever arm. */
    memset(&m, 0, sizeof m);
    for (unsigned i = 0u; i < 200u; i++) {
        add_match(&m, 1u, 6.283185 * i / 200.0, 0.0, 0.01);
    }
    ego_cov_weakest(m.fx, 0u, FX_Q16_16_C(9.0), FX_Q2_30_ONE / 50, &weak);
    TEST_ASSERT_EQUAL_UINT8(EGO_WEAK_ROTATION, weak.kind);
    /* A ring of radius 9 seen from 6 m off its centre: the arms are
     * 6 sin(phi), the turn trades against a sideways slide (3 m off it,
     * the weak direction is 18 deg from the turn: a rotation). */
    memset(&m, 0, sizeof m);
    for (unsigned i = 0u; i < 200u; i++) {
        const double phi = 6.283185 * i / 200.0;
        add_match(&m, 1u, phi, 6.0 * sin(phi), 0.01);
    }
    ego_cov_weakest(m.fx, 0u, FX_Q16_16_C(9.0), FX_Q2_30_ONE / 50, &weak);
    TEST_ASSERT_EQUAL_UINT8(EGO_WEAK_COUPLED, weak.kind);
    /* A room: four walls, arms of metres. */
    memset(&m, 0, sizeof m);
    for (unsigned i = 0u; i < 200u; i++) {
        const double arm = ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * 8.0;
        add_match(&m, (i % 4u < 2u) ? 0u : 1u, 1.5707963 * (i % 4u), arm, 0.01);
    }
    ego_cov_weakest(m.fx, 0u, FX_Q16_16_C(4.0), FX_Q2_30_ONE / 50, &weak);
    TEST_ASSERT_EQUAL_UINT8(EGO_WEAK_NONE, weak.kind);
}

static void test_cov_unknown_without_enough_matches(void)
{
    matches_t m;
    memset(&m, 0, sizeof m);
    add_match(&m, 0u, 0.0, 1.0, 0.01);
    add_match(&m, 0u, 1.0, 2.0, 0.01);
    add_match(&m, 1u, 2.0, 3.0, 0.01);
    ego_cov_t got;
    ego_cov_estimate(m.fx, 0, true, &got);
    TEST_ASSERT_EQUAL_INT32(EGO_COV_SATURATED, got.xx);
    TEST_ASSERT_EQUAL_INT32(EGO_COV_SATURATED, got.yy);
    TEST_ASSERT_EQUAL_INT32(EGO_COV_SATURATED, got.tt);
    TEST_ASSERT_EQUAL_INT32(0, got.xy);
    /* No information at all (every sum 0): singular, unknown. */
    memset(&m, 0, sizeof m);
    m.fx[0].n = 50;
    ego_cov_estimate(m.fx, 0, true, &got);
    TEST_ASSERT_EQUAL_INT32(EGO_COV_SATURATED, got.tt);
    ego_cov_unknown(&got);
    TEST_ASSERT_EQUAL_INT32(EGO_COV_SATURATED, got.xx);
    TEST_ASSERT_EQUAL_INT32(0, got.yt);
}

/* Residuals of metres (a registration that fits nothing): variances past
 * 2 m^2 saturate, never wrap. */
static void test_cov_saturates(void)
{
    matches_t m;
    memset(&m, 0, sizeof m);
    for (unsigned i = 0u; i < 6u; i++) {
        add_match(&m, 0u, 0.3 * i, 0.5, 20.0);
    }
    ego_cov_t got;
    ego_cov_estimate(m.fx, 0, true, &got);
    TEST_ASSERT_EQUAL_INT32(EGO_COV_SATURATED, got.xx);
    TEST_ASSERT_TRUE(got.yy > 0);
}

/* What the output does where a corridor's length or a heading came from
 * the prediction: 1 m^2 more along the direction, 1 rad^2 more of turn. */
static void test_cov_unmeasured_parts(void)
{
    ego_cov_t c = {1000, 0, 5, 2000, 0, 30};
    const fx_q2_30_t cs = (fx_q2_30_t)lround(cos(0.5235988) * 1073741824.0);
    const fx_q2_30_t sn = (fx_q2_30_t)lround(sin(0.5235988) * 1073741824.0);
    ego_cov_unmeasured_along(&c, cs, sn);
    const double one = 1073741824.0;
    const int32_t guard = 2; /* each rounding adds 2 LSB to the variances (ego_cov.h) */
    TEST_ASSERT_INT32_WITHIN(1, 1000 + guard + (int32_t)lround((double)cs * cs / one), c.xx);
    TEST_ASSERT_INT32_WITHIN(1, (int32_t)lround((double)cs * sn / one), c.xy);
    TEST_ASSERT_INT32_WITHIN(1, 2000 + guard + (int32_t)lround((double)sn * sn / one), c.yy);
    TEST_ASSERT_EQUAL_INT32(5, c.xt);
    TEST_ASSERT_EQUAL_INT32(30 + guard, c.tt);
    ego_cov_unmeasured_rotation(&c);
    TEST_ASSERT_EQUAL_INT32(30 + guard + 1073741824, c.tt);
    ego_cov_unmeasured_rotation(&c); /* past 2 rad^2: saturated */
    TEST_ASSERT_EQUAL_INT32(EGO_COV_SATURATED, c.tt);
    ego_cov_unknown(&c);
    ego_cov_unmeasured_along(&c, 1073741824, 0);
    TEST_ASSERT_EQUAL_INT32(EGO_COV_SATURATED, c.xx);
}

/* The table of the cut's factor against its formula: within 0.7 % of
 * kappa everywhere, 1 for residuals far inside the cut, 16 where they
 * fill it, and never smaller for a wider scatter. */
static void test_cov_cut_factor_matches_its_formula(void)
{
    uint32_t last = 0u;
    for (uint32_t r = 0u; r <= 65536u; r += 97u) {
        const double want = cov_ref_cut_factor((double)r / 65536.0);
        const uint32_t got = ego_cov_cut_factor(r);
        char msg[96];
        (void)snprintf(msg, sizeof msg, "r %.4f: fixed %.4f, formula %.4f", (double)r / 65536.0,
                       (double)got / 65536.0, want);
        TEST_ASSERT_TRUE_MESSAGE(fabs((double)got / 65536.0 - want) <= CUT_TABLE_REL * want, msg);
        TEST_ASSERT_TRUE_MESSAGE(got >= last, msg);
        last = got;
    }
    TEST_ASSERT_EQUAL_UINT32(65536u, ego_cov_cut_factor(0u));
    TEST_ASSERT_EQUAL_UINT32(16u * 65536u, ego_cov_cut_factor(65536u));
}

/* A unit normal sample by Box-Muller. */
static double normal_sample(uint32_t *seed)
{
    const double u = ((double)tu_rand(seed) + 1.0) / 4294967297.0;
    const double v = (double)tu_rand(seed) / 4294967296.0;
    return sqrt(-2.0 * log(u)) * cos(2.0 * 3.14159265358979323846 * v);
}

#if defined(LMSEGO_UNIT_ON_TARGET)
#define FIT_TRIALS 120u /* software doubles */
#define FIT_TOLERANCE 0.45 /* 3.5 standard errors of the scatter's estimate */
#else
#define FIT_TRIALS 2000u
#define FIT_TOLERANCE 0.12 /* four standard errors of the scatter's estimate */
#endif
/* The model errs on the side of caution where kappa is steep: 11 % over
 * at a cut of 2 sigma, 26 % at 1.35 (each fit's r scatters, and kappa is
 * convex in it); at most this much over. */
#define FIT_CAUTION 0.40
#define FIT_SAMPLES 400u

/* Why the cut's factor: a location fitted by least squares to the samples
 * within `cut` of it (iterated until it stays, as a registration's last
 * passes), 400 unit normal samples a trial. The scatter of the fits
 * against the model's variance from each fit's own residuals: kappa m /
 * n_in (m their mean square, n_in their count) agrees or errs on the side
 * of caution; m / n_in alone, the residuals' scatter, is short by about
 * kappa (3.8 at a cut of 1.35 sigma). */
static void check_trimmed_fit(double cut, uint32_t seed)
{
    double scatter = 0.0;
    double model = 0.0;
    double plain = 0.0;
    static double x[FIT_SAMPLES];
    for (unsigned trial = 0u; trial < FIT_TRIALS; trial++) {
        for (unsigned i = 0u; i < FIT_SAMPLES; i++) {
            x[i] = normal_sample(&seed);
        }
        double mu = 0.0;
        double m = 0.0;
        double n_in = 0.0;
        for (unsigned pass = 0u; pass < 50u; pass++) {
            double sum = 0.0;
            double sum_sq = 0.0;
            n_in = 0.0;
            for (unsigned i = 0u; i < FIT_SAMPLES; i++) {
                if (fabs(x[i] - mu) <= cut) {
                    sum += x[i];
                    sum_sq += (x[i] - mu) * (x[i] - mu);
                    n_in += 1.0;
                }
            }
            m = sum_sq / n_in;
            const double next = sum / n_in;
            if (next == mu) {
                break;
            }
            mu = next;
        }
        scatter += mu * mu;
        model += cov_ref_cut_factor(m / (cut * cut)) * m / n_in;
        plain += m / n_in;
    }
    char msg[128];
    (void)snprintf(msg, sizeof msg, "cut %.2f sigma: fits scatter %.3g, model %.3g, residuals alone %.3g",
                   cut, scatter / FIT_TRIALS, model / FIT_TRIALS, plain / FIT_TRIALS);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(model >= (1.0 - FIT_TOLERANCE) * scatter, msg);
    TEST_ASSERT_TRUE_MESSAGE(model <= (1.0 + FIT_CAUTION + FIT_TOLERANCE) * scatter, msg);
    if (cut < 2.0) {
        TEST_ASSERT_TRUE_MESSAGE(plain < 0.5 * scatter, msg);
    }
}

static void test_cov_cut_factor_matches_a_trimmed_fit(void)
{
    check_trimmed_fit(1.35, 5u); /* 3 cm of range noise, a 5 cm cut */
    check_trimmed_fit(2.0, 6u);
    check_trimmed_fit(3.0, 7u);
}

/* Is the symmetric m positive definite (Cholesky)? */
static bool positive_definite(double m[3][3])
{
    double l[3][3] = {{0.0}};
    for (unsigned j = 0u; j < 3u; j++) {
        double d = m[j][j];
        for (unsigned k = 0u; k < j; k++) {
            d -= l[j][k] * l[j][k];
        }
        if (!(d > 0.0)) {
            return false;
        }
        l[j][j] = sqrt(d);
        for (unsigned i = j + 1u; i < 3u; i++) {
            double v = m[i][j];
            for (unsigned k = 0u; k < j; k++) {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = v / l[j][j];
        }
    }
    return true;
}

/* Registrations a few LSB of Q2.30 precise (0.05-0.5 mm residuals, long
 * arms: a heading known to tens of microradians): the rounded matrix a
 * consumer reads stays positive definite (without the guard, rounding
 * left a fifth of the noise-free campus's lines indefinite). */
static void test_cov_rounded_matrix_stays_positive_definite(void)
{
    uint32_t seed = 23u;
    for (unsigned trial = 0u; trial < 400u; trial++) {
        matches_t m;
        memset(&m, 0, sizeof m);
        const double sigma = 0.00005 * (double)tu_rand_range(&seed, 1u, 10u);
        const double reach = (double)tu_rand_range(&seed, 5u, 60u);
        const unsigned n = tu_rand_range(&seed, 20u, 360u);
        for (unsigned i = 0u; i < n; i++) {
            const double normal = (double)tu_rand(&seed) / 4294967296.0 * 6.2831853;
            const double arm = ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * 2.0 * reach;
            const double d = ((double)tu_rand(&seed) / 4294967296.0 - 0.5) * 3.4641 * sigma;
            add_match(&m, i % 3u == 0u ? 1u : 0u, normal, arm, d);
        }
        ego_cov_t got;
        ego_cov_estimate(m.fx, FX_Q16_16_C(0.015), true, &got);
        double q[3][3];
        fixed_matrix(&got, q);
        char msg[160];
        (void)snprintf(msg, sizeof msg, "trial %u: xx %d xy %d xt %d yy %d yt %d tt %d (LSB)", trial,
                       (int)got.xx, (int)got.xy, (int)got.xt, (int)got.yy, (int)got.yt, (int)got.tt);
        TEST_ASSERT_TRUE_MESSAGE(positive_definite(q), msg);
    }
}

/* A uniform double in [0, 1) from the splitmix64 stream. */
static double rng_unit(uint64_t *rng)
{
    return (double)(test_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
}

/* The translation information of matches for ego_cov_on_objects: every
 * match's n n^T rounded to Q14 (T), and the same for the matches on
 * objects (O). */
typedef struct {
    int32_t all[3];
    int32_t objects[3];
} objects_info_t;

static void add_normal(objects_info_t *info, double rad, bool on_object)
{
    const double nx = cos(rad);
    const double ny = sin(rad);
    const int32_t e[3] = {(int32_t)lround(16384.0 * nx * nx), (int32_t)lround(16384.0 * nx * ny),
                          (int32_t)lround(16384.0 * ny * ny)};
    for (unsigned k = 0u; k < 3u; k++) {
        info->all[k] += e[k];
        info->objects[k] += on_object ? e[k] : 0;
    }
}

/* The oracle on an info's integers (exact in double: below 2^22). */
static bool objects_oracle(const objects_info_t *info, double share, double *mu, double eig[2])
{
    const double t[3] = {(double)info->all[0], (double)info->all[1], (double)info->all[2]};
    const double o[3] = {(double)info->objects[0], (double)info->objects[1], (double)info->objects[2]};
    return cov_ref_on_objects(t, o, share, mu, eig);
}

#if defined(LMSEGO_UNIT_ON_TARGET)
#define OBJECTS_TRIALS 400u
#else
#define OBJECTS_TRIALS 2000u
#endif
/* Decisions within this relative distance of the threshold are not
 * compared (the double roots themselves are good to 1e-8). */
#define OBJECTS_BAND 1e-3
/* The kernel truncates share T to whole Q14 units: each entry of its M
 * lies within one unit of the exact one, its least eigenvalue within two.
 * Where that eigenvalue is within this of 0 the decision is the
 * truncation's. */
#define OBJECTS_ROUNDING 2.0

/* The objects test against its double oracle on random information sums:
 * T from 1-200 unit normals (uniform or in a fan, a corridor's), O from a
 * random subset (a random share of them, or those within a sector: the
 * objects' normals all in one direction), share 0.05-0.5 (every third
 * case 0.2-2 % either side of its threshold). It holds exactly when the
 * least generalized eigenvalue mu of T - O against T is below share (away
 * from it by OBJECTS_BAND). */
static void test_cov_on_objects_matches_oracle(void)
{
    uint64_t rng = 0x0B1EC75u;
    unsigned fired = 0u;
    unsigned quiet = 0u;
    unsigned band = 0u;
    unsigned rounding = 0u;
    unsigned singular = 0u;
    unsigned near = 0u; /* shares put near their threshold */
    for (unsigned trial = 0u; trial < OBJECTS_TRIALS; trial++) {
        objects_info_t info;
        memset(&info, 0, sizeof info);
        const unsigned k = 1u + (unsigned)(test_rng_next(&rng) % 200u);
        const double base = rng_unit(&rng) * 6.283185307179586;
        const double fan = (0.05 + 0.95 * rng_unit(&rng)) * 3.14159265358979323846;
        const bool by_sector = (test_rng_next(&rng) & 1u) != 0u;
        const double p_object = rng_unit(&rng);
        const double sector_mid = rng_unit(&rng) * 3.14159265358979323846;
        const double sector_half = rng_unit(&rng) * 0.8;
        for (unsigned i = 0u; i < k; i++) {
            const double rad = base + (rng_unit(&rng) - 0.5) * fan;
            bool on_object;
            if (by_sector) {
                /* A normal's line within sector_half of the sector's. */
                on_object = fx_host_line_angle_diff(rad, sector_mid) <= sector_half;
            } else {
                on_object = rng_unit(&rng) < p_object;
            }
            add_normal(&info, rad, on_object);
        }
        double mu = 0.0;
        double eig[2];
        double share_d = 0.05 + 0.45 * rng_unit(&rng);
        const double side = ((test_rng_next(&rng) & 1u) != 0u) ? 1.0 : -1.0;
        const double off = (0.002 + 0.018 * rng_unit(&rng)) * side;
        if (trial % 3u == 2u && objects_oracle(&info, share_d, &mu, eig) && mu * (1.0 + off) >= 0.05 &&
            mu * (1.0 + off) <= 0.5) {
            share_d = mu * (1.0 + off);
            near++;
        }
        const fx_q2_30_t share_q30 = (fx_q2_30_t)lround(share_d * 1073741824.0);
        const double share = (double)share_q30 / 1073741824.0;
        const bool got = ego_cov_on_objects(info.all, info.objects, share_q30);

        /* A T that is not positive definite (one normal, or a few along
         * one line) has no mu. */
        if ((int64_t)info.all[0] * info.all[2] - (int64_t)info.all[1] * info.all[1] <= 0 ||
            !objects_oracle(&info, share, &mu, eig)) {
            singular++;
            continue;
        }
        char msg[240];
        (void)snprintf(msg, sizeof msg,
                       "trial %u (k %u): T %ld %ld %ld, O %ld %ld %ld, share %.5f: got %d; mu %.6f, "
                       "M's eigenvalues %.2f %.2f",
                       trial, k, (long)info.all[0], (long)info.all[1], (long)info.all[2], (long)info.objects[0],
                       (long)info.objects[1], (long)info.objects[2], share, got, mu, eig[0], eig[1]);
        if (fabs(mu - share) <= OBJECTS_BAND * share) {
            band++;
            continue;
        }
        /* mu < share exactly when M is not positive definite: the oracle
         * agrees with itself. */
        TEST_ASSERT_TRUE_MESSAGE((mu < share) == (eig[0] < 0.0), msg);
        if (fabs(eig[0]) <= OBJECTS_ROUNDING) {
            rounding++;
            continue;
        }
        TEST_ASSERT_EQUAL_MESSAGE(mu < share, got, msg);
        fired += got ? 1u : 0u;
        quiet += got ? 0u : 1u;
    }
    const unsigned skipped = band + rounding + singular;
    char seen[200];
    (void)snprintf(seen, sizeof seen,
                   "%u fired, %u quiet (%u near the threshold); skipped %u (%u at the threshold, %u at the "
                   "rounding, %u T singular)",
                   fired, quiet, near, skipped, band, rounding, singular);
    TEST_MESSAGE(seen);
    TEST_ASSERT_TRUE_MESSAGE(fired >= OBJECTS_TRIALS / 10u, seen);
    TEST_ASSERT_TRUE_MESSAGE(quiet >= OBJECTS_TRIALS / 10u, seen);
    TEST_ASSERT_TRUE_MESSAGE(near >= OBJECTS_TRIALS / 10u, seen);
    TEST_ASSERT_TRUE_MESSAGE(skipped * 50u < OBJECTS_TRIALS, seen); /* under 2 % */
}

/* The objects test's limits: nothing on objects never holds, not even
 * where T constrains a direction not at all (the weak test's case) or is
 * empty; no objects under a room's information does not
 * hold, not even at half as the share; everything on objects holds; a
 * corridor whose length is measured only on objects (normals along y from
 * the walls, a few along x from the back of a truck) holds, and not with
 * those few off objects (a wall at the corridor's end). */
static void test_cov_on_objects_edges(void)
{
    const fx_q2_30_t share = (fx_q2_30_t)(FX_Q2_30_ONE / 5);
    objects_info_t info;

    memset(&info, 0, sizeof info);
    TEST_ASSERT_FALSE(ego_cov_on_objects(info.all, info.objects, share));
    info.all[2] = 3000; /* a corridor's: nothing along x */
    TEST_ASSERT_FALSE(ego_cov_on_objects(info.all, info.objects, share));
    info.all[0] = 50; /* along x a little, all of it on objects */
    info.objects[0] = 50;
    TEST_ASSERT_TRUE(ego_cov_on_objects(info.all, info.objects, share));

    /* A room: normals every 7 deg all round, none on objects. */
    memset(&info, 0, sizeof info);
    for (unsigned i = 0u; i < 100u; i++) {
        add_normal(&info, 0.122 * (double)i, false);
    }
    TEST_ASSERT_FALSE(ego_cov_on_objects(info.all, info.objects, share));
    TEST_ASSERT_FALSE(ego_cov_on_objects(info.all, info.objects, (fx_q2_30_t)(FX_Q2_30_ONE / 2)));
    /* A quarter of its normals on objects, spread all round: mu about
     * 0.75, the test holds from a share of about 0.75 up. */
    memset(&info, 0, sizeof info);
    for (unsigned i = 0u; i < 100u; i++) {
        add_normal(&info, 0.122 * (double)i, i % 4u == 0u);
    }
    double mu = 0.0;
    double eig[2];
    TEST_ASSERT_TRUE(objects_oracle(&info, 0.5, &mu, eig));
    char msg[48];
    (void)snprintf(msg, sizeof msg, "mu %.4f", mu);
    TEST_ASSERT_TRUE_MESSAGE(fabs(mu - 0.75) < 0.05, msg);
    const fx_q2_30_t below = (fx_q2_30_t)lround(0.99 * mu * 1073741824.0);
    const fx_q2_30_t above = (fx_q2_30_t)lround(1.01 * mu * 1073741824.0);
    TEST_ASSERT_FALSE(ego_cov_on_objects(info.all, info.objects, below));
    TEST_ASSERT_TRUE(ego_cov_on_objects(info.all, info.objects, above));

    /* Everything on objects: normals within 30 deg of 60 deg. */
    memset(&info, 0, sizeof info);
    for (unsigned i = 0u; i < 60u; i++) {
        add_normal(&info, (60.0 + 60.0 * ((double)i / 59.0 - 0.5)) * 3.14159265358979323846 / 180.0, true);
    }
    TEST_ASSERT_TRUE(ego_cov_on_objects(info.all, info.objects, share));

    /* The corridor: 100 normals across it (along +-y), 5 along x on a
     * truck. Also at the smallest share the kernel is used with. */
    memset(&info, 0, sizeof info);
    for (unsigned i = 0u; i < 100u; i++) {
        add_normal(&info, (i % 2u == 0u) ? 1.5707963267948966 : -1.5707963267948966, false);
    }
    for (unsigned i = 0u; i < 5u; i++) {
        add_normal(&info, 0.01 * ((double)i - 2.0), true);
    }
    TEST_ASSERT_TRUE(ego_cov_on_objects(info.all, info.objects, share));
    TEST_ASSERT_TRUE(ego_cov_on_objects(info.all, info.objects, (fx_q2_30_t)(FX_Q2_30_ONE / 20)));
    memset(info.objects, 0, sizeof info.objects);
    TEST_ASSERT_FALSE(ego_cov_on_objects(info.all, info.objects, share));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_cov_matches_its_oracle_on_random_equations);
    RUN_TEST(test_cov_corridor_length_is_not_measured);
    RUN_TEST(test_cov_cut_factor_matches_its_formula);
    RUN_TEST(test_cov_cut_factor_matches_a_trimmed_fit);
    RUN_TEST(test_cov_rounded_matrix_stays_positive_definite);
    RUN_TEST(test_cov_unknown_without_enough_matches);
    RUN_TEST(test_cov_saturates);
    RUN_TEST(test_cov_unmeasured_parts);
    RUN_TEST(test_cov_weakest_matches_its_oracle);
    RUN_TEST(test_cov_weakest_kinds);
    RUN_TEST(test_cov_on_objects_matches_oracle);
    RUN_TEST(test_cov_on_objects_edges);
    return UNITY_END();
}
