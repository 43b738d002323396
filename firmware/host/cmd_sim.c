/* cmd_sim.c - `lmsego sim` and `lmsego play`: a simulated LMS 2xx on a
 * pseudo-terminal (or, for play, a real serial port), host-only.
 *
 *   lmsego sim [--baud B] [--source STREAM] [--faults SPEC] [--rate X]
 *              [--link PATH] [--address A] [--units cm|mm]
 *              [--power-delay MS] [--scans N]
 *   lmsego play FILE (--pty [--link PATH] | --port DEV) [--rate X] [--loop]
 *
 * Both run the portable scanner model (driver/sim/lms_sim.h) on the
 * scanner's end of a line and print the device path a driver should open
 * as the first line of stdout (flushed at once). The scanner starts at
 * --baud (its power-on rate; 9600 by default, as from the factory), sends
 * its power-on telegram after --power-delay ms (default 100), answers the
 * bring-up and streams:
 * - sim: scans from STREAM (its B0 telegrams, looped) or, without
 *   --source, from a built-in synthetic scene (a 6 m x 4 m room, the
 *   scanner driving an ellipse in it), in the variant and units the
 *   driver set. --scans N ends the simulator after N streamed scans.
 * - play: the B0 telegrams of FILE (a raw stream or a recording of
 *   `lmsego record`) once, with the gaps between them as the scanner sent
 *   them (play_timing.h: a recorder's late reads are not played as
 *   silence; raw streams: at the scan rate); the scanner only accepts the
 *   recording's own variant. A stream the host restarts resumes with the
 *   first scan that had not left (sim --source too). It ends when the last
 *   scan has left; --loop repeats.
 * On a pseudo-terminal the simulator reads the rate the driver set and
 * garbles both directions when it differs from its own. On a real port
 * (--port) it sets the port to its own rate, as a scanner's UART would.
 * --faults: see lms_sim_parse_faults (drop=PPM,flip=PPM,insert=PPM,
 * nak=PERCENT,silence=AFTER:MS,power=AFTER,hangup=AFTER,seed=N). A hang-up
 * closes the pseudo-terminal and opens a new one behind the same --link.
 * SIGINT / SIGTERM end it; the last stderr line holds the counters.
 */
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli_options.h"
#include "commands.h"
#include "live_common.h"
#include "lms_encode.h"
#include "lms_framer.h"
#include "lms_pty.h"
#include "lms_serial.h"
#include "lms_sim.h"
#include "play_timing.h"
#include "stream_frames.h"

/* --- Scan sources ------------------------------------------------------- */

/* The B0 telegrams of a file, with the gap before each (0: scan rate). */
typedef struct {
    uint8_t *bytes;      /* all telegrams back to back */
    size_t *offset;      /* start of telegram k */
    uint64_t *time_us;   /* while loading: read time of telegram k; 0 in a raw stream */
    uint32_t *gap_us;    /* gap before telegram k on the wire (play_timing.h) */
    play_cursor_t cursor; /* the next one across restarts of the stream */
    size_t count;
    size_t cap;
    size_t used;
    bool loop;
    bool done;           /* play: the last one was handed out */
    uint16_t values;     /* N of the first telegram */
    bool partial;
} recorded_t;

static int recorded_add(recorded_t *r, const uint8_t *t, size_t len, uint64_t time_us)
{
    if (t == NULL || len == 0u) {
        return -1;
    }
    if (r->count % 256u == 0u) {
        size_t *o = realloc(r->offset, (r->count + 256u) * sizeof *o);
        if (o != NULL) {
            r->offset = o;
        }
        uint64_t *tm = realloc(r->time_us, (r->count + 256u) * sizeof *tm);
        if (tm != NULL) {
            r->time_us = tm;
        }
        if (o == NULL || tm == NULL) {
            return -1;
        }
    }
    if (r->used + len > r->cap) {
        const size_t cap = (r->cap + len) * 2u;
        uint8_t *b = realloc(r->bytes, cap);
        if (b == NULL) {
            return -1;
        }
        r->bytes = b;
        r->cap = cap;
    }
    if (r->bytes == NULL) {
        return -1;
    }
    memcpy(r->bytes + r->used, t, len);
    r->offset[r->count] = r->used;
    r->time_us[r->count] = time_us;
    r->used += len;
    r->count++;
    return 0;
}

static void recorded_free(recorded_t *r)
{
    free(r->bytes);
    free(r->offset);
    free(r->time_us);
    free(r->gap_us);
    memset(r, 0, sizeof *r);
}

/* One telegram of the file: B0 telegrams are kept, with their read time. */
static int load_telegram(void *ctx, const uint8_t *t, size_t len, uint64_t time_us)
{
    recorded_t *r = ctx;
    static lms_scan_t scan;
    if (len <= LMS_HEADER_SIZE || t[LMS_HEADER_SIZE] != LMS_REPLY_VALUES ||
        lms_decode_scan(t, len, &scan) != LMS_OK) {
        return 0;
    }
    if (r->count == 0u) {
        r->values = scan.count;
        r->partial = scan.is_partial;
    }
    if (recorded_add(r, t, len, time_us) != 0) {
        cli_error("out of memory reading the scans");
        return 1;
    }
    return 0;
}

/* Reads every B0 of path (raw stream or recording) and times them: a
 * recording's as they left the scanner (play_timing.h), a raw stream's at
 * the scan rate (gaps of 0). Returns 0, or -1 after a message. */
static int recorded_load(recorded_t *r, const char *path)
{
    static lms_framer_t framer;
    if (stream_frames_run_path(path, &framer, load_telegram, r) != CLI_EXIT_OK) {
        return -1;
    }
    if (r->count == 0u) {
        cli_file_error("no scans in ", path, "no valid B0 telegram");
        return -1;
    }
    r->gap_us = calloc(r->count, sizeof *r->gap_us);
    if (r->gap_us == NULL) {
        cli_error("out of memory reading the scans");
        return -1;
    }
    if (r->time_us[r->count - 1u] != 0u) {
        play_wire_gaps(r->time_us, r->gap_us, r->count);
    }
    free(r->time_us); /* the gaps are all play needs */
    r->time_us = NULL;
    return 0;
}

static bool recorded_scan(void *ctx, uint32_t k, uint16_t angle_deg, uint16_t resolution_cdeg,
                          bool partial, lms_unit_t unit, uint8_t reply_address, uint8_t *out,
                          size_t cap, size_t *len, uint32_t *gap_us)
{
    (void)angle_deg;
    (void)resolution_cdeg;
    (void)partial;
    (void)unit;
    (void)reply_address; /* played verbatim, as recorded */
    recorded_t *r = ctx;
    const uint64_t next = play_cursor_index(&r->cursor, k);
    if (!r->loop && next >= r->count) {
        r->done = true;
        return false;
    }
    const size_t i = (size_t)(next % r->count);
    const size_t end = i + 1u < r->count ? r->offset[i + 1u] : r->used;
    const size_t n = end - r->offset[i];
    if (n > cap) {
        return false;
    }
    memcpy(out, r->bytes + r->offset[i], n);
    *len = n;
    /* A stream's first scan, and the first of each loop, at the next rotation. */
    *gap_us = k == 0u || i == 0u ? 0u : r->gap_us[i];
    return true;
}

/* The built-in scene: a closed 6 m x 4 m room with a pillar, the scanner
 * on an ellipse around its middle, one turn every 600 scans. Distances
 * stay below 8 m, so mm units in an 8 m mode hold them. */
#define ROOM_W 6.0
#define ROOM_D 4.0
#define PILLAR_X 4.6
#define PILLAR_Y 2.9
#define PILLAR_R 0.25
#define PI_D 3.14159265358979323846

static double ray_room(double x, double y, double a)
{
    const double c = cos(a);
    const double s = sin(a);
    double best = 1e9;
    if (c > 1e-12) {
        best = fmin(best, (ROOM_W - x) / c);
    } else if (c < -1e-12) {
        best = fmin(best, -x / c);
    }
    if (s > 1e-12) {
        best = fmin(best, (ROOM_D - y) / s);
    } else if (s < -1e-12) {
        best = fmin(best, -y / s);
    }
    /* Pillar: |p + t d - q| = r. */
    const double px = x - PILLAR_X;
    const double py = y - PILLAR_Y;
    const double b = px * c + py * s;
    const double disc = b * b - (px * px + py * py - PILLAR_R * PILLAR_R);
    if (disc >= 0.0) {
        const double t = -b - sqrt(disc);
        if (t > 0.0) {
            best = fmin(best, t);
        }
    }
    return best;
}

static bool synthetic_scan(void *ctx, uint32_t k, uint16_t angle_deg, uint16_t resolution_cdeg,
                           bool partial, lms_unit_t unit, uint8_t reply_address, uint8_t *out,
                           size_t cap, size_t *len, uint32_t *gap_us)
{
    (void)ctx;
    static lms_scan_t scan;
    memset(&scan, 0, sizeof scan);
    const uint32_t res = partial ? 100u : resolution_cdeg;
    scan.count = (uint16_t)((uint32_t)angle_deg * 100u / res + 1u);
    scan.unit = unit;
    scan.status = 0x10u;
    scan.is_partial = partial;
    scan.partial_index = (uint8_t)(partial ? k % 4u : 0u);
    const double phase = 2.0 * PI_D * (double)(k % 600u) / 600.0;
    const double x = ROOM_W / 2.0 + 1.2 * cos(phase);
    const double y = ROOM_D / 2.0 + 0.8 * sin(phase);
    const double heading = atan2(0.8 * cos(phase), -1.2 * sin(phase));
    const double start_deg = angle_deg == 100u ? 40.0 : 0.0;
    const double shift = partial ? 0.25 * (double)scan.partial_index : 0.0;
    for (uint16_t i = 0u; i < scan.count; i++) {
        const double deg = start_deg + shift + (double)i * (double)res / 100.0;
        /* Scanner 90 deg is straight ahead. */
        const double a = heading + (deg - 90.0) * PI_D / 180.0;
        const double r = ray_room(x, y, a);
        const double v = unit == LMS_UNIT_MM ? r * 1000.0 : r * 100.0;
        scan.values[i] = (uint16_t)(v > 8000.0 ? 8000L : lround(v));
    }
    *gap_us = 0u;
    return lms_encode_scan(out, cap, reply_address, &scan, len) == LMS_OK;
}

/* --- The line ---------------------------------------------------------- */

typedef struct {
    bool use_pty;
    lms_pty_t pty;
    lms_serial_t port;
    uint32_t dropped; /* bytes the other end did not take */
} line_t;

static int line_fd(const line_t *l)
{
    return l->use_pty ? l->pty.master : l->port.fd;
}

static const char help_sim[] =
    "input: none, or --source STREAM\n"
    "options:\n"
    "  --baud B      the scanner's power-on rate: 9600 (default), 19200, 38400 or 500000\n"
    "  --source STREAM  scans from STREAM's B0 telegrams (a raw stream or a recording),\n"
    "                looped (default: a built-in synthetic room the scanner drives in)\n"
    "  --faults SPEC drop=PPM,flip=PPM,insert=PPM (bytes, per million), nak=PERCENT,\n"
    "                silence=AFTER:MS, power=AFTER, hangup=AFTER (AFTER in scans),\n"
    "                seed=N (default: none)\n"
    "  --rate X      time scale, 0.01 .. 100 (default 1: real time)\n"
    "  --link PATH   a symbolic link to the pseudo-terminal (kept across hang-ups)\n"
    "  --address A   the scanner's address, 0..127 (default 0)\n"
    "  --units cm|mm the unit it starts in (default cm)\n"
    "  --power-delay MS  ms from power-on to its power-on telegram, 0..120000 (default 100)\n"
    "  --scans N     end after N streamed scans, 1..1000000000 (default: at SIGINT / SIGTERM)\n"
    "\n"
    "output: the first line on stdout is the device path to open (--port of run);\n"
    "  stderr: one line of counters at the end\n"
    "exit status: 0 after a clean end, 1 when the pseudo-terminal or STREAM cannot be\n"
    "  used, 2 bad command line\n";

static const char help_play[] =
    CLI_HELP_STREAM_INPUT
    "options:\n"
    "  --pty         act as the scanner on a new pseudo-terminal (its path: the first\n"
    "                stdout line)\n"
    "  --link PATH   with --pty: a symbolic link to it\n"
    "  --port DEV    or on a real serial port (exactly one of --pty and --port)\n"
    "  --rate X      time scale, 0.01 .. 100 (default 1: the recorded timing, as the\n"
    "                scanner sent the scans; a raw stream at the scan rate)\n"
    "  --loop        play it again and again (default: once)\n"
    "\n"
    "output: the first line on stdout is the device path; stderr: one line of counters\n"
    "exit status: 0 when the last scan has left (or at SIGINT / SIGTERM), 1 when FILE\n"
    "  holds no scan or the line cannot be used, 2 bad command line\n";

void sim_options_defaults(sim_options_t *o)
{
    memset(o, 0, sizeof *o);
    lms_sim_defaults(&o->sim);
}

/* The options of sim (play false) or play (cli_options.h). */
int sim_parse_options(const cli_command_t *self, int argc, char **argv, bool play,
                      sim_options_t *o)
{
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (cli_is_help(arg)) {
            cli_print_command_usage(self, play ? help_play : help_sim);
            return cli_finish_stdout() ? CLI_PARSED_HELP : CLI_EXIT_RUNTIME;
        }
        if (play && strcmp(arg, "--pty") == 0) {
            o->pty = true;
            continue;
        }
        if (play && strcmp(arg, "--loop") == 0) {
            o->loop = true;
            continue;
        }
        if (arg[0] != '-' && play) {
            if (o->source != NULL) {
                return cli_usage_error(self, "more than one FILE", arg, NULL);
            }
            o->source = arg;
            continue;
        }
        if (strcmp(arg, "--rate") == 0) {
            double x = 0.0;
            if (value == NULL || cli_parse_double(value, &x) != 0 || x < 0.01 || x > 100.0) {
                return cli_usage_error(self, "invalid --rate", value, "0.01 .. 100");
            }
            o->sim.speed_permille = (uint32_t)lround(x * 1000.0);
        } else if (strcmp(arg, "--link") == 0 && value != NULL) {
            o->link = value;
        } else if (play && strcmp(arg, "--port") == 0 && value != NULL) {
            o->port = value;
        } else if (!play && strcmp(arg, "--baud") == 0) {
            if (live_parse_baud(value, &o->sim.power_on_baud) != 0) {
                return cli_usage_error(self, "invalid --baud", value, "9600, 19200, 38400 or 500000");
            }
        } else if (!play && strcmp(arg, "--source") == 0 && value != NULL) {
            o->source = value;
        } else if (!play && strcmp(arg, "--faults") == 0) {
            if (value == NULL || !lms_sim_parse_faults(value, &o->sim.faults)) {
                return cli_usage_error(self, "invalid --faults", value,
                                       "e.g. drop=100,nak=5,silence=200:500,power=400,hangup=600");
            }
        } else if (!play && strcmp(arg, "--address") == 0) {
            unsigned long a = 0u;
            if (cli_parse_whole(value, 0u, 127u, &a) != 0) {
                return cli_usage_error(self, "invalid --address", value, "0..127");
            }
            o->sim.address = (uint8_t)a;
        } else if (!play && strcmp(arg, "--units") == 0) {
            if (live_parse_unit(value, &o->sim.unit) != 0) {
                return cli_usage_error(self, "invalid --units", value, "cm or mm");
            }
        } else if (!play && strcmp(arg, "--power-delay") == 0) {
            unsigned long ms = 0u;
            if (cli_parse_whole(value, 0u, 120000u, &ms) != 0) {
                return cli_usage_error(self, "invalid --power-delay", value, "ms, 0..120000");
            }
            o->sim.power_on_delay_us = (uint32_t)(ms * 1000u);
        } else if (!play && strcmp(arg, "--scans") == 0) {
            if (cli_parse_whole(value, 1u, 1000000000u, &o->scans) != 0) {
                return cli_usage_error(self, "invalid --scans", value, "1..1000000000");
            }
        } else if (value == NULL && arg[0] == '-') {
            return cli_usage_error(self, "unknown option or missing value", arg, NULL);
        } else {
            return cli_usage_error(self, "unknown option", arg, NULL);
        }
        i++;
    }
    if (play && o->source == NULL) {
        return cli_usage_error(self, "missing FILE", NULL, NULL);
    }
    if (play && o->pty == (o->port != NULL)) {
        return cli_usage_error(self, "give exactly one of --pty and --port DEV", NULL, NULL);
    }
    return 0;
}

/* Writes what the scanner sends; a full pseudo-terminal (nobody reading)
 * loses bytes, as a line without a listener does. */
static void line_send(line_t *l, const uint8_t *bytes, size_t n)
{
    size_t off = 0u;
    while (off < n) {
        const ssize_t w = write(line_fd(l), bytes + off, n - off);
        if (w > 0) {
            off += (size_t)w;
        } else if (w < 0 && errno == EINTR) {
            continue;
        } else {
            l->dropped += (uint32_t)(n - off);
            return;
        }
    }
}

/* A wake-up this much later than the simulator asked for: its process was
 * not running (a busy machine), and the line was silent meanwhile, which a
 * real scanner never is. Counted, so that a test can tell a silence of the
 * machine from one the driver should not have seen (live.sh). */
#define STALL_US 50000u

typedef struct {
    uint64_t wake_us;   /* when the loop asked to run again; 0: not yet */
    unsigned long count; /* wake-ups STALL_US or more late */
    uint64_t max_us;    /* the latest of them */
} stalls_t;

static void stalls_check(stalls_t *st, uint64_t now)
{
    if (st->wake_us != 0u && now >= st->wake_us + STALL_US) {
        st->count++;
        if (now - st->wake_us > st->max_us) {
            st->max_us = now - st->wake_us;
        }
    }
}

/* Until the model's next event, 1 .. 100 ms. At least 1 ms: bytes then
 * leave in chunks of up to a millisecond of line time, as a USB serial
 * adapter delivers them, instead of a wake-up per 20-us byte at 500 kbaud. */
static int poll_timeout_ms(uint64_t now, uint64_t next)
{
    if (next == UINT64_MAX || next >= now + 100000u) {
        return 100;
    }
    const uint64_t ms = next > now ? (next - now) / 1000u : 0u;
    return ms < 1u ? 1 : (int)ms;
}

static int sim_main(const cli_command_t *self, int argc, char **argv, bool play)
{
    static sim_options_t o;
    static lms_sim_t sim;
    static recorded_t rec;
    static line_t line;
    memset(&rec, 0, sizeof rec);
    memset(&line, 0, sizeof line);
    line.pty.master = -1;
    line.port.fd = -1;
    sim_options_defaults(&o);
    const int rc = sim_parse_options(self, argc, argv, play, &o);
    if (rc == CLI_PARSED_HELP) {
        return CLI_EXIT_OK;
    }
    if (rc != 0) {
        return rc;
    }
    if (o.source != NULL) {
        if (recorded_load(&rec, o.source) != 0) {
            recorded_free(&rec);
            return CLI_EXIT_RUNTIME;
        }
        rec.loop = !play || o.loop;
        o.sim.scan_source = recorded_scan;
        o.sim.scan_ctx = &rec;
        /* The recording fixes the variant: only that one is accepted. */
        if (!rec.partial) {
            o.sim.fixed_angle_deg = (rec.values == 101u || rec.values == 201u || rec.values == 401u)
                                        ? 100u : 180u;
            o.sim.fixed_resolution_cdeg =
                (uint16_t)(o.sim.fixed_angle_deg * 100u / (uint32_t)(rec.values - 1u));
        }
    } else {
        o.sim.scan_source = synthetic_scan;
    }
    line.use_pty = !play || o.pty;
    if (line.use_pty) {
        const int e = lms_pty_open(&line.pty, o.link);
        if (e != 0) {
            cli_file_error("cannot create a pseudo-terminal", o.link != NULL ? o.link : "",
                           strerror(e));
            recorded_free(&rec);
            return CLI_EXIT_RUNTIME;
        }
    } else {
        const lms_serial_status_t st = lms_serial_open(&line.port, o.port, o.sim.power_on_baud);
        if (st != LMS_SERIAL_OK) {
            cli_file_error("cannot open ", o.port, lms_serial_status_name(st));
            recorded_free(&rec);
            return CLI_EXIT_RUNTIME;
        }
    }
    (void)printf("%s\n", line.use_pty ? lms_pty_path(&line.pty) : o.port);
    (void)fflush(stdout);

    live_catch_stop_signals();

    const uint64_t t0 = live_monotonic_us();
    lms_sim_init(&sim, &o.sim, 0u);
    int status = CLI_EXIT_OK;
    static uint8_t buf[4096];
    lms_baud_t port_baud = o.sim.power_on_baud;
    stalls_t stalls = {0u, 0u, 0u};
    while (!live_stop_requested()) {
        const uint64_t now = live_monotonic_us() - t0;
        stalls_check(&stalls, now);
        /* The host's rate: what the driver set on the pseudo-terminal (a
         * rate none of the four: anything but ours, so all is garbled); on
         * a real port, our own (the port follows us). */
        lms_baud_t host = lms_sim_baud(&sim);
        if (line.use_pty && !lms_pty_host_baud(&line.pty, &host)) {
            host = lms_sim_baud(&sim) == LMS_BAUD_9600 ? LMS_BAUD_19200 : LMS_BAUD_9600;
        }
        const size_t n = lms_sim_transmit(&sim, host, now, buf, sizeof buf);
        if (n > 0u) {
            line_send(&line, buf, n);
        }
        if (!line.use_pty && lms_sim_baud(&sim) != port_baud) {
            port_baud = lms_sim_baud(&sim);
            (void)lms_serial_set_baud(&line.port, port_baud);
        }
        if (lms_sim_take_hangup(&sim) && line.use_pty) {
            const int e = lms_pty_reopen(&line.pty);
            if (e != 0) {
                cli_error("cannot reopen the pseudo-terminal after the hang-up");
                status = CLI_EXIT_RUNTIME;
                break;
            }
            (void)fprintf(stderr, "lmsego: %s: hung up; now at %s\n", self->name,
                          lms_pty_path(&line.pty));
        }
        const lms_sim_stats_t *ss = lms_sim_stats(&sim);
        if ((o.scans > 0u && ss->scans_sent >= o.scans) ||
            (rec.done && lms_sim_next_event_us(&sim, now) == UINT64_MAX)) {
            break; /* sim --scans reached, or play: the recording has left */
        }
        const uint64_t next = lms_sim_next_event_us(&sim, now);
        struct pollfd p = {line_fd(&line), POLLIN, 0};
        const int timeout_ms = poll_timeout_ms(now, next);
        stalls.wake_us = now + (uint64_t)timeout_ms * 1000u;
        const int pr = poll(&p, 1u, timeout_ms);
        if (pr < 0 && errno != EINTR) {
            cli_error(strerror(errno));
            status = CLI_EXIT_RUNTIME;
            break;
        }
        if (pr > 0 && (p.revents & POLLIN) != 0) {
            const ssize_t r = read(line_fd(&line), buf, sizeof buf);
            if (r > 0) {
                lms_sim_receive(&sim, buf, (size_t)r, host, live_monotonic_us() - t0);
            }
        } else if (pr > 0 && (p.revents & (POLLHUP | POLLERR)) != 0 && !line.use_pty) {
            cli_file_error("hang-up on ", o.port, "the line was closed");
            status = CLI_EXIT_RUNTIME;
            break;
        }
    }
    const lms_sim_stats_t *ss = lms_sim_stats(&sim);
    (void)fprintf(stderr,
                  "lmsego: %s: scans_sent=%lu scans_skipped=%lu host_telegrams=%lu host_bad=%lu "
                  "garbled_bytes=%lu baud_changes=%lu config_writes=%lu power_cycles=%lu "
                  "dropped=%lu flipped=%lu inserted=%lu unread=%lu stalls=%lu stall_max_ms=%lu\n",
                  self->name, (unsigned long)ss->scans_sent, (unsigned long)ss->scans_skipped,
                  (unsigned long)ss->host_telegrams, (unsigned long)ss->host_bad,
                  (unsigned long)ss->garbled_bytes, (unsigned long)ss->baud_changes,
                  (unsigned long)ss->config_writes, (unsigned long)ss->power_cycles,
                  (unsigned long)ss->bytes_dropped, (unsigned long)ss->bytes_flipped,
                  (unsigned long)ss->bytes_inserted, (unsigned long)line.dropped, stalls.count,
                  (unsigned long)(stalls.max_us / 1000u));
    if (line.use_pty) {
        lms_pty_close(&line.pty);
    } else {
        lms_serial_close(&line.port);
    }
    recorded_free(&rec);
    return status;
}

int cmd_sim(const cli_command_t *self, int argc, char **argv)
{
    return sim_main(self, argc, argv, false);
}

int cmd_play(const cli_command_t *self, int argc, char **argv)
{
    return sim_main(self, argc, argv, true);
}
