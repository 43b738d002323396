/* lmsgen.c - synthetic LMS 2xx recording generator (host-only).
 *
 * Writes what a host would record on the scanner -> host line after
 * sending 20 24 (continuous output): the ACK byte 06, the A0 reply
 * 02 80 03 00 A0 00 10 16 0A, then B0 telegrams back to back, built with
 * lms_encode_scan from scans ray-cast in a simulated room (room_scene.h).
 * Measuring mode 00 (13-bit values): ranges above 8182 units become 0x1FF7
 * (beyond max), a few seeded values become 0x1FFF (no return) and 0x1FFE
 * (dazzle), and ranges under 2 m / 1.5 m carry the field A / field B flag
 * bits 13 / 14 as a scanner with such warning fields would send them.
 *
 * With --faults it damages the stream at fixed fractions of its length
 * (see place_faults) and predicts the framer's counters with the
 * contract model in framer_model.c.
 *
 * With --adversarial it writes issue 15's hard scans instead of the room,
 * a few of each kind in one stream; with --case NAME one of those kinds
 * alone, --scans of it (issue 18: a stream per case, each starting the
 * estimator afresh; host_tests/data/recordings/adversarial/).
 *
 * Ground-truth outputs, written from the generator's own values (not by
 * decoding what it wrote):
 *   --truth FILE         the exact `lmsego scans FILE` output
 *   --expect-stats FILE  the exact `lmsego stats FILE` output
 *
 * Deterministic: xorshift64 seeded from --seed, no rand(), no clock.
 */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "framer_model.h"
#include "gen_common.h"
#include "lms_encode.h"
#include "lms_proto.h"
#include "room_scene.h"

#define EXIT_RUNTIME 1
#define EXIT_USAGE 2

#define GEN_PI 3.14159265358979323846
#define GEN_ADDRESS 0x80u /* scanner at address 0 */
#define GEN_STATUS 0x10u  /* healthy status byte */
#define GEN_MAX_SCANS 100000u
#define GEN_MIN_FAULT_SCANS 20u

/* 13-bit measuring mode 00: largest range, special codes, flag bits. */
#define WORD_MAX_RANGE 0x1FF6u
#define WORD_BEYOND_MAX 0x1FF7u
#define WORD_DAZZLE 0x1FFEu
#define WORD_NO_RETURN 0x1FFFu
#define WORD_DISTANCE_MASK 0x1FFFu
#define WORD_FIELD_A 0x2000u
#define WORD_FIELD_B 0x4000u
#define FIELD_A_MM 2000.0
#define FIELD_B_MM 1500.0

/* Per mille of values replaced by special codes. */
#define NO_RETURN_PER_MILLE 2u
#define DAZZLE_PER_MILLE 1u

/* The codes `lmsego scans` prints for special values (lms_value_kind_t). */
#define TRUTH_NO_RETURN (-1)
#define TRUTH_DAZZLE (-2)
#define TRUTH_BEYOND_MAX (-7)

/* ------------------------------------------------------------------ */
/* Random numbers: xorshift64 (13, 7, 17), seeded through splitmix64 so
 * that neighbouring seeds give unrelated sequences and 0 is never the
 * state. */

typedef struct {
    uint64_t state;
} rng_t;

static void rng_seed(rng_t *r, uint64_t seed)
{
    uint64_t z = seed + 0x9E3779B97F4A7C15u;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    z ^= z >> 31;
    r->state = (z != 0u) ? z : 0x2545F4914F6CDD1Du;
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

/* Uniform in [0, n) for small n (modulo bias below 1e-15). */
static uint32_t rng_below(rng_t *r, uint32_t n)
{
    return (uint32_t)(rng_next(r) % n);
}

/* Uniform in [0, 1). */
static double rng_unit(rng_t *r)
{
    return (double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

/* ------------------------------------------------------------------ */
/* Growable byte buffer for the stream and the text outputs. */

static void buf_byte(buf_t *b, uint8_t byte)
{
    buf_append(b, &byte, 1u);
}

static void buf_text(buf_t *b, const char *text)
{
    buf_append(b, text, strlen(text));
}

static void buf_long(buf_t *b, long value)
{
    char text[24];
    (void)snprintf(text, sizeof text, "%ld", value);
    buf_text(b, text);
}

/* Issue 15's hard scans (the estimator must keep its budget and say what it
 * could not measure): ADVERSARIAL_SCANS of each kind in turn. */
enum {
    ADV_ALL_INVALID = 0,
    ADV_ONE_POINT,
    ADV_TWO_POINTS,
    ADV_STRAIGHT_WALL,
    ADV_ONE_RANGE,
    ADV_ZIGZAG_AT_LIMIT,
    ADV_ALL_AT_MAX,
    ADV_SPECIALS,
    ADV_ROOM_REPEATED,
    ADV_MIRRORED,
    ADVERSARIAL_KINDS
};
#define ADVERSARIAL_SCANS 8u
#define CASE_DEFAULT_SCANS 30u

/* --case NAME: the kind's name on the command line, in enum order. */
static const char *const adversarial_names[ADVERSARIAL_KINDS] = {
    "invalid",      "one-point", "two-points", "collinear", "one-range",
    "zigzag-limit", "all-max",   "specials",   "repeated",  "alternating"};

/* Every code of measuring mode 00 that is not a range (lms2xx-protocol.md
 * section 4.3: 0x1FF7 and above), with the number `lmsego scans` prints
 * for it (lms_value_kind_t): --case specials cycles through all nine. */
typedef struct {
    uint16_t word;
    long truth;
} special_code_t;

static const special_code_t special_codes[] = {
    {0x1FF7u, -7}, /* beyond the maximum range */
    {0x1FF8u, -8}, /* reserved */
    {0x1FF9u, -8}, /* reserved */
    {0x1FFAu, -5}, /* error reading channel 1 */
    {0x1FFBu, -4}, /* signal-to-noise ratio too small */
    {0x1FFCu, -8}, /* reserved */
    {0x1FFDu, -3}, /* operation overflow */
    {0x1FFEu, -2}, /* dazzle */
    {0x1FFFu, -1}  /* no return */
};
#define SPECIAL_CODES (sizeof special_codes / sizeof special_codes[0])

/* ------------------------------------------------------------------ */
/* Options. */

typedef struct {
    uint64_t seed;
    unsigned scans;
    unsigned values; /* 181, 361 or 401 */
    lms_unit_t unit;
    bool faults;
    bool adversarial; /* issue 15's hard scans instead of the room */
    int one_case;     /* --case: that kind alone (0..ADVERSARIAL_KINDS-1), else -1 */
    bool verbose;
    const char *out_path;
    const char *truth_path;
    const char *stats_path;
} gen_options_t;

static void print_usage(FILE *to)
{
    (void)fputs(
        "usage: lmsgen [--seed N] [--scans N] [--values 181|361|401] [--unit mm|cm]\n"
        "              [--faults | --adversarial | --case NAME] [--verbose]\n"
        "              -o FILE [--truth FILE] [--expect-stats FILE]\n"
        "Writes a synthetic LMS 2xx scanner->host recording: 06, A0 reply, B0 stream.\n"
        "  --seed N            xorshift seed (default 1)\n"
        "  --scans N           B0 telegrams to write (default 200)\n"
        "  --values N          181 / 361: 180 deg at 1 / 0.5 deg; 401: 100 deg at 0.25 deg\n"
        "  --unit mm|cm        value unit (default mm)\n"
        "  --faults            inject garbage, a CRC error, a bad length, truncations\n"
        "  --adversarial       instead of the room, ADVERSARIAL_SCANS scans of each hard case\n"
        "                      in turn: every value invalid, one valid point, two, a straight\n"
        "                      wall, all at one range, a zig-zag at the range limit, all at\n"
        "                      maximum range, special values alternating, one room scan\n"
        "                      repeated, a room and its mirror image alternating (--scans\n"
        "                      is then ignored)\n"
        "  --verbose           describe the faults and expected counters on stderr\n"
        "  -o FILE             the recording\n"
        "  --truth FILE        expected `lmsego scans FILE` output\n"
        "  --expect-stats FILE expected `lmsego stats FILE` output\n",
        to);
}

static int usage_error(const char *problem, const char *arg)
{
    (void)fprintf(stderr, "lmsgen: %s%s%s%s (try --help)\n", problem, arg ? " '" : "",
                  arg ? arg : "", arg ? "'" : "");
    return EXIT_USAGE;
}

/* Returns -1 when the options are good, else the exit code. */
static int parse_options(int argc, char **argv, gen_options_t *o)
{
    o->seed = 1u;
    o->scans = 200u;
    o->values = 181u;
    o->unit = LMS_UNIT_MM;
    o->faults = false;
    o->adversarial = false;
    o->one_case = -1;
    o->verbose = false;
    o->out_path = NULL;
    o->truth_path = NULL;
    o->stats_path = NULL;

    bool scans_given = false;
    for (int i = 1; i < argc; i++) {
        const char *opt = argv[i];
        if (strcmp(opt, "-h") == 0 || strcmp(opt, "--help") == 0) {
            print_usage(stdout);
            return 0;
        }
        if (strcmp(opt, "--faults") == 0) {
            o->faults = true;
            continue;
        }
        if (strcmp(opt, "--verbose") == 0) {
            o->verbose = true;
            continue;
        }
        if (strcmp(opt, "--adversarial") == 0) {
            o->adversarial = true;
            continue;
        }
        if (i + 1 >= argc) {
            return usage_error("missing value or unknown option", opt);
        }
        const char *val = argv[++i];
        uint64_t number = 0u;
        if (strcmp(opt, "--seed") == 0) {
            if (!parse_unsigned(val, UINT64_MAX, &number)) {
                return usage_error("bad --seed", val);
            }
            o->seed = number;
        } else if (strcmp(opt, "--scans") == 0) {
            if (!parse_unsigned(val, GEN_MAX_SCANS, &number) || number == 0u) {
                return usage_error("bad --scans (1..100000)", val);
            }
            o->scans = (unsigned)number;
            scans_given = true;
        } else if (strcmp(opt, "--case") == 0) {
            o->one_case = -1;
            for (unsigned k = 0u; k < (unsigned)ADVERSARIAL_KINDS; k++) {
                if (strcmp(val, adversarial_names[k]) == 0) {
                    o->one_case = (int)k;
                }
            }
            if (o->one_case < 0) {
                return usage_error("bad --case (see --help)", val);
            }
        } else if (strcmp(opt, "--values") == 0) {
            if (!parse_unsigned(val, 1000u, &number) ||
                (number != 181u && number != 361u && number != 401u)) {
                return usage_error("bad --values (181, 361 or 401)", val);
            }
            o->values = (unsigned)number;
        } else if (strcmp(opt, "--unit") == 0) {
            if (strcmp(val, "mm") == 0) {
                o->unit = LMS_UNIT_MM;
            } else if (strcmp(val, "cm") == 0) {
                o->unit = LMS_UNIT_CM;
            } else {
                return usage_error("bad --unit (mm or cm)", val);
            }
        } else if (strcmp(opt, "-o") == 0) {
            o->out_path = val;
        } else if (strcmp(opt, "--truth") == 0) {
            o->truth_path = val;
        } else if (strcmp(opt, "--expect-stats") == 0) {
            o->stats_path = val;
        } else {
            return usage_error("unknown option", opt);
        }
    }
    if (o->out_path == NULL) {
        return usage_error("-o FILE is required", NULL);
    }
    if (o->faults && o->scans < GEN_MIN_FAULT_SCANS) {
        return usage_error("--faults needs --scans 20 or more", NULL);
    }
    if (o->adversarial && o->faults) {
        return usage_error("--adversarial and --faults do not mix", NULL);
    }
    if (o->one_case >= 0 && (o->faults || o->adversarial)) {
        return usage_error("--case mixes with neither --faults nor --adversarial", NULL);
    }
    if (o->adversarial) {
        o->scans = ADVERSARIAL_KINDS * ADVERSARIAL_SCANS;
    }
    if (o->one_case >= 0 && !scans_given) {
        o->scans = CASE_DEFAULT_SCANS;
    }
    return -1;
}

/* ------------------------------------------------------------------ */
/* Scans. */

typedef struct {
    unsigned count;
    double start_deg;
    double step_deg;
} layout_t;

static layout_t layout_for(unsigned values)
{
    layout_t l;
    l.count = values;
    if (values == 401u) {
        l.start_deg = 40.0; /* 100 deg field, 0.25 deg */
        l.step_deg = 0.25;
    } else {
        l.start_deg = 0.0; /* 180 deg field, 1 or 0.5 deg */
        l.step_deg = 180.0 / (double)(values - 1u);
    }
    return l;
}

/* One scan: the value words to encode and what lmsego must print for each. */
typedef struct {
    uint16_t words[LMS_SCAN_MAX_VALUES];
    long truth[LMS_SCAN_MAX_VALUES];
} gen_scan_t;

static void make_scan(rng_t *rng, unsigned k, const layout_t *layout, lms_unit_t unit,
                      gen_scan_t *out)
{
    const double unit_mm = (unit == LMS_UNIT_MM) ? 1.0 : 10.0;
    const room_pose_t pose = room_scanner_pose(k);
    for (unsigned i = 0u; i < layout->count; i++) {
        /* Scanner angles: 0 right, 90 ahead, 180 left. */
        const double beam_deg = layout->start_deg + layout->step_deg * (double)i;
        const double world = pose.heading + (beam_deg - 90.0) * (GEN_PI / 180.0);
        const double range_mm = room_cast_ray(pose.x, pose.y, world) * 1000.0;
        /* Range noise: sum of four uniforms, +-20 mm, sigma about 5.8 mm. */
        const double noise_mm =
            (rng_unit(rng) + rng_unit(rng) + rng_unit(rng) + rng_unit(rng) - 2.0) * 10.0;
        const uint32_t special = rng_below(rng, 1000u);

        long units = lround((range_mm + noise_mm) / unit_mm);
        if (units < 1) {
            units = 1;
        }
        if (special < NO_RETURN_PER_MILLE) {
            out->words[i] = WORD_NO_RETURN;
            out->truth[i] = TRUTH_NO_RETURN;
        } else if (special < NO_RETURN_PER_MILLE + DAZZLE_PER_MILLE) {
            out->words[i] = WORD_DAZZLE;
            out->truth[i] = TRUTH_DAZZLE;
        } else if (units > (long)WORD_MAX_RANGE) {
            out->words[i] = WORD_BEYOND_MAX;
            out->truth[i] = TRUTH_BEYOND_MAX;
        } else {
            const double mm = (double)units * unit_mm;
            unsigned word = (unsigned)units;
            if (mm < FIELD_A_MM) {
                word |= WORD_FIELD_A;
            }
            if (mm < FIELD_B_MM) {
                word |= WORD_FIELD_B;
            }
            out->words[i] = (uint16_t)word;
            out->truth[i] = units * (long)unit_mm;
        }
    }
}


/* A range in the stream's unit, as a value word and its truth. */
static void put_range(gen_scan_t *out, unsigned i, double range_mm, lms_unit_t unit)
{
    const double unit_mm = (unit == LMS_UNIT_MM) ? 1.0 : 10.0;
    long units = lround(range_mm / unit_mm);
    units = (units < 1) ? 1 : ((units > (long)WORD_MAX_RANGE) ? (long)WORD_MAX_RANGE : units);
    out->words[i] = (uint16_t)units;
    out->truth[i] = units * (long)unit_mm;
}

static void put_word(gen_scan_t *out, unsigned i, uint16_t word, long truth)
{
    out->words[i] = word;
    out->truth[i] = truth;
}

/* Scan k of the hard case kind. every_code: the special values cycle
 * through all nine codes, one beam further each scan (--case); else
 * through no return, dazzle and beyond max (--adversarial, as shipped). */
static void make_adversarial(unsigned kind, unsigned k, bool every_code, const layout_t *layout,
                             lms_unit_t unit, gen_scan_t *out)
{
    const unsigned n = layout->count;
    const double unit_mm = (unit == LMS_UNIT_MM) ? 1.0 : 10.0;
    const double max_mm = (double)WORD_MAX_RANGE * unit_mm;
    const room_pose_t pose = room_scanner_pose(0u);
    for (unsigned i = 0u; i < n; i++) {
        const double beam_deg = layout->start_deg + layout->step_deg * (double)i;
        /* The mirror image swaps the beams end for end on odd scans. */
        const unsigned mirrored = (kind == ADV_MIRRORED && k % 2u == 1u) ? n - 1u - i : i;
        const double room_deg = layout->start_deg + layout->step_deg * (double)mirrored;
        const double room_mm =
            room_cast_ray(pose.x, pose.y, pose.heading + (room_deg - 90.0) * (GEN_PI / 180.0)) *
            1000.0;
        switch (kind) {
        case ADV_ALL_INVALID:
            put_word(out, i, WORD_NO_RETURN, TRUTH_NO_RETURN);
            break;
        case ADV_ONE_POINT:
            if (i == n / 2u) {
                put_range(out, i, 5000.0, unit);
            } else {
                put_word(out, i, WORD_NO_RETURN, TRUTH_NO_RETURN);
            }
            break;
        case ADV_TWO_POINTS:
            if (i == n / 3u || i == 2u * n / 3u) {
                put_range(out, i, 5000.0, unit);
            } else {
                put_word(out, i, WORD_NO_RETURN, TRUTH_NO_RETURN);
            }
            break;
        case ADV_STRAIGHT_WALL: { /* 5 m ahead, across the whole field */
            const double c = fabs(cos((beam_deg - 90.0) * (GEN_PI / 180.0)));
            put_range(out, i, (c > 0.06) ? 5000.0 / c : max_mm, unit);
            break;
        }
        case ADV_ONE_RANGE: /* a circle around the scanner */
            put_range(out, i, 5000.0, unit);
            break;
        case ADV_ZIGZAG_AT_LIMIT:
            put_range(out, i, (i % 2u == 0u) ? max_mm : max_mm - 800.0, unit);
            break;
        case ADV_ALL_AT_MAX:
            put_range(out, i, max_mm, unit);
            break;
        case ADV_SPECIALS:
            if (every_code) {
                const special_code_t *c = &special_codes[(i + k) % SPECIAL_CODES];
                put_word(out, i, c->word, c->truth);
            } else if (i % 3u == 0u) {
                put_word(out, i, WORD_NO_RETURN, TRUTH_NO_RETURN);
            } else if (i % 3u == 1u) {
                put_word(out, i, WORD_DAZZLE, TRUTH_DAZZLE);
            } else {
                put_word(out, i, WORD_BEYOND_MAX, TRUTH_BEYOND_MAX);
            }
            break;
        default: /* the room from one pose, repeated or mirrored */
            put_range(out, i, room_mm, unit);
            break;
        }
    }
}

/* Encodes a scan with the driver, then checks the bytes against the
 * protocol layout (lms2xx-protocol.md section 4) with our own CRC, so a
 * broken encoder cannot slip into the shipped recordings. */
static size_t encode_scan(const gen_scan_t *s, unsigned count, lms_unit_t unit, uint8_t *tel)
{
    static lms_scan_t scan;
    memset(&scan, 0, sizeof scan);
    scan.status = GEN_STATUS;
    scan.unit = unit;
    scan.count = (uint16_t)count;
    memcpy(scan.values, s->words, count * sizeof s->words[0]);

    size_t written = 0u;
    const lms_status_t st = lms_encode_scan(tel, LMS_TELEGRAM_MAX, GEN_ADDRESS, &scan, &written);
    if (st != LMS_OK) {
        (void)fprintf(stderr, "lmsgen: lms_encode_scan failed: %s\n", lms_status_name(st));
        exit(EXIT_RUNTIME);
    }

    uint8_t expect[LMS_TELEGRAM_MAX];
    const unsigned length = 2u * count + 4u;
    const unsigned count_word = count | ((unit == LMS_UNIT_MM) ? 0x4000u : 0u);
    size_t n = 0u;
    expect[n++] = LMS_STX;
    expect[n++] = GEN_ADDRESS;
    expect[n++] = (uint8_t)(length & 0xFFu);
    expect[n++] = (uint8_t)(length >> 8);
    expect[n++] = LMS_REPLY_VALUES;
    expect[n++] = (uint8_t)(count_word & 0xFFu);
    expect[n++] = (uint8_t)(count_word >> 8);
    for (unsigned i = 0u; i < count; i++) {
        expect[n++] = (uint8_t)(s->words[i] & 0xFFu);
        expect[n++] = (uint8_t)(s->words[i] >> 8);
    }
    expect[n++] = GEN_STATUS;
    const uint16_t crc = framer_model_crc(expect, n);
    expect[n++] = (uint8_t)(crc & 0xFFu);
    expect[n++] = (uint8_t)(crc >> 8);

    if (written != n || memcmp(tel, expect, n) != 0) {
        size_t at = 0u;
        while (at < n && at < written && tel[at] == expect[at]) {
            at++;
        }
        (void)fprintf(stderr,
                      "lmsgen: lms_encode_scan output (%zu bytes) differs from the protocol layout "
                      "(%zu bytes) at byte %zu\n",
                      written, n, at);
        exit(EXIT_RUNTIME);
    }
    return n;
}

/* ------------------------------------------------------------------ */
/* Faults. */

typedef enum {
    TEL_GOOD = 0,
    TEL_BIT_FLIP,   /* one data bit flipped: CRC error */
    TEL_BAD_LENGTH, /* L = 2N + 5: impossible for a B0, length error */
    TEL_CUT_MID,    /* only the first half sent, the next telegram follows */
    TEL_CUT_END     /* the recording stops in the middle of it */
} tel_fate_t;

typedef struct {
    unsigned garbage_a; /* garbage block A goes before this scan, ... */
    unsigned garbage_b;
    unsigned garbage_c;
    unsigned bit_flip; /* ... and these scans are damaged */
    unsigned bad_length;
    unsigned cut_mid;
    unsigned cut_end;
} fault_plan_t;

/* Fixed fractions of the stream; distinct for scans >= 20. */
static fault_plan_t place_faults(unsigned scans)
{
    fault_plan_t p;
    p.garbage_a = scans / 10u;
    p.bit_flip = scans / 4u;
    p.garbage_b = (2u * scans) / 5u;
    p.bad_length = (11u * scans) / 20u;
    p.cut_mid = (7u * scans) / 10u;
    p.garbage_c = (17u * scans) / 20u;
    p.cut_end = scans - 1u;
    return p;
}

static tel_fate_t fate_of(const fault_plan_t *p, bool faults, unsigned k)
{
    if (!faults) {
        return TEL_GOOD;
    }
    if (k == p->bit_flip) {
        return TEL_BIT_FLIP;
    }
    if (k == p->bad_length) {
        return TEL_BAD_LENGTH;
    }
    if (k == p->cut_mid) {
        return TEL_CUT_MID;
    }
    if (k == p->cut_end) {
        return TEL_CUT_END;
    }
    return TEL_GOOD;
}

/* Bytes that would turn into ACK / NAK events when the framer searches a
 * rejected candidate again. The contract is not explicit about those, so
 * no damaged telegram or garbage contains them. */
static bool is_handshake_byte(uint8_t b)
{
    return b == LMS_ACK || b == LMS_NAK;
}

/* Random garbage byte: anything but STX, ACK and NAK, so that the only
 * telegram starts in the garbage are the ones put there on purpose. */
static uint8_t garbage_byte(rng_t *rng)
{
    for (;;) {
        const uint8_t b = (uint8_t)rng_below(rng, 256u);
        if (b != LMS_STX && !is_handshake_byte(b)) {
            return b;
        }
    }
}

static void garbage_random(buf_t *stream, rng_t *rng, unsigned n)
{
    for (unsigned i = 0u; i < n; i++) {
        buf_byte(stream, garbage_byte(rng));
    }
}

/* Block A: "02 41" (STX, no address: skipped) and "02 80 FF 7F" (L =
 * 0x7FFF, length error at once). */
static void garbage_block_a(buf_t *stream, rng_t *rng)
{
    static const uint8_t stx_no_address[] = {0x02, 0x41};
    static const uint8_t huge_length[] = {0x02, 0x80, 0xFF, 0x7F};
    garbage_random(stream, rng, 5u);
    buf_append(stream, stx_no_address, sizeof stx_no_address);
    garbage_random(stream, rng, 3u);
    buf_append(stream, huge_length, sizeof huge_length);
    garbage_random(stream, rng, 2u);
}

/* Block B: a plausible B2 header (L = 32, variable-size code) that
 * swallows the start of the next telegram: CRC error, and the telegram
 * must be found again inside the rejected candidate. */
static void garbage_block_b(buf_t *stream, rng_t *rng)
{
    static const uint8_t b2_header[] = {0x02, 0x80, 0x20, 0x00, 0xB2};
    garbage_random(stream, rng, 4u);
    buf_append(stream, b2_header, sizeof b2_header);
    garbage_random(stream, rng, 3u);
}

/* Block C: ends in "02 80" right before the next telegram's "02 80", so
 * the length field reads 0x8002: length error. */
static void garbage_block_c(buf_t *stream, rng_t *rng)
{
    static const uint8_t stx_address[] = {0x02, 0x80};
    garbage_random(stream, rng, 6u);
    buf_append(stream, stx_address, sizeof stx_address);
}

/* Moves the range value at or after index i (cyclically) one unit, so
 * that a damaged telegram loses a handshake byte. */
static void nudge_value(gen_scan_t *s, unsigned count, unsigned i)
{
    for (unsigned step = 0u; step < count; step++) {
        uint16_t *w = &s->words[(i + step) % count];
        const unsigned distance = *w & WORD_DISTANCE_MASK;
        if (distance > WORD_MAX_RANGE) {
            continue; /* special codes stay */
        }
        const unsigned moved = (distance < WORD_MAX_RANGE) ? distance + 1u : distance - 1u;
        *w = (uint16_t)((*w & ~WORD_DISTANCE_MASK) | moved);
        return;
    }
    (void)fputs("lmsgen: cannot clean a damaged scan without range values\n", stderr);
    exit(EXIT_RUNTIME);
}

/* Encodes a scan that will be damaged, nudging values until no byte after
 * its STX is 06 or 15. Such a telegram is never in the truth files, so
 * its values are free to move. */
static size_t encode_clean(gen_scan_t *s, unsigned count, lms_unit_t unit, uint8_t *tel)
{
    for (unsigned attempt = 0u; attempt < 100000u; attempt++) {
        const size_t n = encode_scan(s, count, unit, tel);
        size_t bad = 0u;
        for (size_t j = 1u; j < n && bad == 0u; j++) {
            if (is_handshake_byte(tel[j])) {
                bad = j;
            }
        }
        if (bad == 0u) {
            return n;
        }
        const size_t first_value = 7u;
        if (bad >= first_value && bad < first_value + 2u * (size_t)count) {
            nudge_value(s, count, (unsigned)((bad - first_value) / 2u));
        } else if (bad >= n - LMS_CRC_SIZE) {
            nudge_value(s, count, 0u); /* change the CRC */
        } else {
            (void)fprintf(stderr, "lmsgen: header byte %zu of a B0 is a handshake byte\n", bad);
            exit(EXIT_RUNTIME);
        }
    }
    (void)fputs("lmsgen: could not clean a damaged scan\n", stderr);
    exit(EXIT_RUNTIME);
}

/* ------------------------------------------------------------------ */
/* The stream. */

typedef struct {
    size_t offset;
    size_t size;
} span_t;

typedef struct {
    buf_t stream;
    buf_t truth;
    span_t *good; /* telegrams that must survive, in stream order */
    size_t good_count;
    size_t good_cap;
    unsigned scans_good;
    unsigned scans_damaged;
} gen_t;

static void add_good(gen_t *g, size_t offset, size_t size)
{
    if (g->good_count == g->good_cap) {
        const size_t cap = (g->good_cap != 0u) ? 2u * g->good_cap : 256u;
        span_t *grown = realloc(g->good, cap * sizeof *grown);
        if (grown == NULL) {
            (void)fputs("lmsgen: out of memory\n", stderr);
            exit(EXIT_RUNTIME);
        }
        g->good = grown;
        g->good_cap = cap;
    }
    g->good[g->good_count].offset = offset;
    g->good[g->good_count].size = size;
    g->good_count++;
}

static void add_truth_line(gen_t *g, const gen_scan_t *s, unsigned count, lms_unit_t unit)
{
    buf_long(&g->truth, (long)g->scans_good);
    buf_text(&g->truth, (unit == LMS_UNIT_MM) ? " 1 " : " 10 ");
    buf_long(&g->truth, (long)count);
    for (unsigned i = 0u; i < count; i++) {
        buf_byte(&g->truth, ' ');
        buf_long(&g->truth, s->truth[i]);
    }
    buf_byte(&g->truth, '\n');
    g->scans_good++;
}

static void append_damaged(gen_t *g, tel_fate_t fate, uint8_t *tel, size_t n, unsigned count,
                           rng_t *fault_rng, bool verbose)
{
    const size_t at = g->stream.len;
    if (verbose) {
        (void)fprintf(stderr, "lmsgen: scan %u is damaged:\n", g->scans_good + g->scans_damaged);
    }
    g->scans_damaged++;
    size_t keep = n;
    switch (fate) {
    case TEL_BIT_FLIP: {
        /* A low byte of a value; a bit whose flip makes no 06 / 15. */
        const size_t byte = 7u + 2u * (size_t)rng_below(fault_rng, count);
        const unsigned first_bit = rng_below(fault_rng, 8u);
        for (unsigned b = 0u; b < 8u; b++) {
            const uint8_t flipped = (uint8_t)(tel[byte] ^ (1u << ((first_bit + b) % 8u)));
            if (!is_handshake_byte(flipped)) {
                tel[byte] = flipped;
                break;
            }
        }
        if (verbose) {
            (void)fprintf(stderr, "lmsgen: bit flip in byte %zu of the telegram at offset %zu\n",
                          byte, at);
        }
        break;
    }
    case TEL_BAD_LENGTH: {
        const unsigned length = 2u * count + 5u;
        tel[2] = (uint8_t)(length & 0xFFu);
        tel[3] = (uint8_t)(length >> 8);
        if (verbose) {
            (void)fprintf(stderr, "lmsgen: length field %u in the telegram at offset %zu\n", length,
                          at);
        }
        break;
    }
    case TEL_CUT_MID:
        keep = n / 2u;
        if (verbose) {
            (void)fprintf(stderr, "lmsgen: telegram at offset %zu cut to %zu of %zu bytes\n", at,
                          keep, n);
        }
        break;
    case TEL_CUT_END:
        /* The stream must not end in a lone 02 (see framer_model.h). */
        keep = (3u * n) / 5u;
        while (keep > 2u && tel[keep - 1u] == LMS_STX) {
            keep--;
        }
        if (verbose) {
            (void)fprintf(stderr,
                          "lmsgen: recording ends after %zu of %zu bytes of the telegram at "
                          "offset %zu\n",
                          keep, n, at);
        }
        break;
    case TEL_GOOD:
        break;
    }
    buf_append(&g->stream, tel, keep);
}

static void generate(gen_t *g, const gen_options_t *o)
{
    /* Bring-up as seen on the scanner -> host line: ACK + A0 reply to the
     * host's 20 24 (lms2xx-vectors.txt V21). */
    static const uint8_t a0_reply[] = {0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A};
    buf_byte(&g->stream, LMS_ACK);
    add_good(g, g->stream.len, sizeof a0_reply);
    buf_append(&g->stream, a0_reply, sizeof a0_reply);

    /* Two generators: the scene's values do not depend on --faults. */
    rng_t scene_rng;
    rng_t fault_rng;
    rng_seed(&scene_rng, o->seed);
    rng_seed(&fault_rng, o->seed ^ 0xFA017FA017u);

    const layout_t layout = layout_for(o->values);
    const fault_plan_t plan = place_faults(o->scans);
    static gen_scan_t scan;
    static uint8_t tel[LMS_TELEGRAM_MAX];

    for (unsigned k = 0u; k < o->scans; k++) {
        const size_t before = g->stream.len;
        if (o->faults && k == plan.garbage_a) {
            garbage_block_a(&g->stream, &fault_rng);
        }
        if (o->faults && k == plan.garbage_b) {
            garbage_block_b(&g->stream, &fault_rng);
        }
        if (o->faults && k == plan.garbage_c) {
            garbage_block_c(&g->stream, &fault_rng);
        }
        if (o->verbose && g->stream.len != before) {
            (void)fprintf(stderr, "lmsgen: %zu garbage bytes at offset %zu, before scan %u\n",
                          g->stream.len - before, before, k);
        }
        if (o->adversarial) {
            make_adversarial(k / ADVERSARIAL_SCANS, k, false, &layout, o->unit, &scan);
        } else if (o->one_case >= 0) {
            make_adversarial((unsigned)o->one_case, k, true, &layout, o->unit, &scan);
        } else {
            make_scan(&scene_rng, k, &layout, o->unit, &scan);
        }
        const tel_fate_t fate = fate_of(&plan, o->faults, k);
        if (fate == TEL_GOOD) {
            const size_t n = encode_scan(&scan, layout.count, o->unit, tel);
            add_good(g, g->stream.len, n);
            buf_append(&g->stream, tel, n);
            add_truth_line(g, &scan, layout.count, o->unit);
        } else {
            const size_t n = encode_clean(&scan, layout.count, o->unit, tel);
            append_damaged(g, fate, tel, n, layout.count, &fault_rng, o->verbose);
        }
    }
}

/* ------------------------------------------------------------------ */
/* Expected counters. */

typedef struct {
    const gen_t *g;
    size_t seen;
    bool mismatch;
    bool verbose;
} check_ctx_t;

static void check_event(void *ctx, framer_model_verdict_t verdict, size_t offset, size_t size)
{
    static const char *const names[] = {"telegram", "length error", "crc error", "truncated"};
    check_ctx_t *c = ctx;
    if (verdict != FRAMER_MODEL_TELEGRAM) {
        if (c->verbose) {
            (void)fprintf(stderr, "lmsgen: model: %s at offset %zu\n", names[verdict], offset);
        }
        return;
    }
    if (c->seen >= c->g->good_count || c->g->good[c->seen].offset != offset ||
        c->g->good[c->seen].size != size) {
        if (!c->mismatch) {
            (void)fprintf(stderr,
                          "lmsgen: the framer model accepts an unexpected telegram at offset "
                          "%zu (%zu bytes)\n",
                          offset, size);
        }
        c->mismatch = true;
    }
    c->seen++;
}

static int expected_stats(const gen_t *g, const gen_options_t *o, buf_t *line)
{
    framer_model_counts_t m;
    check_ctx_t check = {g, 0u, false, o->verbose};
    framer_model_run(g->stream.data, g->stream.len, &m, check_event, &check);

    if (check.mismatch || check.seen != g->good_count) {
        (void)fprintf(stderr,
                      "lmsgen: seed %llu: the model keeps %zu telegrams, %zu were meant to "
                      "survive; try another seed\n",
                      (unsigned long long)o->seed, check.seen, g->good_count);
        return -1;
    }
    if (m.acks != 1u || m.naks != 0u || m.ends_with_lone_stx) {
        (void)fputs("lmsgen: the stream would depend on unspecified framer behaviour\n", stderr);
        return -1;
    }
    if (m.bytes_in != m.telegram_bytes + m.acks + m.naks + m.bytes_skipped) {
        (void)fputs("lmsgen: framer model counters do not add up\n", stderr);
        return -1;
    }
    if (o->verbose) {
        (void)fprintf(stderr,
                      "lmsgen: model: %lu telegrams, %lu crc errors, %lu length errors, %lu "
                      "truncated, %lu bytes skipped, %lu resyncs\n",
                      (unsigned long)m.telegrams, (unsigned long)m.crc_errors,
                      (unsigned long)m.length_errors, (unsigned long)m.truncated,
                      (unsigned long)m.bytes_skipped, (unsigned long)m.resyncs);
    }

    char text[400];
    (void)snprintf(text, sizeof text,
                   "telegrams=%lu scans=%u crc_errors=%lu length_errors=%lu bytes_skipped=%lu"
                   " resyncs=%lu truncated=%lu acks=%lu naks=%lu bytes=%lu decode_errors=0\n",
                   (unsigned long)m.telegrams, g->scans_good, (unsigned long)m.crc_errors,
                   (unsigned long)m.length_errors, (unsigned long)m.bytes_skipped,
                   (unsigned long)m.resyncs, (unsigned long)m.truncated, (unsigned long)m.acks,
                   (unsigned long)m.naks, (unsigned long)m.bytes_in);
    buf_text(line, text);
    return 0;
}

int main(int argc, char **argv)
{
    gen_program = "lmsgen";
    gen_options_t o;
    const int parsed = parse_options(argc, argv, &o);
    if (parsed >= 0) {
        return parsed;
    }

    gen_t g;
    memset(&g, 0, sizeof g);
    generate(&g, &o);

    buf_t stats;
    memset(&stats, 0, sizeof stats);
    int rc = (expected_stats(&g, &o, &stats) == 0) ? 0 : EXIT_RUNTIME;
    if (rc == 0 && write_file(o.out_path, &g.stream) != 0) {
        rc = EXIT_RUNTIME;
    }
    if (rc == 0 && o.truth_path != NULL && write_file(o.truth_path, &g.truth) != 0) {
        rc = EXIT_RUNTIME;
    }
    if (rc == 0 && o.stats_path != NULL && write_file(o.stats_path, &stats) != 0) {
        rc = EXIT_RUNTIME;
    }
    buf_free(&g.stream);
    buf_free(&g.truth);
    buf_free(&stats);
    free(g.good);
    return rc;
}
