/* exp_hist.c - the paper's Table 3: rotation error of the histogram stage
 * alone (AH, length-weighted AH, HAH, HAH with angle of interest, HTAH)
 * over a sequence with ground truth, and the time each histogram takes.
 *
 *   exp_hist STREAM TRUTH.pairs
 *
 * For every consecutive pair: both scans prepared and fitted (ego_scan,
 * tfit), each histogram kind built and correlated (ego_hist.h, +-45 deg), the
 * best candidate's rotation compared with the truth's dtheta. HAH+AOI
 * builds both scans of a pair over the angles where the last scan's plain
 * AH has at least 2 votes, widened by 5 deg (its time is one scan's). Prints one
 * line per kind: mean, std and max rotation error (deg), and the median
 * time of ego_hist_build per scan (clock_gettime; Release builds only mean
 * anything). Host-only.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ego.h"
#include "ego_lms.h"
#include "scan_file.h"

#define MAX_SCANS 2000u
#define KINDS 5u
#define PI 3.14159265358979323846

static lms_scan_t scans[MAX_SCANS];
static double truth_theta[MAX_SCANS]; /* of scan j relative to j - 1 */
static ego_scan_t prepared[2];
static ego_hist_t hists[KINDS][2];
static double err[KINDS][MAX_SCANS];
static double build_s[KINDS][MAX_SCANS];
static uint8_t aoi[EGO_HIST_BINS];

static void load_truth(const char *path)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        (void)fprintf(stderr, "exp_hist: cannot open '%s'\n", path);
        exit(1);
    }
    char line[256];
    while (fgets(line, sizeof line, f) != NULL) {
        if (line[0] == '#') {
            continue;
        }
        /* "i j dx dy dtheta": only j and dtheta are needed. */
        char *p = line;
        char *end = NULL;
        (void)strtoul(p, &end, 10);
        if (end == p) {
            continue;
        }
        p = end;
        const unsigned long j = strtoul(p, &end, 10);
        if (end == p || j >= MAX_SCANS) {
            continue;
        }
        double v[3];
        int ok = 1;
        for (int k = 0; k < 3 && ok; k++) {
            p = end;
            v[k] = strtod(p, &end);
            ok = end != p;
        }
        if (ok) {
            truth_theta[j] = v[2];
        }
    }
    (void)fclose(f);
}

static double seconds_now(void)
{
    struct timespec t;
    (void)clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        (void)fprintf(stderr, "usage: exp_hist STREAM TRUTH.pairs\n");
        return 2;
    }
    const size_t n = scan_file_load(argv[1], scans, MAX_SCANS);
    load_truth(argv[2]);
    static ego_params_t params;
    ego_defaults(&params);
    ego_lms_params_t lms;
    ego_lms_defaults(&lms);
    static ego_range_scan_t range;
    static const char *const names[KINDS] = {"AH", "LAH", "HAH", "HAH+AOI", "HTAH"};
    static const ego_hist_kind_t kinds[KINDS] = {EGO_HIST_AH, EGO_HIST_LAH, EGO_HIST_HAH, EGO_HIST_HAH, EGO_HIST_HTAH};
    for (size_t k = 0u; k < n; k++) {
        const unsigned cur = (unsigned)(k % 2u);
        if (ego_lms_to_range(&scans[k], &lms, &range) != EGO_LMS_OK ||
            ego_scan_prepare(&range, &params.prep, &prepared[cur]) != EGO_PREP_OK) {
            (void)fprintf(stderr, "exp_hist: scan %zu has no layout\n", k);
            return 1;
        }
        ego_tfit_fit_scan(&prepared[cur], &params.tfit);
        for (unsigned m = 0u; m < KINDS; m++) {
            ego_hist_params_t hp = params.hist;
            hp.kind = kinds[m];
            if (m == 3u) {
                /* Angle of interest: where the last scan's plain AH has at
                 * least 2 votes, widened by 5 deg. */
                if (k == 0u) {
                    hp.aoi = NULL;
                } else {
                    ego_hist_aoi_mask(&hists[0][1u - cur], 2u, 25u, aoi);
                    hp.aoi = aoi;
                }
            }
            const double t0 = seconds_now();
            (void)ego_hist_build(&prepared[cur], &hp, &hists[m][cur]);
            build_s[m][k] = seconds_now() - t0;
            if (k == 0u) {
                continue;
            }
            if (m == 3u) {
                /* Both scans of the pair over the same angles of interest. */
                (void)ego_hist_build(&prepared[1u - cur], &hp, &hists[m][1u - cur]);
            }
            ego_hist_match_t match;
            ego_hist_correlate(&hists[m][cur], &hists[m][1u - cur], 0u, params.max_rotation_bins,
                           params.merge_bins, &match);
            double got = 0.0;
            if (match.count > 0u) {
                got = (double)fx_bam32_diff(match.candidate[0].rotation, 0u) * PI / 2147483648.0;
            }
            err[m][k] = fabs(remainder(got - truth_theta[k], PI)) * 180.0 / PI;
        }
    }
    (void)printf("%-8s %10s %10s %10s %12s\n", "kind", "mean_deg", "std_deg", "max_deg",
                 "build_ms");
    for (unsigned m = 0u; m < KINDS; m++) {
        double sum = 0.0;
        double sq = 0.0;
        double max = 0.0;
        for (size_t k = 1u; k < n; k++) {
            sum += err[m][k];
            sq += err[m][k] * err[m][k];
            max = fmax(max, err[m][k]);
        }
        const double cnt = (double)(n - 1u);
        const double mean = sum / cnt;
        qsort(build_s[m], n, sizeof build_s[m][0], cmp_double);
        (void)printf("%-8s %10.4f %10.4f %10.4f %12.4f\n", names[m], mean,
                     sqrt(fmax(0.0, sq / cnt - mean * mean)), max, build_s[m][n / 2u] * 1e3);
    }
    return 0;
}
