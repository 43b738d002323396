/* lmsworld.c - synthetic-world LMS 2xx stream generator (host-only).
 *
 * Ray-casts a 180-degree LMS 2xx scanner moving through a 2-D map
 * (world_scenario.h) and writes what a host records on the scanner -> host
 * line after sending 20 24 (continuous output of all values): the ACK byte
 * 06, the A0 reply 02 80 03 00 A0 00 10 16 0A, then one B0 telegram per
 * scan (address 0x80, status 0x10, no real-time indices) built with
 * lms_encode_scan. Ground truth, written from the generator's own poses:
 *   --truth FILE  one line per consecutive pair, "i j dx dy dtheta": the
 *                 pose of scan j = i + 1 in the frame of scan i (m, rad),
 *                 the estimate format of ../shared/tools/relpose_eval.py
 *   --poses FILE  absolute scanner poses, TUM "time x y z qx qy qz qw"
 *   --objects FILE  the moving objects of every scan, "scan id cx cy
 *                 heading vx vy length width returns": pose in the
 *                 scanner frame at the scan's time, velocity over ground
 *                 in that frame, beams of the scan that hit the object
 * Beam timing: by default (--timing instant) every value of a scan is cast
 * from the scanner's pose at the scan's time; --timing lms casts value i
 * at its own time on the 75 Hz mirror (world_scan.h), the truth unchanged.
 *
 * Deterministic: Gaussian range noise from xorshift64 (seeded through
 * splitmix64 from --seed) and Box-Muller; no rand(), no clock. Built with
 * -ffp-contract=off so gcc and clang give the same bytes.
 * docs/synthetic-worlds.md describes the scenarios and every choice.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gen_common.h"
#include "lms_encode.h"
#include "lms_proto.h"
#include "world_geom.h"
#include "world_map.h"
#include "world_scan.h"
#include "world_scenario.h"

#define EXIT_RUNTIME 1
#define EXIT_USAGE 2

#define GEN_ADDRESS 0x80u /* scanner at address 0 */
#define GEN_STATUS 0x10u  /* healthy status byte */
#define GEN_MAX_SCANS 100000u
#define GEN_MAX_NOISE_CM 100.0

/* ------------------------------------------------------------------ */
/* Random numbers: xorshift64 (13, 7, 17) seeded through splitmix64, and
 * Gaussian deviates by Box-Muller (both of each pair are used). */

typedef struct {
    uint64_t state;
    double spare;
    bool has_spare;
} rng_t;

static void rng_seed(rng_t *r, uint64_t seed)
{
    uint64_t z = seed + 0x9E3779B97F4A7C15u;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    z ^= z >> 31;
    r->state = (z != 0u) ? z : 0x2545F4914F6CDD1Du;
    r->spare = 0.0;
    r->has_spare = false;
}

static uint64_t rng_next(rng_t *r)
{
    uint64_t x = r->state;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    r->state = x;
    return x;
}

/* Uniform in [0, 1), 53 bits. */
static double rng_unit(rng_t *r)
{
    return (double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

/* Standard normal deviate. */
static double rng_gauss(rng_t *r)
{
    if (r->has_spare) {
        r->has_spare = false;
        return r->spare;
    }
    const double u1 = 1.0 - rng_unit(r); /* (0, 1]: log is finite */
    const double u2 = rng_unit(r);
    const double radius = sqrt(-2.0 * log(u1));
    const double angle = 2.0 * WORLD_PI * u2;
    r->spare = radius * sin(angle);
    r->has_spare = true;
    return radius * cos(angle);
}

/* ------------------------------------------------------------------ */
/* Growable byte buffer. */

/* printf into the buffer; every line written here is short. */
static void buf_printf(buf_t *b, const char *format, ...)
    __attribute__((format(printf, 2, 3)));

static void buf_printf(buf_t *b, const char *format, ...)
{
    char text[512];
    va_list args;
    va_start(args, format);
    /* clang-analyzer 14 misses va_start here (a known false positive). */
    const int n = vsnprintf(text, sizeof text, format, args); // NOLINT(clang-analyzer-valist.Uninitialized)
    va_end(args);
    if (n < 0 || (size_t)n >= sizeof text) {
        (void)fputs("lmsworld: internal error: text line too long\n", stderr);
        exit(EXIT_RUNTIME);
    }
    buf_append(b, text, (size_t)n);
}

/* ------------------------------------------------------------------ */
/* Options. */

typedef struct {
    const wscenario_t *scenario;
    uint64_t seed;
    unsigned scans;  /* 0 until chosen: then the scenario's default */
    unsigned skip;   /* scenario scans left out before the first one written */
    unsigned values; /* 181 or 361 */
    const char *res_text;
    lms_unit_t unit;
    double noise_cm;
    double max_range;
    const char *out_path;
    const char *truth_path;
    const char *poses_path;
    const char *objects_path;
    bool lms_timing; /* --timing lms: each value cast at its own time */
} gen_options_t;

static void print_usage(FILE *to)
{
    (void)fputs(
        "usage: lmsworld --scenario NAME [--seed N] [--scans N] [--skip K] [--res 1|0.5]\n"
        "                [--unit cm|mm] [--noise-cm SIGMA] [--max-range M]\n"
        "                [--timing instant|lms] -o STREAM --truth PAIRS [--poses TUM]\n"
        "                [--objects OBJECTS]\n"
        "Ray-casts an LMS 2xx (180 deg) moving through a 2-D world and writes the\n"
        "scanner->host stream (06, A0 reply, one B0 per scan) and its ground truth.\n"
        "  --scenario NAME   see below\n"
        "  --seed N          noise seed (default 1)\n"
        "  --scans N         number of scans (default: the scenario's)\n"
        "  --skip K          start at scan K of the scenario (an excerpt; times stay\n"
        "                    the scenario's, scan numbers in PAIRS start at 0)\n"
        "  --res 1|0.5       angular resolution, deg: 181 values at 75 Hz or 361 at\n"
        "                    37.5 Hz (default 0.5)\n"
        "  --unit cm|mm      cm: measuring mode 00, no surface = 0x1FF7 (default);\n"
        "                    mm: measuring mode 0F (16 bit), no surface = 0\n"
        "  --noise-cm SIGMA  Gaussian range noise, cm (default 0: rounding only)\n"
        "  --max-range M     metres (default 50; at most 81.82 in cm, 65.535 in mm)\n"
        "  --timing instant|lms\n"
        "                    instant: every value cast from the scan's pose (default);\n"
        "                    lms: value i cast at its own time, the mirror's 75 Hz:\n"
        "                    (i % P)/75 + (i / P)/27000 s after value 0 (P = 2 passes\n"
        "                    for 361 values, 1 for 181), minus their mean (the scan's\n"
        "                    time, to which the truth refers)\n"
        "  -o STREAM         the recording\n"
        "  --truth PAIRS     'i j dx dy dtheta' per consecutive pair: scan j in the\n"
        "                    frame of scan i (m, rad)\n"
        "  --poses TUM       absolute poses 'time x y z qx qy qz qw'\n"
        "  --objects OBJECTS the moving objects per scan, 'scan id cx cy heading vx vy\n"
        "                    length width returns': centre and heading in the scanner\n"
        "                    frame at the scan's time (m, rad), velocity over ground in\n"
        "                    that frame (m/s), size (m), beams that hit it\n"
        "scenarios:\n",
        to);
    for (size_t i = 0u; i < wscenario_count(); i++) {
        const wscenario_t *s = wscenario_at(i);
        (void)fprintf(to, "  %-11s %s\n", s->name, s->summary);
    }
}

static int usage_error(const char *problem, const char *arg)
{
    (void)fprintf(stderr, "lmsworld: %s%s%s%s (try --help)\n", problem, arg ? " '" : "",
                  arg ? arg : "", arg ? "'" : "");
    return EXIT_USAGE;
}

static bool parse_double(const char *text, double *out)
{
    if ((text[0] < '0' || text[0] > '9') && text[0] != '.') {
        return false;
    }
    errno = 0;
    char *end = NULL;
    const double value = strtod(text, &end);
    if (errno != 0 || *end != '\0' || !isfinite(value)) {
        return false;
    }
    *out = value;
    return true;
}

/* One option with a value; returns -1 when good, else the exit code. */
static int parse_option(const char *opt, const char *val, gen_options_t *o)
{
    uint64_t number = 0u;
    double real = 0.0;
    if (strcmp(opt, "--scenario") == 0) {
        o->scenario = wscenario_find(val);
        if (o->scenario == NULL) {
            return usage_error("unknown scenario", val);
        }
    } else if (strcmp(opt, "--seed") == 0) {
        if (!parse_unsigned(val, UINT64_MAX, &number)) {
            return usage_error("bad --seed", val);
        }
        o->seed = number;
    } else if (strcmp(opt, "--scans") == 0) {
        if (!parse_unsigned(val, GEN_MAX_SCANS, &number) || number < 2u) {
            return usage_error("bad --scans (2..100000)", val);
        }
        o->scans = (unsigned)number;
    } else if (strcmp(opt, "--skip") == 0) {
        if (!parse_unsigned(val, GEN_MAX_SCANS, &number)) {
            return usage_error("bad --skip (0..100000)", val);
        }
        o->skip = (unsigned)number;
    } else if (strcmp(opt, "--res") == 0) {
        if (!parse_double(val, &real) || (real != 1.0 && real != 0.5)) {
            return usage_error("bad --res (1 or 0.5)", val);
        }
        o->values = (real == 1.0) ? 181u : 361u;
        o->res_text = (real == 1.0) ? "1" : "0.5";
    } else if (strcmp(opt, "--unit") == 0) {
        if (strcmp(val, "mm") == 0) {
            o->unit = LMS_UNIT_MM;
        } else if (strcmp(val, "cm") == 0) {
            o->unit = LMS_UNIT_CM;
        } else {
            return usage_error("bad --unit (cm or mm)", val);
        }
    } else if (strcmp(opt, "--noise-cm") == 0) {
        if (!parse_double(val, &real) || real > GEN_MAX_NOISE_CM) {
            return usage_error("bad --noise-cm (0..100)", val);
        }
        o->noise_cm = real;
    } else if (strcmp(opt, "--max-range") == 0) {
        if (!parse_double(val, &real) || !(real > 0.0) || real > WORLD_MAX_RANGE_CM) {
            return usage_error("bad --max-range (metres, at most 81.82)", val);
        }
        o->max_range = real;
    } else if (strcmp(opt, "--timing") == 0) {
        if (strcmp(val, "lms") == 0) {
            o->lms_timing = true;
        } else if (strcmp(val, "instant") == 0) {
            o->lms_timing = false;
        } else {
            return usage_error("bad --timing (instant or lms)", val);
        }
    } else if (strcmp(opt, "-o") == 0) {
        o->out_path = val;
    } else if (strcmp(opt, "--truth") == 0) {
        o->truth_path = val;
    } else if (strcmp(opt, "--poses") == 0) {
        o->poses_path = val;
    } else if (strcmp(opt, "--objects") == 0) {
        o->objects_path = val;
    } else {
        return usage_error("unknown option", opt);
    }
    return -1;
}

/* Returns -1 when the options are good, else the exit code. */
static int parse_options(int argc, char **argv, gen_options_t *o)
{
    memset(o, 0, sizeof *o);
    o->seed = 1u;
    o->values = 361u;
    o->res_text = "0.5";
    o->unit = LMS_UNIT_CM;
    o->noise_cm = 0.0;
    o->max_range = 50.0;

    for (int i = 1; i < argc; i++) {
        const char *opt = argv[i];
        if (strcmp(opt, "-h") == 0 || strcmp(opt, "--help") == 0) {
            print_usage(stdout);
            return 0;
        }
        if (i + 1 >= argc) {
            return usage_error("missing value or unknown option", opt);
        }
        const int rc = parse_option(opt, argv[++i], o);
        if (rc >= 0) {
            return rc;
        }
    }
    if (o->scenario == NULL) {
        return usage_error("--scenario NAME is required", NULL);
    }
    if (o->out_path == NULL || o->truth_path == NULL) {
        return usage_error("-o STREAM and --truth PAIRS are required", NULL);
    }
    if (o->unit == LMS_UNIT_MM && o->max_range > WORLD_MAX_RANGE_MM) {
        return usage_error("--unit mm needs --max-range 65.535 or less", NULL);
    }
    if (o->scans == 0u) {
        o->scans = o->scenario->default_scans;
    }
    if (o->scenario->required_scans != 0u &&
        (o->scans != o->scenario->required_scans || o->skip != 0u)) {
        (void)fprintf(stderr, "lmsworld: scenario %s has exactly %u scans (try --help)\n",
                      o->scenario->name, o->scenario->required_scans);
        return EXIT_USAGE;
    }
    return -1;
}

/* ------------------------------------------------------------------ */
/* Generation. */

typedef struct {
    buf_t stream;
    buf_t truth;
    buf_t poses;
    buf_t objects;
} outputs_t;

/* Encodes one scan with the driver and appends the telegram. */
static void append_scan(buf_t *stream, const uint16_t *words, unsigned count, lms_unit_t unit)
{
    static lms_scan_t scan;
    static uint8_t tel[LMS_TELEGRAM_MAX];
    memset(&scan, 0, sizeof scan);
    scan.address = GEN_ADDRESS;
    scan.status = GEN_STATUS;
    scan.unit = unit;
    scan.count = (uint16_t)count;
    memcpy(scan.values, words, count * sizeof words[0]);
    size_t written = 0u;
    const lms_status_t st = lms_encode_scan(tel, sizeof tel, GEN_ADDRESS, &scan, &written);
    if (st != LMS_OK || written != 2u * count + 10u) {
        (void)fprintf(stderr, "lmsworld: lms_encode_scan failed: %s\n", lms_status_name(st));
        exit(EXIT_RUNTIME);
    }
    buf_append(stream, tel, written);
}

/* %.9f without a "-0.000000000". */
static double tidy(double v)
{
    return (fabs(v) < 5e-10) ? 0.0 : v;
}

/* %.6f without a "-0.000000". */
static double tidy6(double v)
{
    return (fabs(v) < 5e-7) ? 0.0 : v;
}

static void header(buf_t *b, const gen_options_t *o, const char *what)
{
    buf_printf(b,
               "# lmsworld --scenario %s --seed %llu --scans %u --skip %u --res %s --unit %s "
               "--noise-cm %g --max-range %g%s\n# %s\n",
               o->scenario->name, (unsigned long long)o->seed, o->scans, o->skip, o->res_text,
               (o->unit == LMS_UNIT_MM) ? "mm" : "cm", o->noise_cm, o->max_range,
               o->lms_timing ? " --timing lms" : "", what);
}

/* Half the time step of the movers' velocities, s: central differences
 * over 2 ms are exact to far below the printed 1e-6 m/s for the smooth
 * motions of the scenarios. */
#define GEN_VELOCITY_DT 1e-3

/* The objects file's lines of stream scan k (scenario scan scene_k): each
 * mover at the scan's time in the frame of the scanner's pose then, its
 * velocity over ground (differenced over +-GEN_VELOCITY_DT) in that frame,
 * and the beams of the cast ranges that hit it. */
static void append_objects(buf_t *b, const gen_options_t *o, unsigned k, unsigned scene_k,
                           double period, double res_deg, wpose_t pose, const double *ranges,
                           wmap_t *scratch)
{
    const wscenario_t *sc = o->scenario;
    unsigned returns[WORLD_MAX_MOVERS];
    const size_t n = world_scan_returns(sc, scene_k, period, o->values, res_deg, o->lms_timing,
                                        ranges, o->max_range, scratch, returns);
    wmover_t now[WORLD_MAX_MOVERS];
    wmover_t before[WORLD_MAX_MOVERS];
    wmover_t after[WORLD_MAX_MOVERS];
    const double t = (double)scene_k * period;
    const size_t n_now = (sc->movers != NULL) ? sc->movers(t, now) : 0u;
    const size_t n_before = (sc->movers != NULL) ? sc->movers(t - GEN_VELOCITY_DT, before) : 0u;
    const size_t n_after = (sc->movers != NULL) ? sc->movers(t + GEN_VELOCITY_DT, after) : 0u;
    if (n_now != n || n_before != n || n_after != n) {
        (void)fputs("lmsworld: internal error: the number of movers changed\n", stderr);
        exit(EXIT_RUNTIME);
    }
    const double c = cos(pose.theta);
    const double s = sin(pose.theta);
    for (size_t j = 0u; j < n; j++) {
        const wpose_t at = {now[j].x, now[j].y, now[j].heading};
        const wpose_t rel = world_between(pose, at);
        const double vx = (after[j].x - before[j].x) / (2.0 * GEN_VELOCITY_DT);
        const double vy = (after[j].y - before[j].y) / (2.0 * GEN_VELOCITY_DT);
        buf_printf(b, "%u %zu %.6f %.6f %.6f %.6f %.6f %.3f %.3f %u\n", k, j, tidy6(rel.x),
                   tidy6(rel.y), tidy6(rel.theta), tidy6(c * vx + s * vy),
                   tidy6(-s * vx + c * vy),
                   now[j].length, now[j].width, returns[j]);
    }
}

static void generate(const gen_options_t *o, outputs_t *out)
{
    /* Bring-up as seen on the scanner -> host line: ACK + A0 reply to the
     * host's 20 24 (lms2xx-vectors.txt V21). */
    static const uint8_t a0_reply[] = {0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A};
    const uint8_t ack = LMS_ACK;
    buf_append(&out->stream, &ack, 1u);
    buf_append(&out->stream, a0_reply, sizeof a0_reply);

    header(&out->truth, o, "i j dx dy dtheta: pose of scan j in the frame of scan i (m, m, rad)");
    header(&out->poses, o, "time x y z qx qy qz qw (TUM; s, m, unit quaternion)");
    header(&out->objects, o,
           "scan id cx cy heading vx vy length width returns: each moving object at the scan's "
           "time in the scanner frame (x forward, y left; m, m, rad), its velocity over ground "
           "in that frame (m/s), its size (m) and the beams of the scan that hit it");

    const double res_deg = (o->values == 181u) ? 1.0 : 0.5;
    const double period = (o->values == 181u) ? 1.0 / 75.0 : 2.0 / 75.0;
    const double noise_m = o->noise_cm / 100.0;

    rng_t rng;
    rng_seed(&rng, o->seed);
    wmap_t world;
    wmap_t active;
    wmap_t scratch;
    wmap_init(&world);
    wmap_init(&active);
    wmap_init(&scratch);
    o->scenario->build_map(&world);

    static double ranges[LMS_SCAN_MAX_VALUES];
    static uint16_t words[LMS_SCAN_MAX_VALUES];
    wmover_t movers[WORLD_MAX_MOVERS];
    wpose_t last = {0.0, 0.0, 0.0};
    for (unsigned k = 0u; k < o->scans; k++) {
        const unsigned scene_k = o->skip + k;
        const double t = (double)scene_k * period;
        const wpose_t pose = o->scenario->pose(scene_k, period, 0.0);
        if (o->lms_timing) {
            world_scan_cast_lms(o->scenario, &world, scene_k, period, o->values, res_deg,
                                o->max_range, &active, &scratch, ranges);
        } else {
            const size_t mover_count =
                (o->scenario->movers != NULL) ? o->scenario->movers(t, movers) : 0u;
            world_scan_prepare(&world, movers, mover_count, pose, o->max_range, &active);
            world_scan_cast(&active, pose, o->values, res_deg, ranges);
        }
        for (unsigned i = 0u; i < o->values; i++) {
            /* One deviate per beam, hit or not: the noise of a beam does
             * not depend on the others. */
            const double noise = noise_m * rng_gauss(&rng);
            words[i] = world_range_word(ranges[i], noise, o->unit, o->max_range);
        }
        append_scan(&out->stream, words, o->values, o->unit);
        if (o->objects_path != NULL) {
            append_objects(&out->objects, o, k, scene_k, period, res_deg, pose, ranges,
                           &scratch);
        }

        buf_printf(&out->poses, "%.9f %.9f %.9f 0 0 0 %.9f %.9f\n", t, tidy(pose.x),
                   tidy(pose.y), tidy(sin(0.5 * pose.theta)), tidy(cos(0.5 * pose.theta)));
        if (k > 0u) {
            const wpose_t rel = world_between(last, pose);
            buf_printf(&out->truth, "%u %u %.9f %.9f %.9f\n", k - 1u, k, tidy(rel.x),
                       tidy(rel.y), tidy(rel.theta));
        }
        last = pose;
    }
    wmap_free(&world);
    wmap_free(&active);
    wmap_free(&scratch);
}

int main(int argc, char **argv)
{
    gen_program = "lmsworld";
    gen_options_t o;
    const int parsed = parse_options(argc, argv, &o);
    if (parsed >= 0) {
        return parsed;
    }

    outputs_t out;
    memset(&out, 0, sizeof out);
    generate(&o, &out);

    int rc = 0;
    if (write_file(o.out_path, &out.stream) != 0 || write_file(o.truth_path, &out.truth) != 0) {
        rc = EXIT_RUNTIME;
    }
    if (rc == 0 && o.poses_path != NULL && write_file(o.poses_path, &out.poses) != 0) {
        rc = EXIT_RUNTIME;
    }
    if (rc == 0 && o.objects_path != NULL && write_file(o.objects_path, &out.objects) != 0) {
        rc = EXIT_RUNTIME;
    }
    buf_free(&out.stream);
    buf_free(&out.truth);
    buf_free(&out.poses);
    buf_free(&out.objects);
    return rc;
}
