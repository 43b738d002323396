/* cmd_replay.c - `lmsego replay FILE [--period S] [--mount X,Y,THETA_DEG]
 * [--mode HEX] [--budget none|default|U] [--icp] [--hist AH|LAH|HAH|HTAH] [--prior FILE] [--pairs OUT]
 * [--tum OUT] [--frames OUT] [--scan-step K] [--scan-offset O] [--times arrival|index]
 * [--baud B] [--sweep lms|instant] [--objects OUT] [--moving]`:
 * runs the firmware loop (firmware/ego_loop.h) over a
 * recorded telegram stream, through a host HAL that reads the file, and
 * prints its CSV on stdout. A summary line goes to stderr at the end:
 *
 *   lmsego: replay: scans=N lines=L predicted=P restarts=R decode_errors=D
 *
 * and a line more when the input ends inside a telegram (left out; exit
 * 0: a recording stopped by hand ends so), when it ends during a search,
 * or when time_s wrapped. An input without a single scan gets one line
 * saying so instead, exit 1 (stream_frames_no_scan). --period takes 0.001
 * .. 10 s (PERIOD_MIN_S, PERIOD_MAX_S below say why).
 *
 * Scan times: a raw stream's scans are one period apart from 0 (scan *
 * period; --period). A recording with arrival times (`lmsego record`,
 * `run --record`) is timed by them through the live core's tracker
 * (ego_loop.h, "Scan times from arrival stamps": the mean beam's time on
 * the recording's clock, the counted interval apart), so `lmsego run`'s
 * CSV without its latency column is the replay of its recording, byte for
 * byte, when the run had no restart; --baud B (default 500000) is the
 * line's rate, which the wire times need; --times index times it as a raw
 * stream.
 *
 * --sweep: when a scan's values were measured. lms (the default): as the
 * LMS measures them, along its mirror's sweep, 0.5-deg scans interlacing
 * two turns 13.3 ms apart (firmware/ego_lms.h); the estimator de-skews
 * them with the last motion. instant: all at once, a simulator's stream
 * (lmsworld and lmsgen cast every value at once unless told otherwise).
 *
 * --budget sets the estimator's work budget (ego.h): `default` (the
 * default: the live core's, 35.62 M work units, about Cortex-M3
 * instructions, estimator/ego_work.h, per second of scan interval, at
 * least 550 000 a scan), U units per second, or `none` (unbounded: the
 * offline mode for analysis, every scan answered at once). Within a
 * budget a search may span several scans (their lines flagged recovering,
 * 64); a recording that ends during one says so on stderr.
 * --prior FILE gives a motion prior per scan (lines `i j dx dy dtheta`, as
 * `import-carmen --odometry` writes them; ego.h says how it is used).
 * --pairs OUT also writes `i j dx dy dtheta` per line's motion (scan
 * numbers count decoded scans; the format relpose_eval.py reads): j - 1 to
 * j for a line of scan j; a restart (flag 1) and a recovering line (64)
 * claim no motion and give no line; a recovered line (128) gives the
 * motion from the last answered scan to the scan its search started from,
 * and the line after it the motion from there (a pair over several
 * scans). --tum OUT
 * writes the integrated trajectory `time x y z qx qy qz qw`, starting at
 * the origin; across a restart it holds the last pose. --frames OUT runs
 * the loop in its frame mode (ego_frame.h) into OUT and prints the same
 * CSV from the observer with ego_format_line; `lmsego frames OUT` gives it
 * back.
 *
 * --scan-step K and --scan-offset O are for a stream made with
 * `import-carmen --stride K --offset O`: stream scan s is log scan
 * O + s*K, so --pairs writes `O+K*(s-1) O+K*s ...` and a --prior line
 * `i j ...` with i = j - K is the prior of stream scan (j - O) / K.
 * The CSV keeps counting stream scans.
 *
 * --objects OUT writes the moving objects of every scan: the firmware
 * loop's own (estimator/ego_moving.h says how they are found; fixed
 * point, the target's bits): a header line, then one line per object and
 * scan, `scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points`, in the
 * vehicle frame of that scan (x forward, y left), the velocity over
 * ground ("nan" until the object's track spans 0.1 s), two decimals (the
 * record's centimetres).
 *
 * --moving: the same objects in the CSV itself, as the firmware writes
 * them: each CSV line is followed by its scan's
 * "o,scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points" lines
 * (ego_loop.h). Not with --frames.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_options.h"
#include "commands.h"
#include "ego_loop.h"
#include "live_common.h"
#include "stream_file.h"
#include "stream_frames.h"

typedef struct {
    stream_file_t file;
    /* The first read, taken before the loop starts to learn the format,
     * handed out first. */
    uint8_t first[STREAM_FILE_CHUNK];
    size_t first_len;
    size_t first_pos;
    int failed; /* a read error happened */
    int write_failed;
    FILE *pairs;  /* --pairs, or NULL */
    ego_pose_t *prior;     /* --prior: prior[j] for scan j, or NULL */
    uint8_t *has_prior;
    uint32_t prior_count;
    unsigned long scan_step;   /* --scan-step: log scans per stream scan */
    unsigned long scan_offset; /* --scan-offset: log number of stream scan 0 */
    FILE *tum;    /* --tum, or NULL */
    FILE *frames; /* --frames: the loop's output goes here, or NULL */
    int header_written; /* --frames: the CSV header is out */
    double x, y, theta; /* integrated pose for --tum */
    unsigned long recovering; /* lines flagged recovering since the last answer */
    uint32_t last_time_us;    /* of the last line, to see the 32-bit clock wrap */
    int wrapped;
    /* --pairs: the scan the next motion starts from (valid once have_ref),
     * and the first scan of a run of recovering lines (the scan a search
     * started from: a recovered line's motion ends there). */
    int have_ref;
    uint32_t ref;
    uint32_t target;
    FILE *objects;            /* --objects, or NULL */
} replay_io_t;

#if EGO_LOOP_OBJECTS
/* --objects: the loop's moving objects of scan (ego_moving.h), metres
 * and m/s from their centimetres. */
static void observe_objects(void *ctx, uint32_t scan, const ego_moving_object_t *objects, uint8_t n)
{
    replay_io_t *io = ctx;
    for (uint8_t i = 0u; i < n; i++) {
        const ego_moving_object_t *o = &objects[i];
        char v[64];
        if (o->vx_cms == EGO_MOVING_UNKNOWN) {
            (void)snprintf(v, sizeof v, "nan,nan");
        } else {
            (void)snprintf(v, sizeof v, "%.2f,%.2f", o->vx_cms / 100.0, o->vy_cms / 100.0);
        }
        if (fprintf(io->objects, "%lu,%u,%.2f,%.2f,%.2f,%.2f,%s,%u\n", (unsigned long)scan,
                    (unsigned)o->id, o->cx_cm / 100.0, o->cy_cm / 100.0, o->length_cm / 100.0,
                    o->width_cm / 100.0, v, (unsigned)o->points) < 0) {
            io->write_failed = 1;
        }
    }
}
#endif

/* Output of one scan: the extra files (host-only, doubles are fine). */
static void observe(void *ctx, uint32_t scan, uint32_t time_us, const ego_output_t *out)
{
    replay_io_t *io = ctx;
    io->wrapped |= time_us < io->last_time_us;
    io->last_time_us = time_us;
    io->recovering = ((out->flags & EGO_FLAG_RECOVERING) != 0u) ? io->recovering + 1ul : 0ul;
    const double dx = (double)out->pose.x / 65536.0;
    const double dy = (double)out->pose.y / 65536.0;
    const double dt = (double)fx_bam32_diff(out->pose.theta, 0u) * (3.14159265358979323846 / 2147483648.0);
    const int restart = (out->flags & EGO_FLAG_FIRST) != 0u;
    /* The translation exactly as the CSV prints it: micrometres rounded
     * half away from zero (x * 10^6 / 2^16 is exact in a double). */
    const long long ux = llround((double)out->pose.x * 1e6 / 65536.0);
    const long long uy = llround((double)out->pose.y * 1e6 / 65536.0);
    /* Numbered as in the log the stream came from (scan >= 1 here). */
    const unsigned long step = io->scan_step;
    const unsigned long first = io->scan_offset;
    if (io->frames != NULL) { /* the loop writes frames: the CSV comes from here */
        char line[EGO_LOOP_LINE_MAX];
        const size_t n = ego_format_line(line, sizeof line, scan, time_us, out);
        if ((!io->header_written && fputs(EGO_LOOP_CSV_HEADER, stdout) == EOF) ||
            fwrite(line, 1u, n, stdout) != n) {
            io->write_failed = 1;
        }
        io->header_written = 1;
    }
    /* The pair a line's motion spans (as pairs_error.py reads the CSV): a
     * restart starts over; a recovering line claims nothing; a recovered
     * one spans from the last answered scan to the scan its search started
     * from; any other line to its own scan. */
    const int recovering = (out->flags & EGO_FLAG_RECOVERING) != 0u;
    if (restart) {
        io->have_ref = 1;
        io->ref = scan;
    } else {
        if (!io->have_ref) {
            io->have_ref = 1;
            io->ref = scan - 1u;
        }
        if (recovering && io->recovering == 1ul) {
            io->target = scan; /* the first of the run */
        }
    }
    if (!restart && !recovering) {
        const uint32_t end =
            ((out->flags & EGO_FLAG_RECOVERED) != 0u && io->target != 0u) ? io->target : scan;
        if (io->pairs != NULL && end > io->ref &&
            fprintf(io->pairs, "%lu %lu %s%lld.%06lld %s%lld.%06lld %.9f\n",
                    first + step * (unsigned long)io->ref, first + step * (unsigned long)end,
                    (ux < 0) ? "-" : "", llabs(ux) / 1000000, llabs(ux) % 1000000,
                    (uy < 0) ? "-" : "", llabs(uy) / 1000000, llabs(uy) % 1000000, dt) < 0) {
            io->write_failed = 1;
        }
        io->ref = end;
        io->target = 0u;
    }
    if (io->tum != NULL) {
        if (!restart) {
            const double c = cos(io->theta);
            const double s = sin(io->theta);
            io->x += c * dx - s * dy;
            io->y += s * dx + c * dy;
            io->theta = remainder(io->theta + dt, 2.0 * 3.14159265358979323846);
        }
        if (fprintf(io->tum, "%.6f %.6f %.6f 0 0 0 %.9f %.9f\n", (double)time_us * 1e-6, io->x,
                    io->y, sin(io->theta / 2.0), cos(io->theta / 2.0)) < 0) {
            io->write_failed = 1;
        }
    }
}

static bool give_prior(void *ctx, uint32_t scan, ego_pose_t *prior)
{
    const replay_io_t *io = ctx;
    if (io->prior == NULL || scan >= io->prior_count || !io->has_prior[scan]) {
        return false;
    }
    *prior = io->prior[scan];
    return true;
}

/* Reads --prior FILE: lines `i j dx dy dtheta` (metres, radians) in log
 * scan numbers; j = i + K (K = --scan-step) is used as the prior of stream
 * scan j / K; '#' lines and other pairs are ignored. Returns 0, or -1
 * after a message. */
static int load_priors(const char *path, replay_io_t *io)
{
    enum { MAX_PRIOR_SCANS = 1000000 };
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        cli_file_error("cannot open ", path, strerror(errno));
        return -1;
    }
    char line[512];
    unsigned long line_no = 0u;
    int rc = 0;
    errno = 0;
    while (rc == 0 && fgets(line, sizeof line, f) != NULL) {
        line_no++;
        if (line[0] == '#' || line[0] == '\n') {
            continue;
        }
        char *end = NULL;
        const unsigned long i = strtoul(line, &end, 10);
        char *p = end;
        const unsigned long j = strtoul(p, &end, 10);
        double v[3];
        int ok = end != p;
        for (int k = 0; k < 3 && ok; k++) {
            p = end;
            v[k] = strtod(p, &end);
            ok = end != p && isfinite(v[k]) && fabs(v[k]) < 1000.0;
        }
        if (!ok || j >= MAX_PRIOR_SCANS) {
            char where[64];
            (void)snprintf(where, sizeof where, "line %lu is not 'i j dx dy dtheta'", line_no);
            cli_file_error("bad prior in ", path, where);
            rc = -1;
            break;
        }
        const unsigned long step = io->scan_step;
        const unsigned long first = io->scan_offset;
        if (j < first + step || i != j - step || (j - first) % step != 0u) {
            continue;
        }
        const unsigned long s = (j - first) / step;
        if (s >= io->prior_count) {
            const uint32_t count = (uint32_t)(s + 1u) * 2u;
            ego_pose_t *grown = realloc(io->prior, count * sizeof *grown);
            uint8_t *flags = realloc(io->has_prior, count);
            if (grown != NULL) {
                io->prior = grown;
            }
            if (flags != NULL) {
                io->has_prior = flags;
            }
            if (grown == NULL || flags == NULL) {
                cli_error("out of memory reading the priors");
                rc = -1;
                break;
            }
            memset(&io->has_prior[io->prior_count], 0, count - io->prior_count);
            io->prior_count = count;
        }
        io->prior[s].x = (fx_q16_16_t)lround(v[0] * 65536.0);
        io->prior[s].y = (fx_q16_16_t)lround(v[1] * 65536.0);
        double turns = v[2] / (2.0 * 3.14159265358979323846);
        turns -= floor(turns);
        io->prior[s].theta = (fx_bam32_t)(uint64_t)llround(turns * 4294967296.0);
        io->has_prior[s] = 1u;
    }
    if (rc == 0 && ferror(f)) { /* a directory opens, and fails here with EISDIR */
        cli_file_error("error reading --prior ", path, strerror(errno != 0 ? errno : EIO));
        rc = -1;
    } else if (rc == 0 && io->prior_count == 0u) {
        char why[96];
        (void)snprintf(why, sizeof why, "no line 'i j dx dy dtheta' with j = i + %lu (--scan-step)",
                       io->scan_step);
        cli_file_error("no prior in ", path, why);
        rc = -1;
    }
    (void)fclose(f);
    return rc;
}

/* Opens an output file for --pairs / --tum; NULL after a message. */
static FILE *open_output(const char *path)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        cli_file_error("cannot create ", path, strerror(errno));
    }
    return f;
}

static int close_output(FILE *f, const char *path)
{
    if (f != NULL && fclose(f) != 0) {
        cli_file_error("error writing ", path, strerror(errno));
        return -1;
    }
    return 0;
}

static int32_t hal_read(void *ctx, uint8_t *buf, size_t cap)
{
    replay_io_t *io = ctx;
    if (io->failed) {
        return -1; /* the first read failed: reported at the end */
    }
    if (io->first_pos < io->first_len) {
        size_t n = io->first_len - io->first_pos;
        n = n < cap ? n : cap;
        memcpy(buf, &io->first[io->first_pos], n);
        io->first_pos += n;
        return (int32_t)n;
    }
    size_t got = 0u;
    const stream_read_t r = stream_file_read(&io->file, buf, cap, &got);
    if (r == STREAM_READ_ERROR) {
        io->failed = 1;
        return -1;
    }
    return (r == STREAM_READ_END) ? -1 : (int32_t)got;
}

static void hal_write(void *ctx, const uint8_t *buf, size_t len)
{
    replay_io_t *io = ctx;
    if (fwrite(buf, 1u, len, io->frames != NULL ? io->frames : stdout) != len) {
        io->write_failed = 1;
    }
}

/* The arrival time of the block the last bytes read came from (a raw
 * stream: 0, unused: its scans are timed by index and period). The same
 * 32-bit clock `lmsego run` stamps its bytes with. */
static uint32_t hal_now_us(void *ctx)
{
    const replay_io_t *io = ctx;
    return (uint32_t)io->file.time_us;
}

/* --period's range. From 1 ms: a microsecond clock keeps it to 0.1 %, and
 * the velocities (Q16.16 m/s, at most 32767 m/s) hold any motion of up to
 * 32 m a scan (below, 6e-7 s gave 32768 m/s). Up to 10 s: the estimator
 * takes any interval as one (ego.h: "A long interval is not a gap"; over
 * 0.2 s it searches every scan instead of tracking, over 1 s it does not
 * judge speed changes), and the times stay on its 32-bit microsecond
 * clock for 429 scans before time_s wraps (reported). */
#define PERIOD_MIN_S 0.001
#define PERIOD_MAX_S 10.0

static int parse_hist(const char *text, ego_hist_kind_t *kind)
{
    static const struct {
        const char *name;
        ego_hist_kind_t kind;
    } kinds[] = {{"AH", EGO_HIST_AH}, {"LAH", EGO_HIST_LAH}, {"HAH", EGO_HIST_HAH}, {"HTAH", EGO_HIST_HTAH}};
    for (size_t k = 0u; k < sizeof kinds / sizeof kinds[0]; k++) {
        if (strcmp(text, kinds[k].name) == 0) {
            *kind = kinds[k].kind;
            return 0;
        }
    }
    return -1;
}

static const char help[] =
    CLI_HELP_STREAM_INPUT
    "options:\n"
    "  --period S    seconds between scans of a raw stream (and with --times index),\n"
    "                0.001 .. 10; default: the LMS's own for the first scan's values\n"
    "                (1/75 s for 181, 1/37.5 s for 361, 1/18.75 s for 401). Any interval\n"
    "                is estimated, none is a gap: over 0.2 s every scan is searched,\n"
    "                not tracked (keyframe logs: their mean spacing, e.g. 2.92), over 1 s\n"
    "                speed changes are not judged (no flag 2048)\n"
    "  --times arrival|index  a recording's scan times: from its arrival times\n"
    "                (default) or scan * period\n"
    "  --baud B      the recorded line's rate, for its wire times: 9600, 19200, 38400 or\n"
    "                500000 (default)\n"
    "  --sweep lms|instant  when a scan's values were measured: along the LMS mirror's\n"
    "                sweep, de-skewed with the last motion (lms, default), or all at\n"
    "                once (instant: a simulator's stream)\n"
    "  --mode HEX    measuring mode of the values: 00..06 or 0F (default 00; 0F for\n"
    "                import-carmen's millimetre streams)\n"
    "  --mount X,Y,DEG  the scanner's pose on the vehicle: m, m, deg counter-clockwise\n"
    "                (default 0,0,0); the output is the vehicle's motion\n"
    "  --budget none|default|U  the estimator's work per second of scan interval:\n"
    "                default 35.62e6 units (about Cortex-M3 instructions, at least\n"
    "                550 000 a scan: the live core's), U units, 1e5 .. 4e9, or none\n"
    "                (unbounded, offline: every scan answered at once)\n"
    "  --icp         plain ICP instead of the weighted registration\n"
    "  --hist KIND   the search's histogram: AH, LAH, HAH or HTAH (default)\n"
    "  --prior FILE  a motion prior (odometry): lines 'i j dx dy dtheta' (m, m, rad; the\n"
    "                pose of scan j in the frame of scan i, j = i + K), as\n"
    "                import-carmen --odometry writes them; a file without one such\n"
    "                line is an error\n"
    "  --pairs OUT   writes 'i j dx dy dtheta' (m, m, rad) per line's motion\n"
    "  --tum OUT     writes the trajectory 'time x y z qx qy qz qw' (s, m, quaternion)\n"
    "  --frames OUT  writes the binary frame per scan too (`lmsego frames OUT`)\n"
    "  --objects OUT writes the moving objects of each scan with a measured motion:\n"
    "                a header, then per object and scan\n"
    "                'scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points': the\n"
    "                centre and the sides of the box around its points along the\n"
    "                cluster's chord and across it (m, the scan's vehicle frame: x\n"
    "                forward, y left), its velocity over ground in that frame (m/s;\n"
    "                nan until its track spans 0.1 s), its points; id is stable\n"
    "                while it is tracked. Found against scans 0.2-0.3 s earlier by\n"
    "                the firmware loop itself (estimator/ego_moving.h, fixed point);\n"
    "                a line without a measured motion starts over\n"
    "  --moving      the same objects in the CSV itself, as the firmware writes them:\n"
    "                after each line, one line per object of its scan,\n"
    "                'o,scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points'; not\n"
    "                with --frames\n"
    "  --scan-step K, --scan-offset O  stream scan s is log scan O + s K (import-carmen\n"
    "                --stride K --offset O): --prior and --pairs count log scans\n"
    "                (default 1 and 0)\n";

static const char help_tail[] =
    "\nstderr: lmsego: replay: scans=N lines=L predicted=P restarts=R decode_errors=D;\n"
    "  a line more when the input ends inside a telegram (left out; a recording\n"
    "  stopped by hand does: exit 0), when it ends during a search (its last lines claim\n"
    "  no motion), or when time_s wrapped (after 4294.967296 s)\n"
    CLI_HELP_EXIT_STATUS;

void replay_options_defaults(replay_options_t *o)
{
    memset(o, 0, sizeof *o);
    ego_loop_defaults(&o->config);
    ego_budget_defaults(&o->config.ego); /* as live: --budget none for the offline mode */
    o->scan_step = 1u;
    o->scan_offset = 0u;
    o->baud = LMS_BAUD_500000;
}

/* The options of replay (cli_options.h). */
int replay_parse_options(const cli_command_t *self, int argc, char **argv, replay_options_t *o)
{
    ego_loop_config_t *config = &o->config;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (cli_is_help(arg)) {
            cli_print_command_usage(self, help);
            cli_print_csv_columns(
                "the scan's time: a raw stream's scan * period (from 0); a\n"
                "                recording's, the mean of its beams' times since the\n"
                "                recording's clock started, from the arrival times",
                false);
            (void)fputs(help_tail, stdout);
            return cli_finish_stdout() ? CLI_PARSED_HELP : CLI_EXIT_RUNTIME;
        }
        if (strcmp(arg, "--times") == 0) {
            if (value != NULL && strcmp(value, "index") == 0) {
                o->times_index = 1;
                o->times_arrival = 0;
            } else if (value != NULL && strcmp(value, "arrival") == 0) {
                o->times_arrival = 1;
                o->times_index = 0;
            } else {
                return cli_usage_error(self, "invalid --times", value, "arrival or index");
            }
            i++;
        } else if (strcmp(arg, "--sweep") == 0) {
            if (value != NULL && strcmp(value, "lms") == 0) {
                config->lms.timing = (uint8_t)EGO_LMS_TIMING_MIRROR;
            } else if (value != NULL && strcmp(value, "instant") == 0) {
                config->lms.timing = (uint8_t)EGO_LMS_TIMING_INSTANT;
            } else {
                return cli_usage_error(self, "invalid --sweep", value, "lms or instant");
            }
            i++;
        } else if (strcmp(arg, "--baud") == 0) {
            if (live_parse_baud(value, &o->baud) != 0) {
                return cli_usage_error(self, "invalid --baud", value,
                                       "9600, 19200, 38400 or 500000");
            }
            i++;
        } else if (strcmp(arg, "--period") == 0) {
            double s;
            if (value == NULL || cli_parse_double(value, &s) != 0 || s < PERIOD_MIN_S ||
                s > PERIOD_MAX_S) {
                return cli_usage_error(self, "invalid --period", value, "seconds, 0.001 .. 10");
            }
            config->period_us = (uint32_t)lround(s * 1e6);
            i++;
        } else if (strcmp(arg, "--mount") == 0) {
            if (value == NULL || cli_parse_mount(value, &config->lms) != 0) {
                return cli_usage_error(self, "invalid --mount", value, "X,Y,THETA_DEG in m and deg");
            }
            i++;
        } else if (strcmp(arg, "--prior") == 0) {
            if (value == NULL) {
                return cli_usage_error(self, "missing file after", arg, NULL);
            }
            o->prior_path = value;
            i++;
        } else if (strcmp(arg, "--moving") == 0) {
#if EGO_LOOP_OBJECTS
            config->objects = true;
#else
            return cli_usage_error(self, "this lmsego was built without", arg,
                                   "LMSEGO_LOOP_OBJECTS=ON");
#endif
        } else if (strcmp(arg, "--objects") == 0) {
            if (value == NULL) {
                return cli_usage_error(self, "missing file after", arg, NULL);
            }
#if !EGO_LOOP_OBJECTS
            return cli_usage_error(self, "this lmsego was built without", arg,
                                   "LMSEGO_LOOP_OBJECTS=ON");
#endif
            o->objects_path = value;
            i++;
        } else if (strcmp(arg, "--pairs") == 0 || strcmp(arg, "--tum") == 0 ||
                   strcmp(arg, "--frames") == 0) {
            if (value == NULL) {
                return cli_usage_error(self, "missing file after", arg, NULL);
            }
            if (arg[2] == 'p') {
                o->pairs_path = value;
            } else if (arg[2] == 't') {
                o->tum_path = value;
            } else {
                o->frames_path = value;
            }
            i++;
        } else if (strcmp(arg, "--scan-step") == 0) {
            if (cli_parse_whole(value, 1u, 100000u, &o->scan_step) != 0) {
                return cli_usage_error(self, "invalid --scan-step", value,
                                       "a whole number, 1..100000");
            }
            i++;
        } else if (strcmp(arg, "--scan-offset") == 0) {
            if (cli_parse_whole(value, 0u, 100000u, &o->scan_offset) != 0) {
                return cli_usage_error(self, "invalid --scan-offset", value,
                                       "a whole number, 0..100000");
            }
            i++;
        } else if (strcmp(arg, "--budget") == 0) {
            double units = 0.0;
            if (value != NULL && strcmp(value, "none") == 0) {
                config->ego.work_per_s = 0u;
            } else if (value != NULL && strcmp(value, "default") == 0) {
                ego_budget_defaults(&config->ego);
            } else if (value == NULL || cli_parse_double(value, &units) != 0 || units < 1e5 ||
                       units > 4e9) {
                return cli_usage_error(self, "invalid --budget", value,
                                       "none, default, or work units per second, 1e5 .. 4e9");
            } else {
                ego_budget_defaults(&config->ego);
                config->ego.work_per_s = (uint32_t)lround(units);
            }
            i++;
        } else if (strcmp(arg, "--icp") == 0) {
            config->ego.track.weighted = false; /* plain ICP, for comparison */
        } else if (strcmp(arg, "--hist") == 0) {
            if (value == NULL || parse_hist(value, &config->ego.hist.kind) != 0) {
                return cli_usage_error(self, "invalid --hist", value, "AH, LAH, HAH or HTAH");
            }
            i++;
        } else if (strcmp(arg, "--mode") == 0) {
            if (value == NULL || cli_parse_meas_mode(value, &config->lms.meas_mode) != 0) {
                return cli_usage_error(self, "invalid --mode", value, "expected 00..06 or 0F");
            }
            i++;
        } else {
            const int rc = cli_take_file(self, arg, &o->path);
            if (rc != CLI_EXIT_OK) {
                return rc;
            }
        }
    }
    if (o->path == NULL) {
        return cli_usage_error(self, "missing FILE", NULL, NULL);
    }
#if EGO_LOOP_OBJECTS
    if (config->objects && o->frames_path != NULL) {
        return cli_usage_error(self, "--moving goes into the CSV, not with", "--frames", NULL);
    }
#endif
    return CLI_PARSED;
}

int cmd_replay(const cli_command_t *self, int argc, char **argv)
{
    static replay_options_t o;
    static ego_loop_t loop;
    replay_options_defaults(&o);
    const int rc = replay_parse_options(self, argc, argv, &o);
    if (rc == CLI_PARSED_HELP) {
        return CLI_EXIT_OK;
    }
    if (rc != CLI_PARSED) {
        return rc;
    }
    ego_loop_config_t config = o.config;
    const char *path = o.path;
    const char *pairs_path = o.pairs_path;
    const char *prior_path = o.prior_path;
    const char *tum_path = o.tum_path;
    const char *frames_path = o.frames_path;
    const char *objects_path = o.objects_path;
    const unsigned long scan_step = o.scan_step;
    const unsigned long scan_offset = o.scan_offset;
    const int times_index = o.times_index;
    const int times_arrival = o.times_arrival;
    const lms_baud_t baud = o.baud;

    replay_io_t io;
    memset(&io, 0, sizeof io);
    io.scan_step = scan_step;
    io.scan_offset = scan_offset;
    if (prior_path != NULL && load_priors(prior_path, &io) != 0) {
        free(io.prior);
        free(io.has_prior);
        return CLI_EXIT_RUNTIME;
    }
    const char *shown = (strcmp(path, "-") == 0) ? "<stdin>" : path;
    const int open_error = stream_file_open(&io.file, path);
    if (open_error != 0) {
        cli_file_error("cannot open ", shown, strerror(open_error));
        return CLI_EXIT_RUNTIME;
    }
    if ((pairs_path != NULL && (io.pairs = open_output(pairs_path)) == NULL) ||
        (tum_path != NULL && (io.tum = open_output(tum_path)) == NULL) ||
        (frames_path != NULL && (io.frames = open_output(frames_path)) == NULL) ||
        (objects_path != NULL && (io.objects = open_output(objects_path)) == NULL)) {
        (void)close_output(io.pairs, pairs_path);
        (void)close_output(io.tum, tum_path);
        (void)close_output(io.frames, frames_path);
        stream_file_close(&io.file);
        free(io.prior);
        free(io.has_prior);
        return CLI_EXIT_RUNTIME;
    }
    /* The first read tells a recording from a raw stream. */
    if (stream_file_read(&io.file, io.first, sizeof io.first, &io.first_len) == STREAM_READ_ERROR) {
        io.failed = 1;
        io.first_len = 0u;
    }
    config.use_clock = io.file.is_recording && !times_index && !io.failed;
    config.line_baud = (uint8_t)baud;
    if (times_arrival && !io.file.is_recording && !io.failed) {
        (void)close_output(io.pairs, pairs_path);
        (void)close_output(io.tum, tum_path);
        (void)close_output(io.frames, frames_path);
        (void)close_output(io.objects, objects_path);
        stream_file_close(&io.file);
        free(io.prior);
        free(io.has_prior);
        return cli_usage_error(self, "--times arrival needs a recording with arrival times",
                               shown, "a raw stream has none");
    }
#if EGO_LOOP_OBJECTS
    if (io.objects != NULL) {
        config.objects_observer = observe_objects;
        config.objects_ctx = &io;
        if (fputs(EGO_LOOP_OBJECTS_COLUMNS "\n", io.objects) == EOF) {
            io.write_failed = 1;
        }
    }
#endif
    if (io.tum != NULL) { /* the first scan, at the origin */
        (void)fprintf(io.tum, "%.6f 0.000000 0.000000 0 0 0 0.000000000 1.000000000\n", 0.0);
    }
    config.observer = observe;
    config.observer_ctx = &io;
    config.prior = give_prior;
    config.prior_ctx = &io;
    config.frames = io.frames != NULL;
    const ego_hal_t hal = {hal_read, hal_write, hal_now_us, &io};
    ego_loop_init(&loop, &config);
    while (ego_loop_step(&loop, &hal) != EGO_LOOP_END) {
    }
    stream_file_close(&io.file);
    free(io.prior);
    free(io.has_prior);
    const int closed = close_output(io.pairs, pairs_path) | close_output(io.tum, tum_path) |
                       close_output(io.frames, frames_path) |
                       close_output(io.objects, objects_path);
    if (io.failed) {
        stream_frames_read_error(&io.file, shown);
        return CLI_EXIT_RUNTIME;
    }
    const ego_loop_stats_t *st = ego_loop_stats(&loop);
    const lms_framer_stats_t *framed = lms_framer_stats(&loop.framer);
    if (st->scans == 0u) {
        stream_frames_no_scan(self->name, shown, framed, st->decode_errors);
        return CLI_EXIT_RUNTIME;
    }
    /* One scan gives no line (a motion needs two); the CSV is still a table
     * with its header, as for any other stream. */
    if (st->lines == 0u &&
        fputs(config.latency ? EGO_LOOP_CSV_HEADER_LATENCY : EGO_LOOP_CSV_HEADER, stdout) == EOF) {
        io.write_failed = 1;
    }
    (void)fprintf(stderr,
                  "lmsego: replay: scans=%lu lines=%lu predicted=%lu restarts=%lu "
                  "decode_errors=%lu\n",
                  (unsigned long)st->scans, (unsigned long)st->lines,
                  (unsigned long)st->predicted, (unsigned long)st->restarts,
                  (unsigned long)st->decode_errors);
    if (io.recovering > 0ul) {
        /* Live, the next scans' budgets would finish the search. */
        (void)fprintf(stderr,
                      "lmsego: replay: the recording ended during a search: its last %lu line(s) "
                      "claim no motion (--budget none answers every scan)\n",
                      io.recovering);
    }
    if (framed->truncated > 0u) {
        /* A recording stopped by hand usually ends so: not an error. */
        cli_file_error("replay: ", shown,
                       "ends inside a telegram, which is left out (stats: truncated)");
    }
    if (io.wrapped) {
        cli_error("replay: time_s went back to 0 after 4294.967296 s (a 32-bit microsecond "
                  "clock); the motions are not affected");
    }
    if (io.write_failed || closed != 0) {
        cli_error("write error");
        return CLI_EXIT_RUNTIME;
    }
    return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
}
