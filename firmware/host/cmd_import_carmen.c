/* cmd_import_carmen.c - `lmsego import-carmen LOG -o STREAM [--odometry OUT]
 * [--no-return M] [--stride K] [--offset O]`: converts the laser lines of a CARMEN log
 * (plain or gzip'd, read through zlib; FLASER/RLASER and ROBOTLASER1) into
 * an LMS 2xx B0 telegram stream, the format `lmsego stats`, `scans` and
 * `replay` read.
 *
 * Beam geometry is kept exact: 180 or 181 beams from -90 deg at 1 deg
 * become a 181-value 1-degree scan, 360 or 361 beams at 0.5 deg a
 * 361-value scan; a missing last beam (+90 deg) is written as no return.
 * Old-style lines carry no angles and follow GMapping's reader (beam k at
 * -90 + k deg for 180 beams); ROBOTLASER1 lines must start at -90 deg with
 * 1 or 0.5 deg steps, others are counted and left out.
 *
 * Ranges are written in centimetres (measuring mode 00) when every reading
 * is a whole number of centimetres (no loss), else in millimetres with the
 * 16-bit measuring mode 0F (replay then needs --mode 0F; no-return is 0
 * there). The no-return code is the largest reading of the log (CARMEN
 * loggers write the maximum range for "no return": 81.83 m in intel,
 * 50.00 m in aces), or --no-return M: readings at or above it, and any
 * reading beyond what the unit can hold, become the LMS no-return value;
 * --no-return none: no reading is one. The summary on stderr says which
 * was taken and how many readings it turned into no return. A log whose
 * every reading is its largest (one that never reaches its maximum range
 * and sees a wall at one distance) would convert to nothing but no
 * return: refused, unless --no-return says what to do. A log without a
 * laser scan (empty, another text) is refused too, and no STREAM written.
 *
 * --odometry OUT writes `i j dx dy dtheta` between consecutive scans from
 * the ODOM records: increments chained into a continuous trajectory, the
 * re-anchoring records GMapping writes right after each laser line (equal
 * to that line's pose) skipped, each scan taking the pose of the last
 * ODOM record before it (the rules of ../shared/tools/carmenlog.py).
 *
 * --stride K keeps only scans 0, K, 2K, ... (counted as the stream would
 * count them at stride 1) for a stride-K evaluation, --offset O (< K)
 * shifts them to O, O + K, ...; the odometry lines
 * are then `i i+K dx dy dtheta` in those numbers, the motion between the
 * two kept scans (the same as relpose_eval.py --stride K --write-baseline
 * odom gives for those pairs). The scans left out still take part in the
 * odometry chaining, which needs every laser line to spot re-anchoring.
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "cli_options.h"
#include "commands.h"
#include "lms_encode.h"

#define LINE_MAX_BYTES 65536u
#define MAX_BEAMS 361u
#define PI 3.14159265358979323846
#define MAX_STRIDE 100000ul

typedef struct {
    double x, y, theta;
} pose_t;

static double wrap(double a)
{
    return remainder(a, 2.0 * PI);
}

static pose_t compose(pose_t a, pose_t b)
{
    const double c = cos(a.theta);
    const double s = sin(a.theta);
    const pose_t r = {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrap(a.theta + b.theta)};
    return r;
}

static pose_t between(pose_t a, pose_t b)
{
    const double c = cos(a.theta);
    const double s = sin(a.theta);
    const double dx = b.x - a.x;
    const double dy = b.y - a.y;
    const pose_t r = {c * dx + s * dy, -s * dx + c * dy, wrap(b.theta - a.theta)};
    return r;
}

/* One laser line: its ranges (metres) and the beam step (1 or 0.5 deg). */
typedef struct {
    double range[MAX_BEAMS];
    unsigned n;
    unsigned values; /* 181 or 361 */
    pose_t pose;     /* the line's (corrected) pose */
} laser_t;

/* Splits line into whitespace-separated tokens (in place). */
static unsigned tokenize(char *line, char **tok, unsigned max)
{
    unsigned n = 0u;
    char *save = NULL;
    for (char *t = strtok_r(line, " \t\r\n", &save); t != NULL && n < max;
         t = strtok_r(NULL, " \t\r\n", &save)) {
        tok[n++] = t;
    }
    return n;
}

static int number(const char *text, double *out)
{
    char *end = NULL;
    *out = strtod(text, &end);
    return (end != text && *end == '\0' && isfinite(*out)) ? 0 : -1;
}

/* Values per scan for n beams of step inc (rad), starting at -90 deg; 0
 * for a geometry the LMS does not have. */
static unsigned lms_values_for(unsigned n, double inc)
{
    if ((n == 180u || n == 181u) && fabs(inc - PI / 180.0) < 1e-6) {
        return 181u;
    }
    if ((n == 360u || n == 361u) && fabs(inc - PI / 360.0) < 1e-6) {
        return 361u;
    }
    return 0u;
}

/* Parses a laser line; 1 = a scan, 0 = not a laser line, -1 = unsupported
 * or malformed laser line. */
static int parse_laser(char **tok, unsigned ntok, laser_t *l)
{
    unsigned first;
    unsigned n;
    double inc;
    size_t pose_at;
    if (strcmp(tok[0], "FLASER") == 0 || strcmp(tok[0], "RLASER") == 0) {
        if (ntok < 2u) {
            return -1;
        }
        n = (unsigned)strtoul(tok[1], NULL, 10);
        first = 2u;
        inc = (n == 360u || n == 361u) ? PI / 360.0 : PI / 180.0;
        pose_at = 2u + n;
    } else if (strcmp(tok[0], "ROBOTLASER1") == 0) {
        double start;
        double res;
        if (ntok < 10u || number(tok[2], &start) != 0 || number(tok[4], &res) != 0 ||
            fabs(start + PI / 2.0) > 1e-6) {
            return -1;
        }
        n = (unsigned)strtoul(tok[8], NULL, 10);
        first = 9u;
        inc = res;
        if (9u + n >= ntok) {
            return -1;
        }
        const unsigned m = (unsigned)strtoul(tok[9u + n], NULL, 10);
        pose_at = 9u + n + 1u + m;
    } else {
        return 0;
    }
    l->values = lms_values_for(n, inc);
    if (l->values == 0u || n > MAX_BEAMS || pose_at + 3u > ntok) {
        return -1;
    }
    l->n = n;
    for (unsigned k = 0u; k < n; k++) {
        if (number(tok[first + k], &l->range[k]) != 0 || l->range[k] < 0.0) {
            return -1;
        }
    }
    if (number(tok[pose_at], &l->pose.x) != 0 || number(tok[pose_at + 1u], &l->pose.y) != 0 ||
        number(tok[pose_at + 2u], &l->pose.theta) != 0) {
        return -1;
    }
    return 1;
}

/* import_options_t (cli_options.h): no_return 0 is the largest reading,
 * INFINITY none (--no-return none). */
typedef import_options_t import_args_t;

/* What pass 1 learns of the log. */
typedef struct {
    unsigned long scans;     /* laser lines that convert */
    unsigned long readings;  /* their readings */
    double largest;          /* the largest reading */
    unsigned long at_largest; /* readings equal to it */
    double smallest_not_cm;  /* the smallest reading not a whole number of cm, or +inf */
} survey_t;

/* Pass 1 over the log. Returns 0, -1 for a line longer than the buffer or
 * binary data, -2 for a read error (a corrupt or truncated gzip stream). */
static int survey(gzFile in, char *line, survey_t *sv)
{
    static char *tok[LINE_MAX_BYTES / 2u];
    static laser_t l;
    memset(sv, 0, sizeof *sv);
    sv->smallest_not_cm = INFINITY;
    while (gzgets(in, line, (int)LINE_MAX_BYTES) != NULL) {
        if (strchr(line, '\n') == NULL && !gzeof(in)) {
            return -1; /* a line longer than the buffer, or a NUL byte */
        }
        const unsigned ntok = tokenize(line, tok, LINE_MAX_BYTES / 2u);
        if (ntok == 0u || parse_laser(tok, ntok, &l) != 1) {
            continue;
        }
        sv->scans++;
        for (unsigned k = 0u; k < l.n; k++) {
            const double cm = l.range[k] * 100.0;
            sv->readings++;
            if (l.range[k] > sv->largest) {
                sv->largest = l.range[k];
                sv->at_largest = 0u;
            }
            sv->at_largest += (l.range[k] == sv->largest) ? 1u : 0u;
            if (fabs(cm - round(cm)) > 1e-6) {
                sv->smallest_not_cm = fmin(sv->smallest_not_cm, l.range[k]);
            }
        }
    }
    return gzeof(in) ? 0 : -2;
}

/* Opens the log for reading through zlib; a directory is refused (gzopen
 * takes it, and its reads fail). NULL after a message. */
static gzFile open_log(const char *path)
{
    const int fd = open(path, O_RDONLY);
    struct stat st;
    int error = 0;
    if (fd < 0 || fstat(fd, &st) != 0) {
        error = errno;
    } else if (S_ISDIR(st.st_mode)) {
        error = EISDIR;
    }
    gzFile in = (error == 0) ? gzdopen(fd, "rb") : NULL;
    if (in == NULL) {
        if (fd >= 0) {
            (void)close(fd);
        }
        cli_file_error("cannot open ", path, strerror(error != 0 ? error : ENOMEM));
    }
    return in;
}

static int import(const import_args_t *a)
{
    static char line[LINE_MAX_BYTES];
    static char *tok[LINE_MAX_BYTES / 2u];
    static laser_t l;
    static lms_scan_t scan;
    static uint8_t telegram[LMS_TELEGRAM_MAX];

    gzFile in = open_log(a->log_path);
    if (in == NULL) {
        return CLI_EXIT_RUNTIME;
    }
    static survey_t sv;
    const int surveyed = survey(in, line, &sv);
    if (surveyed != 0) {
        (void)gzclose(in);
        cli_file_error((surveyed == -1) ? "not a CARMEN text log: " : "error reading ",
                       a->log_path,
                       (surveyed == -1) ? "a line over 64 KiB, or binary data"
                                        : "corrupt or truncated");
        return CLI_EXIT_RUNTIME;
    }
    /* Kept scans: O, O + K, ... below sv.scans. */
    const unsigned long to_keep =
        (sv.scans > a->offset) ? (sv.scans - a->offset - 1u) / a->stride + 1u : 0u;
    const char *refused = NULL;
    char why[160];
    if (sv.scans == 0u) {
        refused = "no laser scan (FLASER, RLASER or ROBOTLASER1 of 180/181 or 360/361 "
                  "beams from -90 deg)";
    } else if (to_keep == 0u) {
        (void)snprintf(why, sizeof why, "--offset %lu, but the log has %lu laser scans",
                       a->offset, sv.scans);
        refused = why;
    } else if (a->no_return == 0.0 && sv.at_largest == sv.readings) {
        (void)snprintf(why, sizeof why,
                       "every reading is %.2f m, its largest, the default no-return: give "
                       "--no-return M or none",
                       sv.largest);
        refused = why;
    }
    if (refused != NULL) {
        (void)gzclose(in);
        cli_file_error("import-carmen: nothing to convert in ", a->log_path, refused);
        return CLI_EXIT_RUNTIME;
    }
    const double no_return = (a->no_return > 0.0) ? a->no_return : sv.largest;
    /* Centimetres lose nothing when every real reading (below the
     * no-return code) is a whole number of them. */
    const int whole_cm = sv.smallest_not_cm >= no_return;
    (void)gzrewind(in);

    FILE *out = fopen(a->out_path, "wb");
    FILE *odom = (a->odom_path != NULL) ? fopen(a->odom_path, "w") : NULL;
    if (out == NULL || (a->odom_path != NULL && odom == NULL)) {
        cli_file_error("cannot create ", (out == NULL) ? a->out_path : a->odom_path,
                       strerror(errno));
        if (out != NULL) {
            (void)fclose(out);
        }
        if (odom != NULL) {
            (void)fclose(odom); /* the output failed, the odometry's did not */
        }
        (void)gzclose(in);
        return CLI_EXIT_RUNTIME;
    }
    /* As recorded after `20 24`: ACK, then the A0 reply, then the stream. */
    static const uint8_t start[] = {0x06, 0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A};
    int failed = fwrite(start, 1u, sizeof start, out) != sizeof start;

    const lms_unit_t unit = whole_cm ? LMS_UNIT_CM : LMS_UNIT_MM;
    const double per_metre = whole_cm ? 100.0 : 1000.0;
    const unsigned largest_code = whole_cm ? 0x1FF6u : 0xFFFFu;
    const uint16_t no_return_code = whole_cm ? 0x1FFFu : 0u;

    unsigned long scans = 0u; /* laser scans read, kept or not */
    unsigned long kept = 0u;
    unsigned long readings = 0u;   /* of the kept scans */
    unsigned long no_returns = 0u; /* of those written as no return */
    unsigned long beyond = 0u;     /* ... below no_return, beyond the unit */
    unsigned long unsupported = 0u;
    pose_t cont = {0.0, 0.0, 0.0};
    pose_t prev_odom = {0.0, 0.0, 0.0};
    int have_odom = 0;
    int just_after_laser = 0;
    pose_t last_laser = {0.0, 0.0, 0.0};
    pose_t prev_scan_odom = {0.0, 0.0, 0.0};
    int prev_scan_has_odom = 0;
    while (!failed && gzgets(in, line, (int)LINE_MAX_BYTES) != NULL) {
        const unsigned ntok = tokenize(line, tok, LINE_MAX_BYTES / 2u);
        if (ntok == 0u) {
            continue;
        }
        if (strcmp(tok[0], "ODOM") == 0) {
            pose_t p;
            if (ntok >= 4u && number(tok[1], &p.x) == 0 && number(tok[2], &p.y) == 0 &&
                number(tok[3], &p.theta) == 0) {
                const int reanchor = just_after_laser && fabs(p.x - last_laser.x) < 1e-6 &&
                                     fabs(p.y - last_laser.y) < 1e-6 &&
                                     fabs(wrap(p.theta - last_laser.theta)) < 1e-6;
                if (have_odom && !reanchor) {
                    cont = compose(cont, between(prev_odom, p));
                }
                have_odom = 1;
                prev_odom = p;
            }
            just_after_laser = 0;
            continue;
        }
        if (strcmp(tok[0], "NEFF") == 0 || tok[0][0] == '#') {
            continue;
        }
        just_after_laser = 0;
        const int parsed = parse_laser(tok, ntok, &l);
        if (parsed == 0) {
            continue;
        }
        if (parsed < 0) {
            unsupported++;
            continue;
        }
        last_laser = l.pose;
        just_after_laser = 1;
        const unsigned long index = scans++;
        if (index < a->offset || (index - a->offset) % a->stride != 0u) {
            continue;
        }
        memset(&scan, 0, sizeof scan);
        scan.count = (uint16_t)l.values;
        scan.unit = unit;
        scan.address = 0x80u;
        scan.status = 0x10u;
        for (unsigned k = 0u; k < l.values; k++) {
            uint16_t v = no_return_code;
            if (k < l.n && l.range[k] < no_return) {
                const double units = round(l.range[k] * per_metre);
                v = (units <= (double)largest_code) ? (uint16_t)units : no_return_code;
                beyond += (units > (double)largest_code) ? 1u : 0u;
            }
            if (k < l.n) { /* a missing last beam is no reading */
                readings++;
                no_returns += (v == no_return_code) ? 1u : 0u;
            }
            scan.values[k] = v;
        }
        size_t written = 0u;
        if (lms_encode_scan(telegram, sizeof telegram, 0x80u, &scan, &written) != LMS_OK ||
            fwrite(telegram, 1u, written, out) != written) {
            failed = 1;
            break;
        }
        if (odom != NULL && have_odom && prev_scan_has_odom) {
            const pose_t d = between(prev_scan_odom, cont);
            if (fprintf(odom, "%lu %lu %.9f %.9f %.9f\n", index - a->stride, index, d.x, d.y,
                        d.theta) < 0) {
                failed = 1;
            }
        }
        prev_scan_odom = cont;
        prev_scan_has_odom = have_odom;
        kept++;
    }
    const int read_error = !gzeof(in) && !failed;
    (void)gzclose(in);
    failed |= (fclose(out) != 0);
    if (odom != NULL) {
        failed |= (fclose(odom) != 0);
    }
    if (read_error) {
        cli_file_error("error reading ", a->log_path, "corrupt or truncated");
        return CLI_EXIT_RUNTIME;
    }
    if (failed) {
        cli_file_error("error writing ", a->out_path, strerror(errno));
        return CLI_EXIT_RUNTIME;
    }
    char strided[64] = "";
    if (a->stride > 1u) {
        (void)snprintf(strided, sizeof strided, " stride=%lu read=%lu", a->stride, scans);
    }
    char beyond_text[64] = "";
    if (beyond > 0u) {
        (void)snprintf(beyond_text, sizeof beyond_text, " (%lu beyond the unit's %.3f m)", beyond,
                       (double)largest_code / per_metre);
    }
    char taken[48];
    if (isinf(no_return)) {
        (void)snprintf(taken, sizeof taken, "none");
    } else {
        (void)snprintf(taken, sizeof taken, "%.2f", no_return);
    }
    (void)fprintf(stderr,
                  "lmsego: import-carmen: scans=%lu unsupported=%lu unit=%s no_return=%s%s%s; "
                  "no_return is %s: %lu of %lu readings written as no return%s\n",
                  kept, unsupported, whole_cm ? "cm" : "mm", taken, strided,
                  whole_cm ? "" : " (replay with --mode 0F)",
                  (a->no_return == 0.0) ? "the log's largest reading (--no-return M|none sets it)"
                                        : "--no-return's",
                  no_returns, readings, beyond_text);
    return CLI_EXIT_OK;
}

static const char help[] =
    "input:\n"
    "  LOG           a CARMEN laser log, plain text or gzip'd: its FLASER, RLASER and\n"
    "                ROBOTLASER1 lines of 180/181 beams at 1 deg or 360/361 at 0.5 deg\n"
    "                from -90 deg (others are counted as unsupported), its ODOM lines\n"
    "options:\n"
    "  -o STREAM     the LMS 2xx telegram stream to write (required): one B0 scan per\n"
    "                laser line, 181 or 361 values; in cm (measuring mode 00) when\n"
    "                every reading is a whole number of cm, else in mm (mode 0F: replay\n"
    "                and scans then need --mode 0F)\n"
    "  --no-return M|none  readings at or above M metres are written as no return\n"
    "                (default: the log's largest reading, which CARMEN loggers write\n"
    "                for no return: 81.83 m in intel, 50.00 m in aces; a log that\n"
    "                never reaches its maximum range loses its farthest returns so:\n"
    "                give M); none: every reading is a return. Readings beyond the\n"
    "                unit (81.82 m in cm, 65.535 m in mm) are no return either way\n"
    "  --odometry OUT  writes the odometry between kept scans, 'i j dx dy dtheta'\n"
    "                (m, m, rad: scan j's pose in scan i's frame), for replay --prior\n"
    "  --stride K    keeps every K-th laser scan (default 1), 1..100000\n"
    "  --offset O    ... starting at scan O (default 0), below K\n"
    "\n"
    "output: STREAM (and OUT); on stderr one line: scans=N unsupported=U unit=cm|mm\n"
    "  no_return=M|none; where M came from: how many readings became no return\n"
    "exit status: 0 ok; 1 LOG cannot be read, is not a CARMEN log, holds no laser scan,\n"
    "  or would convert to nothing but no return (every reading its largest: give\n"
    "  --no-return); an output cannot be written; 2 bad command line\n";

void import_options_defaults(import_options_t *o)
{
    const import_options_t d = {NULL, NULL, NULL, 0.0, 1u, 0u};
    *o = d;
}

/* The options of import-carmen (cli_options.h). */
int import_carmen_parse_options(const cli_command_t *self, int argc, char **argv,
                                import_options_t *o)
{
    import_options_t a = *o;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (cli_is_help(arg)) {
            cli_print_command_usage(self, help);
            return cli_finish_stdout() ? CLI_PARSED_HELP : CLI_EXIT_RUNTIME;
        }
        if (strcmp(arg, "-o") == 0 || strcmp(arg, "--odometry") == 0) {
            if (value == NULL) {
                return cli_usage_error(self, "missing file after", arg, NULL);
            }
            if (arg[1] == 'o') {
                a.out_path = value;
            } else {
                a.odom_path = value;
            }
            i++;
        } else if (strcmp(arg, "--no-return") == 0) {
            if (value != NULL && strcmp(value, "none") == 0) {
                a.no_return = INFINITY;
            } else if (value == NULL || number(value, &a.no_return) != 0 || a.no_return <= 0.0) {
                return cli_usage_error(self, "invalid --no-return", value, "metres, > 0, or none");
            }
            i++;
        } else if (strcmp(arg, "--stride") == 0) {
            if (cli_parse_whole(value, 1u, MAX_STRIDE, &a.stride) != 0) {
                return cli_usage_error(self, "invalid --stride", value, "a whole number, 1..100000");
            }
            i++;
        } else if (strcmp(arg, "--offset") == 0) {
            if (cli_parse_whole(value, 0u, MAX_STRIDE - 1u, &a.offset) != 0) {
                return cli_usage_error(self, "invalid --offset", value, "a whole number, 0..99999");
            }
            i++;
        } else {
            const int rc = cli_take_file(self, arg, &a.log_path);
            if (rc != CLI_EXIT_OK) {
                return rc;
            }
        }
    }
    if (a.offset >= a.stride) {
        return cli_usage_error(self, "--offset must be below --stride", NULL, NULL);
    }
    if (a.log_path == NULL) {
        return cli_usage_error(self, "missing LOG", NULL, NULL);
    }
    if (a.out_path == NULL) {
        return cli_usage_error(self, "missing -o STREAM", NULL, NULL);
    }
    *o = a;
    return CLI_PARSED;
}

int cmd_import_carmen(const cli_command_t *self, int argc, char **argv)
{
    import_options_t a;
    import_options_defaults(&a);
    const int rc = import_carmen_parse_options(self, argc, argv, &a);
    if (rc == CLI_PARSED_HELP) {
        return CLI_EXIT_OK;
    }
    if (rc != CLI_PARSED) {
        return rc;
    }
    /* The parser leaves neither path NULL; said again for gcc's analyzer,
     * which cannot see that cli_usage_error never returns CLI_PARSED. */
    return (a.log_path != NULL && a.out_path != NULL) ? import(&a) : CLI_EXIT_USAGE;
}
