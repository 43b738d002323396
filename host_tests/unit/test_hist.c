/* test_hist.c - angle histograms and their correlation (estimator/ego_hist.c):
 * bin geometry, the four histogram kinds on constructed scans, and the
 * correlation against a double-precision evaluation of eq. 5. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fx_host.h"
#include "ego_fx_math.h"
#include "ego_hist.h"
#include "synth_scan.h"
#include "ego_tfit.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

static lms_scan_t g_lms;
static ego_scan_t g_last;
static ego_scan_t g_current;
static ego_hist_t g_hl;
static ego_hist_t g_hc;
static ego_hist_t g_h2;

static double deg_of_bam(int32_t signed_bam)
{
    return (double)signed_bam * 180.0 / 2147483648.0;
}

/* Prepared scan with tangents, of the test room from (x, y, heading). */
static void room_scan(double x, double y, double heading_deg, unsigned count, ego_scan_t *scan)
{
    synth_scan(synth_room, synth_room_walls, x, y, heading_deg * FX_HOST_PI / 180.0, count,
               LMS_UNIT_CM, &g_lms);
    ego_prep_params_t prep;
    ego_prep_defaults(&prep);
    TEST_ASSERT_EQUAL_INT(EGO_PREP_OK, ego_scan_prepare(synth_range(&g_lms), &prep, scan));
    ego_tfit_params_t fit;
    ego_tfit_defaults(&fit);
    ego_tfit_fit_scan(scan, &fit);
}

static void test_hist_bin_geometry(void)
{
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        const fx_bam32_t c = ego_hist_bin_centre(b);
        TEST_ASSERT_EQUAL_UINT32(0u, c >> 31);
        TEST_ASSERT_EQUAL_UINT16(b, ego_hist_bin_of(c));
        TEST_ASSERT_EQUAL_UINT16(b, ego_hist_bin_of(c + FX_BAM32_HALF)); /* lines: mod 180 */
    }
    TEST_ASSERT_EQUAL_UINT16(0u, ego_hist_bin_of(0u));
    TEST_ASSERT_EQUAL_UINT16(EGO_HIST_BINS - 1u, ego_hist_bin_of(FX_BAM32_HALF - 1u));
    TEST_ASSERT_EQUAL_UINT16(EGO_HIST_BINS / 2u, ego_hist_bin_of(FX_BAM32_QUARTER));
}

static void test_hist_ah_of_a_room_peaks_at_the_walls(void)
{
    room_scan(0.0, 0.0, 0.0, 361u, &g_current);
    ego_hist_params_t p;
    ego_hist_defaults(&p);
    p.kind = EGO_HIST_AH;
    const uint32_t votes = ego_hist_build(&g_current, &p, &g_hc);
    TEST_ASSERT_TRUE(votes > 200u);
    /* Walls along x (0 deg) and y (90 deg) dominate. */
    const uint16_t main_bin = ego_hist_bin_of(ego_hist_main_direction(&g_hc));
    /* cm ranges 4-9 cm apart scatter plain segment directions by degrees
     * (the paper's reason for HTAH): within 5 bins of a wall is enough. */
    const uint16_t off0 = (uint16_t)((main_bin < EGO_HIST_BINS / 2u) ? main_bin : EGO_HIST_BINS - main_bin);
    const uint16_t off90 =
        (uint16_t)((main_bin > EGO_HIST_BINS / 2u) ? main_bin - EGO_HIST_BINS / 2u : EGO_HIST_BINS / 2u - main_bin);
    TEST_ASSERT_TRUE(off0 <= 5u || off90 <= 5u);
    p.kind = EGO_HIST_LAH;
    TEST_ASSERT_EQUAL_UINT32(votes, ego_hist_build(&g_current, &p, &g_h2));
    uint64_t total_mm = 0u;
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        total_mm += g_h2.bin[b];
    }
    /* The surfaces seen add up to tens of metres. */
    TEST_ASSERT_TRUE(total_mm > 20000u && total_mm < 200000u);
}

static void test_hist_htah_votes_within_hah(void)
{
    room_scan(0.5, -0.3, 10.0, 361u, &g_current);
    ego_hist_params_t p;
    ego_hist_defaults(&p);
    p.kind = EGO_HIST_HTAH;
    const uint32_t htah_votes = ego_hist_build(&g_current, &p, &g_hc);
    p.kind = EGO_HIST_HAH;
    const uint32_t hah_votes = ego_hist_build(&g_current, &p, &g_h2);
    TEST_ASSERT_TRUE(htah_votes > 0u);
    /* HTAH tries a contiguous run from the tangent; HAH tries every bin
     * with the same test: HTAH's votes are a subset, bin by bin. */
    TEST_ASSERT_TRUE(htah_votes <= hah_votes);
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        TEST_ASSERT_TRUE_MESSAGE(g_hc.bin[b] <= g_h2.bin[b], "HTAH voted where HAH did not");
    }
    /* The angle of interest restricts HAH to the masked bins. */
    static uint8_t mask[EGO_HIST_BINS];
    ego_hist_t ah;
    p.kind = EGO_HIST_AH;
    (void)ego_hist_build(&g_current, &p, &ah);
    ego_hist_aoi_mask(&ah, 3u, 10u, mask);
    p.kind = EGO_HIST_HAH;
    p.aoi = mask;
    const uint32_t aoi_votes = ego_hist_build(&g_current, &p, &g_hl);
    TEST_ASSERT_TRUE(aoi_votes > 0u && aoi_votes <= hah_votes);
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        TEST_ASSERT_TRUE(mask[b] ? g_hl.bin[b] == g_h2.bin[b] : g_hl.bin[b] == 0u);
    }
}

/* Eq. 5 in doubles for shift j. */
static double ref_correlation(const ego_hist_t *c, const ego_hist_t *l, int j)
{
    double mc = 0.0;
    double ml = 0.0;
    for (unsigned i = 0u; i < EGO_HIST_BINS; i++) {
        mc += c->bin[i];
        ml += l->bin[i];
    }
    mc /= EGO_HIST_BINS;
    ml /= EGO_HIST_BINS;
    double num = 0.0;
    double sc = 0.0;
    double sl = 0.0;
    for (unsigned i = 0u; i < EGO_HIST_BINS; i++) {
        const unsigned k = (unsigned)(((int)i + j + 2 * (int)EGO_HIST_BINS) % (int)EGO_HIST_BINS);
        num += (c->bin[i] - mc) * (l->bin[k] - ml);
        sc += (c->bin[i] - mc) * (c->bin[i] - mc);
        sl += (l->bin[i] - ml) * (l->bin[i] - ml);
    }
    return num / sqrt(sc * sl);
}

/* The histograms (g_hl, g_hc) of the room seen from one place, then
 * turned by theta_deg. */
static void turned_room(ego_hist_kind_t kind, double theta_deg)
{
    room_scan(0.2, 0.1, 0.0, 361u, &g_last);
    room_scan(0.2, 0.1, theta_deg, 361u, &g_current);
    ego_hist_params_t p;
    ego_hist_defaults(&p);
    p.kind = kind;
    (void)ego_hist_build(&g_last, &p, &g_hl);
    (void)ego_hist_build(&g_current, &p, &g_hc);
}

static void check_rotation(ego_hist_kind_t kind, double theta_deg, double tolerance_deg)
{
    /* Same place, the vehicle turned by theta: R(theta) P = P'. */
    turned_room(kind, theta_deg);
    ego_hist_match_t m;
    ego_hist_correlate(&g_hc, &g_hl, 0u, 250u, 15u, &m);
    TEST_ASSERT_TRUE(m.count >= 1u);
    const double got = deg_of_bam(fx_bam32_diff(m.candidate[0].rotation, 0u));
    char msg[96];
    (void)snprintf(msg, sizeof msg, "kind %d: theta %.3f got %.4f deg", (int)kind, theta_deg, got);
    TEST_ASSERT_TRUE_MESSAGE(fabs(got - theta_deg) < tolerance_deg, msg);

    /* The peak's correlation value against eq. 5 in doubles. */
    const int j = (int)lround(got * EGO_HIST_BINS / 180.0);
    double best = -2.0;
    for (int k = j - 1; k <= j + 1; k++) {
        const double r = ref_correlation(&g_hc, &g_hl, k);
        best = (r > best) ? r : best;
    }
    const double c = (double)m.candidate[0].correlation / 1073741824.0;
    (void)snprintf(msg, sizeof msg, "correlation %.6f, double %.6f", c, best);
    TEST_ASSERT_TRUE_MESSAGE(fabs(c - best) < 1e-4, msg);
    TEST_ASSERT_TRUE_MESSAGE(c > 0.5, msg);
    /* Candidates are ordered by correlation. */
    for (uint8_t k = 1u; k < m.count; k++) {
        TEST_ASSERT_TRUE(m.candidate[k].correlation <= m.candidate[k - 1u].correlation);
    }
}

static void test_hist_correlation_finds_the_rotation(void)
{
    /* Errors seen: HTAH/HAH <= 0.05 deg, LAH <= 0.3 deg up to 25 deg; at
     * 40 deg the 180-deg field sees other walls and all three drift by
     * about half a degree (the later stages refine the rotation). */
    const double thetas[] = {0.0, 3.3, -7.71, 25.07};
    for (unsigned k = 0u; k < 4u; k++) {
        check_rotation(EGO_HIST_HTAH, thetas[k], 0.1);
        check_rotation(EGO_HIST_HAH, thetas[k], 0.1);
        check_rotation(EGO_HIST_LAH, thetas[k], 0.5);
    }
    check_rotation(EGO_HIST_HTAH, -40.0, 1.0);
    check_rotation(EGO_HIST_HAH, -40.0, 1.0);
    check_rotation(EGO_HIST_LAH, -40.0, 1.0);
}

/* The 1-deg turn guess (tracking's retry): the same rotation as the full
 * correlation within 0.5 deg on the AH histograms of a turned room, the
 * dot products at its best coarse shift against a double oracle, and
 * nothing for an empty histogram. */
static void test_hist_turn_guess_finds_the_turn(void)
{
    const double thetas[] = {0.0, 3.3, -7.71, 10.4, -14.2};
    for (unsigned k = 0u; k < 5u; k++) {
        turned_room(EGO_HIST_AH, thetas[k]);
        fx_bam32_t turn = 0u;
        /* Centred 2 deg off the truth, as a prediction would be. */
        const fx_bam32_t centre = (fx_bam32_t)(int32_t)lround((thetas[k] + 2.0) / 180.0 * 2147483648.0);
        TEST_ASSERT_TRUE(ego_hist_turn_guess(&g_hc, &g_hl, centre, 15u, &turn));
        const double got = deg_of_bam(fx_bam32_diff(turn, 0u));
        /* The oracle: the best whole-degree shift of the 1-deg sums. */
        double best_dot = -1.0;
        int best_shift = 0;
        for (int s = -17; s <= 13; s++) {
            double dot = 0.0;
            for (unsigned c = 0u; c < EGO_HIST_BINS / 5u; c++) {
                double a = 0.0;
                double b = 0.0;
                for (unsigned q = 0u; q < 5u; q++) {
                    a += g_hc.bin[c * 5u + q];
                    b += g_hl.bin[(unsigned)(((int)(c * 5u + q) + (int)lround(thetas[k] + 2.0) * 5 + s * 5 +
                                             10 * (int)EGO_HIST_BINS) %
                                            (int)EGO_HIST_BINS)];
                }
                dot += a * b;
            }
            if (dot > best_dot) {
                best_dot = dot;
                best_shift = s + (int)lround(thetas[k] + 2.0);
            }
        }
        char msg[128];
        (void)snprintf(msg, sizeof msg, "turn %.2f: guess %.3f, oracle's whole degree %d", thetas[k],
                       got, best_shift);
        TEST_ASSERT_TRUE_MESSAGE(fabs(got - thetas[k]) < 0.5, msg);
        TEST_ASSERT_TRUE_MESSAGE(fabs(got - (double)best_shift) <= 0.5, msg);
    }
    memset(&g_hc, 0, sizeof g_hc);
    fx_bam32_t turn = 0u;
    TEST_ASSERT_FALSE(ego_hist_turn_guess(&g_hc, &g_hl, 0u, 15u, &turn));
}

/* The 1-deg correlation as candidates (the light search): on the AH
 * histograms of a turned room the best is the turn within 0.5 deg, its
 * correlation the normalised dot product of the 1-deg sums at its whole
 * degree against a double oracle, and an empty histogram gives none. */
static void test_hist_coarse_match_finds_the_turn(void)
{
    const double thetas[] = {0.0, 12.3, -27.71, 40.4};
    for (unsigned k = 0u; k < 4u; k++) {
        turned_room(EGO_HIST_AH, thetas[k]);
        ego_hist_match_t m;
        ego_hist_coarse_match(&g_hc, &g_hl, 0u, 45u, 15u, &m);
        TEST_ASSERT_TRUE(m.count >= 1u);
        const double got = deg_of_bam(fx_bam32_diff(m.candidate[0].rotation, 0u));
        /* The oracle: the 1-deg sums' normalised dot at the nearest degree. */
        const int shift = (int)lround(got);
        double dot = 0.0;
        double na = 0.0;
        double nb = 0.0;
        for (unsigned c = 0u; c < EGO_HIST_BINS / 5u; c++) {
            double a = 0.0;
            double b = 0.0;
            double bb = 0.0;
            for (unsigned q = 0u; q < 5u; q++) {
                a += g_hc.bin[c * 5u + q];
                b += g_hl.bin[(unsigned)(((int)(c * 5u + q) + shift * 5 + 10 * (int)EGO_HIST_BINS) %
                                         (int)EGO_HIST_BINS)];
                bb += g_hl.bin[c * 5u + q];
            }
            dot += a * b;
            na += a * a;
            nb += bb * bb;
        }
        const double oracle = dot / sqrt(na * nb);
        const double corr = (double)m.candidate[0].correlation / 1073741824.0;
        char msg[128];
        (void)snprintf(msg, sizeof msg, "turn %.2f: candidate %.3f deg, c %.4f, oracle %.4f",
                       thetas[k], got, corr, oracle);
        TEST_ASSERT_TRUE_MESSAGE(fabs(got - thetas[k]) < 0.5, msg);
        TEST_ASSERT_TRUE_MESSAGE(fabs(corr - oracle) < 0.002, msg);
    }
    memset(&g_hc, 0, sizeof g_hc);
    ego_hist_match_t m;
    ego_hist_coarse_match(&g_hc, &g_hl, 0u, 45u, 15u, &m);
    TEST_ASSERT_EQUAL_UINT8(0u, m.count);
}

static void test_hist_flat_histogram_gives_no_candidate(void)
{
    memset(&g_hc, 0, sizeof g_hc);
    memset(&g_hl, 0, sizeof g_hl);
    g_hl.bin[3] = 10u;
    ego_hist_match_t m;
    ego_hist_correlate(&g_hc, &g_hl, 0u, 100u, 5u, &m);
    TEST_ASSERT_EQUAL_UINT8(0u, m.count);
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        g_hc.bin[b] = 7u;
    }
    ego_hist_correlate(&g_hc, &g_hl, 0u, 100u, 5u, &m);
    TEST_ASSERT_EQUAL_UINT8(0u, m.count);
}

static void test_hist_correlation_of_a_shifted_copy(void)
{
    /* Two peaks, shifted by exactly 37 bins: c = 1 at +37, and a large
     * count does not overflow the product sums. */
    memset(&g_hl, 0, sizeof g_hl);
    memset(&g_hc, 0, sizeof g_hc);
    g_hl.bin[100] = 4000000000u;
    g_hl.bin[101] = 2000000000u;
    g_hl.bin[500] = 3000000000u;
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        g_hc.bin[b] = g_hl.bin[(b + 37u) % EGO_HIST_BINS];
    }
    ego_hist_match_t m;
    ego_hist_correlate(&g_hc, &g_hl, 0u, EGO_HIST_BINS / 2u, 5u, &m);
    TEST_ASSERT_TRUE(m.count >= 1u);
    const double got = deg_of_bam(fx_bam32_diff(m.candidate[0].rotation, 0u));
    TEST_ASSERT_TRUE(fabs(got - 37.0 * 180.0 / EGO_HIST_BINS) < 0.1);
    TEST_ASSERT_INT32_WITHIN(2000, 1073741824, m.candidate[0].correlation);
}

static void test_hist_correlation_around_a_centre(void)
{
    /* A copy shifted by 600 bins (120 deg): line directions repeat every
     * 180 deg, so around 0 the shift reads as -300 bins (-60 deg), out of
     * a +-45 deg window; around a prior of 110 deg it is found as 120 deg. */
    memset(&g_hl, 0, sizeof g_hl);
    memset(&g_hc, 0, sizeof g_hc);
    g_hl.bin[40] = 900u;
    g_hl.bin[41] = 500u;
    g_hl.bin[300] = 700u;
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        g_hc.bin[b] = g_hl.bin[(b + 600u) % EGO_HIST_BINS];
    }
    ego_hist_match_t m;
    ego_hist_correlate(&g_hc, &g_hl, FX_BAM32_DEG_C(110.0), 225u, 5u, &m);
    TEST_ASSERT_TRUE(m.count >= 1u);
    const double got = deg_of_bam(fx_bam32_diff(m.candidate[0].rotation, 0u));
    TEST_ASSERT_TRUE(fabs(got - 120.0) < 0.1);
    TEST_ASSERT_TRUE(m.candidate[0].correlation > 1073741824 / 1000 * 999); /* c = 1 */
    /* A centre on the other side of zero: -250 deg is 110 deg. */
    ego_hist_correlate(&g_hc, &g_hl, FX_BAM32_DEG_C(-250.0), 225u, 5u, &m);
    TEST_ASSERT_TRUE(m.count >= 1u);
    TEST_ASSERT_TRUE(fabs(deg_of_bam(fx_bam32_diff(m.candidate[0].rotation,
                                                     FX_BAM32_DEG_C(120.0)))) < 0.1);
    /* Around 0 with +-45 deg the true shift is out of reach. */
    ego_hist_correlate(&g_hc, &g_hl, 0u, 225u, 5u, &m);
    for (uint8_t k = 0u; k < m.count; k++) {
        const double r = deg_of_bam(fx_bam32_diff(m.candidate[k].rotation, 0u));
        TEST_ASSERT_TRUE(fabs(r - 120.0) > 1.0 && fabs(r + 60.0) > 1.0);
    }
}

/* A small deterministic generator: lo + (0 .. span). */
static unsigned next_in(uint32_t *state, unsigned lo, unsigned span)
{
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    return lo + *state % (span + 1u);
}

/* Sparse histograms (a few runs of filled bins, one across the wrap from
 * the last bin to the first) and dense ones (more runs than the sparse
 * path keeps): every candidate's correlation equals eq. 5 in doubles, and
 * the best is the shift. */
static void test_hist_correlation_of_sparse_and_dense_histograms(void)
{
    /* Up to 16 runs: the dot products over the runs; more, but at most
     * 128 bins that are not zero: over the list of those bins; beyond:
     * over every bin. All three must give eq. 5. */
    uint32_t rng = 5u;
    for (unsigned runs = 1u; runs <= 80u; runs++) {
        memset(&g_hl, 0, sizeof g_hl);
        memset(&g_hc, 0, sizeof g_hc);
        for (unsigned r = 0u; r < runs; r++) {
            const unsigned start =
                (r == 0u) ? EGO_HIST_BINS - 2u : next_in(&rng, 0u, EGO_HIST_BINS - 1u);
            const unsigned length = next_in(&rng, 1u, 4u);
            for (unsigned k = 0u; k < length; k++) {
                g_hl.bin[(start + k) % EGO_HIST_BINS] = next_in(&rng, 1u, 5000u);
            }
        }
        const int shift = (int)next_in(&rng, 0u, 400u) - 200;
        for (unsigned b = 0u; b < EGO_HIST_BINS; b++) {
            g_hc.bin[b] = g_hl.bin[(unsigned)((int)b + shift + (int)EGO_HIST_BINS) % EGO_HIST_BINS];
        }
        ego_hist_match_t m;
        ego_hist_correlate(&g_hc, &g_hl, 0u, 225u, 5u, &m);
        TEST_ASSERT_TRUE(m.count >= 1u);
        const double first_bins = deg_of_bam(fx_bam32_diff(m.candidate[0].rotation, 0u)) *
                                  EGO_HIST_BINS / 180.0;
        char msg[96];
        (void)snprintf(msg, sizeof msg, "runs %u shift %d got %.2f bins", runs, shift, first_bins);
        TEST_ASSERT_TRUE_MESSAGE(fabs(first_bins - shift) < 0.5, msg);
        for (uint8_t k = 0u; k < m.count; k++) {
            const double bins = deg_of_bam(fx_bam32_diff(m.candidate[k].rotation, 0u)) *
                                EGO_HIST_BINS / 180.0;
            const int j = (int)lround(bins);
            double best = -2.0;
            for (int i = j - 1; i <= j + 1; i++) {
                const double r = ref_correlation(&g_hc, &g_hl, i);
                best = (r > best) ? r : best;
            }
            const double c = (double)m.candidate[k].correlation / 1073741824.0;
            (void)snprintf(msg, sizeof msg, "runs %u candidate %u: %.6f, double %.6f", runs,
                           (unsigned)k, c, best);
            TEST_ASSERT_TRUE_MESSAGE(fabs(c - best) < 1e-4, msg);
        }
    }
}

/* Eq. 7 in the estimator's own fixed-point steps, bin by bin, with
 * nothing skipped: the oracle of the HTAH walk. */
static bool ref_band_holds(const ego_scan_t *scan, uint16_t i, unsigned n, fx_q16_16_t t_line,
                           uint16_t b)
{
    fx_q2_30_t sn;
    fx_q2_30_t cs;
    fx_sincos(ego_hist_bin_centre(b), &sn, &cs);
    fx_q16_16_t d[2u * EGO_TFIT_MAX_HALF_WINDOW + 1u];
    for (unsigned k = 0u; k < 2u * n + 1u; k++) {
        const fx_q16_16_t rx = fx_sub_q16(scan->x[i - n + k], scan->x[i]);
        const fx_q16_16_t ry = fx_sub_q16(scan->y[i - n + k], scan->y[i]);
        d[k] = fx_sub_q16(fx_mul_q16_q30(ry, cs), fx_mul_q16_q30(rx, sn));
    }
    const int64_t mid2 = (int64_t)d[0] + d[2u * n];
    for (unsigned k = 0u; k < 2u * n + 1u; k++) {
        const int64_t dev2 = 2 * (int64_t)d[k] - mid2;
        if (dev2 > 2 * (int64_t)t_line || dev2 < -2 * (int64_t)t_line) {
            return false;
        }
    }
    return true;
}

static void ref_htah(const ego_scan_t *scan, unsigned n, fx_q16_16_t t_line, ego_hist_t *h)
{
    memset(h, 0, sizeof *h);
    for (uint16_t i = 0u; i < scan->count; i++) {
        bool full = (scan->flags[i] & EGO_POINT_HAS_TANGENT) != 0u && i >= n &&
                    (unsigned)i + n < scan->count;
        for (unsigned j = i - n; full && j < i + n; j++) {
            full = ego_scan_linked(scan, (uint16_t)j);
        }
        const uint16_t start = ego_hist_bin_of(scan->tangent[i]);
        if (!full || !ref_band_holds(scan, i, n, t_line, start)) {
            continue;
        }
        h->bin[start]++;
        uint16_t up = start;
        for (;;) {
            const uint16_t next = (uint16_t)((up + 1u) % EGO_HIST_BINS);
            if (next == start || !ref_band_holds(scan, i, n, t_line, next)) {
                break;
            }
            h->bin[next]++;
            up = next;
        }
        uint16_t down = start;
        for (;;) {
            const uint16_t next = (uint16_t)((down + EGO_HIST_BINS - 1u) % EGO_HIST_BINS);
            if (next == up || !ref_band_holds(scan, i, n, t_line, next)) {
                break;
            }
            h->bin[next]++;
            down = next;
        }
    }
}

/* The HTAH walk counts the bins it is sure of without testing them: the
 * votes must be exactly those of testing every bin, for narrow and wide
 * bands, short and long windows, near and far scans. */
/* The emulated target compares one in four of the host's 120 cases (24 s of
 * CI's cores otherwise), spread over every place, band and window. */
#if defined(LMSEGO_UNIT_ON_TARGET)
#define HTAH_CASE_EVERY 4u
#else
#define HTAH_CASE_EVERY 1u
#endif

static void test_hist_htah_skips_nothing_it_should_test(void)
{
    static ego_hist_t reference;
    const double places[][3] = {{0.0, 0.0, 0.0}, {0.5, -0.3, 10.0}, {-4.0, 2.0, 95.0},
                                {8.0, -4.0, 200.0}};
    const double bands[] = {0.005, 0.02, 0.05, 0.2, 1.0};
    unsigned cases = 0u;
    unsigned skip = 0u; /* cases left to skip before the next compared one */
    unsigned compared = 0u;
    uint32_t votes = 0u;
    for (unsigned pl = 0u; pl < 4u; pl++) {
        for (unsigned count = 181u; count <= 361u; count += 180u) {
            room_scan(places[pl][0], places[pl][1], places[pl][2], count, &g_current);
            for (unsigned bi = 0u; bi < 5u; bi++) {
                for (uint8_t n = 1u; n <= EGO_TFIT_MAX_HALF_WINDOW; n += 2u) {
                    cases++;
                    if (skip > 0u) {
                        skip--;
                        continue;
                    }
                    skip = HTAH_CASE_EVERY - 1u;
                    ego_hist_params_t p;
                    ego_hist_defaults(&p);
                    p.kind = EGO_HIST_HTAH;
                    p.half_window = n;
                    p.t_line = fx_q16_16_from_double(bands[bi]);
                    votes += ego_hist_build(&g_current, &p, &g_hc);
                    ref_htah(&g_current, n, p.t_line, &reference);
                    TEST_ASSERT_EQUAL_MEMORY(reference.bin, g_hc.bin, sizeof reference.bin);
                    compared++;
                }
            }
        }
    }
    char msg[64];
    (void)snprintf(msg, sizeof msg, "%u histograms, %lu votes", compared, (unsigned long)votes);
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_UINT32(120u, cases);
    TEST_ASSERT_EQUAL_UINT32(120u / HTAH_CASE_EVERY, compared);
    TEST_ASSERT_TRUE(votes > 100000u / HTAH_CASE_EVERY);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_hist_bin_geometry);
    RUN_TEST(test_hist_ah_of_a_room_peaks_at_the_walls);
    RUN_TEST(test_hist_htah_votes_within_hah);
    RUN_TEST(test_hist_correlation_finds_the_rotation);
    RUN_TEST(test_hist_turn_guess_finds_the_turn);
    RUN_TEST(test_hist_coarse_match_finds_the_turn);
    RUN_TEST(test_hist_flat_histogram_gives_no_candidate);
    RUN_TEST(test_hist_correlation_of_a_shifted_copy);
    RUN_TEST(test_hist_correlation_around_a_centre);
    RUN_TEST(test_hist_correlation_of_sparse_and_dense_histograms);
    RUN_TEST(test_hist_htah_skips_nothing_it_should_test);
    return UNITY_END();
}
