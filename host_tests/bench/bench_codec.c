/* bench_codec.c - throughput of the receive path: lms_framer over a byte
 * stream, lms_decode_scan of every B0, lms_value_decode of every value.
 *
 * Builds an in-memory stream of BENCH_TELEGRAMS 361-value B0 telegrams
 * (mm, seeded xorshift values with a few special codes) with
 * lms_encode_scan, then times bench_decode_pass over it BENCH_RUNS times
 * with clock_gettime(CLOCK_MONOTONIC) and prints the median and best
 * figures. The stream is fed in BENCH_CHUNK-byte pieces, as a UART ring
 * or the CLI would hand it over.
 *
 *   bench_codec [--runs N]   timed runs (default 15)
 *   bench_codec --once       one pass, no timing (for callgrind and ctest)
 *
 * Exit status 1 if a pass does not decode every telegram it was given.
 * callgrind: --toggle-collect=bench_decode_pass counts only the pass, not
 * the stream construction (host_tests/bench/run_bench.sh).
 */
/* clock_gettime is POSIX: the build defines _POSIX_C_SOURCE (CMakeLists.txt). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lms_decode.h"
#include "lms_encode.h"
#include "lms_framer.h"

#define BENCH_TELEGRAMS 2000u
#define BENCH_VALUES 361u
#define BENCH_RUNS_DEFAULT 15u
#define BENCH_RUNS_MAX 1000u
#define BENCH_CHUNK 4096u
#define BENCH_SEED 0x5EED2024u

/* Keep bench_decode_pass a real call so callgrind can toggle on it. */
#if defined(__GNUC__)
#define BENCH_NOINLINE __attribute__((noinline))
#else
#define BENCH_NOINLINE
#endif

typedef struct {
    uint32_t telegrams; /* framer telegrams */
    uint32_t scans;     /* B0 accepted by lms_decode_scan */
    uint64_t sum_mm;    /* sum of all range values, keeps the work observable */
    uint32_t specials;  /* values that were not ranges */
} bench_result_t;

static uint64_t xorshift64(uint64_t *state)
{
    uint64_t x = *state;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    *state = x;
    return x;
}

/* Stream of BENCH_TELEGRAMS B0 telegrams; returns its size, 0 on error. */
static size_t build_stream(uint8_t *stream, size_t cap)
{
    static lms_scan_t scan;
    uint64_t state = BENCH_SEED;
    size_t len = 0u;
    for (uint32_t t = 0u; t < BENCH_TELEGRAMS; t++) {
        memset(&scan, 0, sizeof scan);
        scan.unit = LMS_UNIT_MM;
        scan.count = BENCH_VALUES;
        scan.status = 0x10u;
        for (uint32_t i = 0u; i < BENCH_VALUES; i++) {
            const uint64_t r = xorshift64(&state);
            /* 1 % no return, the rest 300 .. 8181 mm. */
            scan.values[i] = (r % 100u == 0u) ? 0x1FFFu : (uint16_t)(300u + (r >> 8) % 7882u);
        }
        size_t written = 0u;
        if (lms_encode_scan(stream + len, cap - len, 0x80u, &scan, &written) != LMS_OK) {
            return 0u;
        }
        len += written;
    }
    return len;
}

/* One pass of the receive path over the stream. */
BENCH_NOINLINE void bench_decode_pass(const uint8_t *stream, size_t len, bench_result_t *out);

BENCH_NOINLINE void bench_decode_pass(const uint8_t *stream, size_t len, bench_result_t *out)
{
    static lms_framer_t framer;
    static lms_scan_t scan;
    memset(out, 0, sizeof *out);
    lms_framer_init(&framer, LMS_FROM_SCANNER);

    size_t offset = 0u;
    while (offset < len) {
        const size_t chunk = (len - offset < BENCH_CHUNK) ? len - offset : BENCH_CHUNK;
        size_t used_total = 0u;
        for (;;) {
            size_t used = 0u;
            const lms_framer_event_t ev =
                lms_framer_feed(&framer, stream + offset + used_total, chunk - used_total, &used);
            used_total += used;
            if (ev == LMS_FRAMER_NEED_MORE) {
                break;
            }
            if (ev != LMS_FRAMER_TELEGRAM) {
                continue;
            }
            size_t tlen = 0u;
            const uint8_t *tel = lms_framer_telegram(&framer, &tlen);
            if (lms_decode_scan(tel, tlen, &scan) != LMS_OK) {
                continue;
            }
            out->scans++;
            for (uint16_t i = 0u; i < scan.count; i++) {
                lms_value_t v;
                if (lms_value_decode(scan.values[i], LMS_MEAS_8M_FIELDS_DAZZLE, scan.unit, &v) ==
                        LMS_OK &&
                    v.kind == LMS_VALUE_RANGE) {
                    out->sum_mm += v.distance_mm;
                } else {
                    out->specials++;
                }
            }
        }
        offset += chunk;
    }
    while (lms_framer_flush(&framer) != LMS_FRAMER_NEED_MORE) {
    }
    out->telegrams = lms_framer_stats(&framer)->telegrams;
}

static double seconds_between(const struct timespec *a, const struct timespec *b)
{
    return (double)(b->tv_sec - a->tv_sec) + (double)(b->tv_nsec - a->tv_nsec) * 1e-9;
}

static int compare_double(const void *pa, const void *pb)
{
    const double a = *(const double *)pa;
    const double b = *(const double *)pb;
    return (a > b) - (a < b);
}

static int check_result(const bench_result_t *r)
{
    if (r->telegrams != BENCH_TELEGRAMS || r->scans != BENCH_TELEGRAMS) {
        (void)fprintf(stderr, "bench_codec: decoded %lu telegrams / %lu scans, expected %lu\n",
                      (unsigned long)r->telegrams, (unsigned long)r->scans,
                      (unsigned long)BENCH_TELEGRAMS);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    unsigned runs = BENCH_RUNS_DEFAULT;
    int once = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--once") == 0) {
            once = 1;
        } else if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) {
            char *end = NULL;
            const unsigned long n = strtoul(argv[++i], &end, 10);
            if (*end != '\0' || n == 0u || n > BENCH_RUNS_MAX) {
                (void)fputs("bench_codec: --runs takes 1..1000\n", stderr);
                return 2;
            }
            runs = (unsigned)n;
        } else {
            (void)fputs("usage: bench_codec [--runs N] | --once\n", stderr);
            return 2;
        }
    }

    const size_t cap = (size_t)BENCH_TELEGRAMS * (2u * BENCH_VALUES + 10u);
    uint8_t *stream = malloc(cap);
    if (stream == NULL) {
        (void)fputs("bench_codec: out of memory\n", stderr);
        return 1;
    }
    const size_t len = build_stream(stream, cap);
    if (len == 0u) {
        (void)fputs("bench_codec: lms_encode_scan failed\n", stderr);
        free(stream);
        return 1;
    }

    bench_result_t r;
    if (once) {
        bench_decode_pass(stream, len, &r);
        (void)printf("stream_bytes=%zu telegrams=%lu scans=%lu specials=%lu sum_mm=%llu\n", len,
                     (unsigned long)r.telegrams, (unsigned long)r.scans, (unsigned long)r.specials,
                     (unsigned long long)r.sum_mm);
        free(stream);
        return check_result(&r);
    }

    double seconds[BENCH_RUNS_MAX] = {0.0};
    bench_decode_pass(stream, len, &r); /* warm-up: caches, page faults */
    for (unsigned run = 0u; run < runs; run++) {
        struct timespec t0;
        struct timespec t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        bench_decode_pass(stream, len, &r);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        seconds[run] = seconds_between(&t0, &t1);
        if (check_result(&r) != 0) {
            free(stream);
            return 1;
        }
    }
    qsort(seconds, runs, sizeof seconds[0], compare_double);
    const double median = (runs % 2u != 0u) ? seconds[runs / 2u]
                                            : 0.5 * (seconds[runs / 2u - 1u] + seconds[runs / 2u]);
    const double best = seconds[0];
    const double mb = (double)len / 1e6;

    (void)printf("stream: %zu bytes, %u telegrams of %u values (%zu bytes each)\n", len,
                 BENCH_TELEGRAMS, BENCH_VALUES, len / BENCH_TELEGRAMS);
    (void)printf("runs: %u (after one warm-up pass)\n", runs);
    (void)printf("median: %.1f MB/s  %.2f ns/byte  %.0f ns/telegram\n", mb / median,
                 median * 1e9 / (double)len, median * 1e9 / BENCH_TELEGRAMS);
    (void)printf("best:   %.1f MB/s  %.2f ns/byte  %.0f ns/telegram\n", mb / best,
                 best * 1e9 / (double)len, best * 1e9 / BENCH_TELEGRAMS);
    (void)printf("checksum: scans=%lu specials=%lu sum_mm=%llu\n", (unsigned long)r.scans,
                 (unsigned long)r.specials, (unsigned long long)r.sum_mm);
    free(stream);
    return 0;
}
