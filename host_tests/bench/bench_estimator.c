/* bench_estimator.c - cost of the estimator per scan on the host.
 *
 *   bench_estimator [--icp] [--mode HEX] [--once] [--budget none|default|U] [--period S]
 *                   [--trace] STREAM
 *
 * Decodes every B0 scan of a recorded stream into memory first, then runs
 * ego_process over them in order (scan k at k times the LMS mode's period,
 * or --period seconds: keyframe logs),
 * timing each call with clock_gettime(CLOCK_MONOTONIC). Prints the number
 * of scans, the median and maximum time per scan, and the mean ITCP
 * iterations, and the work units (ego_work.h) per scan: median, maximum,
 * and the largest share of its budget a scan used. --trace prints every
 * scan's flags, work and budget. --icp runs plain ICP instead of ITCP; --once skips the timing
 * summary (for callgrind: valgrind --tool=callgrind
 * --toggle-collect=bench_process_all ... gives instructions per scan).
 * Host-only.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ego.h"
#include "ego_lms.h"
#include "scan_file.h"

#define MAX_SCANS 2000u

static lms_scan_t scans[MAX_SCANS];
static double seconds[MAX_SCANS];
static double units[MAX_SCANS];
static double worst_share;
static int trace;
static ego_state_t state;
static ego_lms_params_t lms;
static lms_scan_t work; /* the adapter turns its values into ranges in place */
static ego_range_scan_t range;
static uint32_t period_us; /* 0: the LMS mode's */


static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Everything callgrind should count. */
__attribute__((noinline)) static unsigned long bench_process_all(const ego_params_t *p, size_t n,
                                                                 int timed)
{
    unsigned long iterations = 0u;
    ego_reset(&state);
    for (size_t k = 0u; k < n; k++) {
        struct timespec t0;
        struct timespec t1;
        ego_output_t out;
        /* The adapter's share (one pass over the values) is timed too: it
         * is part of every scan's work. */
        if (timed) {
            (void)clock_gettime(CLOCK_MONOTONIC, &t0);
        }
        work = scans[k];
        if (ego_lms_to_range(&work, &lms, &range) == EGO_LMS_OK) {
            (void)ego_process(&state, p, &range, (uint32_t)k * ((period_us != 0u) ? period_us : lms_scan_period_us(scans[k].count)),
                              &out);
        } else {
            memset(&out, 0, sizeof out);
        }
        if (timed) {
            (void)clock_gettime(CLOCK_MONOTONIC, &t1);
            seconds[k] = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-9;
        }
        iterations += out.iterations;
        units[k] = out.work;
        if (out.work_limit != 0u && k > 0u) {
            const double share = (double)out.work / (double)out.work_limit;
            worst_share = (share > worst_share) ? share : worst_share;
        }
        if (trace) {
            (void)printf("scan %zu flags 0x%02x work %u limit %u iterations %u\n", k,
                         (unsigned)out.flags, (unsigned)out.work, (unsigned)out.work_limit,
                         (unsigned)out.iterations);
        }
    }
    return iterations;
}

int main(int argc, char **argv)
{
    static ego_params_t params;
    ego_defaults(&params);
    ego_lms_defaults(&lms);
    int once = 0;
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--icp") == 0) {
            params.track.weighted = false;
        } else if (strcmp(argv[i], "--trace") == 0) {
            trace = 1;
        } else if (strcmp(argv[i], "--budget") == 0 && i + 1 < argc) {
            i++;
            if (strcmp(argv[i], "none") == 0) {
                params.work_per_s = 0u;
            } else {
                ego_budget_defaults(&params);
                if (strcmp(argv[i], "default") != 0) {
                    params.work_per_s = (uint32_t)strtoul(argv[i], NULL, 10);
                }
            }
        } else if (strcmp(argv[i], "--period") == 0 && i + 1 < argc) {
            period_us = (uint32_t)(strtod(argv[++i], NULL) * 1e6 + 0.5);
        } else if (strcmp(argv[i], "--once") == 0) {
            once = 1;
        } else if (strcmp(argv[i], "--mode") == 0 && i + 1 < argc) {
            lms.meas_mode = (uint8_t)strtoul(argv[++i], NULL, 16);
        } else {
            path = argv[i];
        }
    }
    if (path == NULL) {
        (void)fprintf(stderr, "usage: bench_estimator [--icp] [--mode HEX] [--once] STREAM\n");
        return 2;
    }
    const size_t n = scan_file_load(path, scans, MAX_SCANS);
    if (n < 2u) {
        (void)fprintf(stderr, "bench_estimator: fewer than two scans in '%s'\n", path);
        return 1;
    }
    const unsigned long iterations = bench_process_all(&params, n, !once);
    (void)printf("scans=%zu values=%u mode=%s iterations_mean=%.2f\n", n, scans[0].count,
                 params.track.weighted ? "ITCP" : "ICP", (double)iterations / (double)(n - 1u));
    /* Scan 0 (the first: its preparation only) is nobody's budget. */
    qsort(units + 1, n - 1u, sizeof units[0], cmp_double);
    (void)printf("work per scan: median %.0f  max %.0f units, at most %.1f %% of a budget\n",
                 units[1 + (n - 1u) / 2u], units[n - 1u], worst_share * 100.0);
    if (!once) {
        qsort(seconds, n, sizeof seconds[0], cmp_double);
        (void)printf("per scan: median %.3f ms  max %.3f ms\n", seconds[n / 2u] * 1e3,
                     seconds[n - 1u] * 1e3);
    }
    return 0;
}
