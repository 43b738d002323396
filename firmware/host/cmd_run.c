/* cmd_run.c - `lmsego run` and `lmsego record`: a live scanner on a serial
 * port (host-only).
 *
 *   lmsego run --port DEV [--baud B] [--variant DEG,RES] [--units cm|mm]
 *              [--mode HEX] [--partial] [--address A] [--power-wait S]
 *              [--mount X,Y,DEG] [--scans N] [--record FILE] [--moving]
 *   lmsego record --port DEV [same bring-up options] -o FILE [--scans N]
 *
 * Both open the port (driver/posix/lms_serial), run the session
 * (driver/lms_session) until the scanner streams, and then:
 * - run: feeds every B0 to the firmware loop and prints the CSV of
 *   `lmsego replay`, one line per scan, plus latency_ms. time_s is the
 *   scan's time (the mean of its beams' times: ego_range.h) in seconds
 *   since run started, from the arrival times of its bytes less their wire
 *   time and the lag of its beams, tracked by counting scan intervals
 *   (ego_loop.h, "Scan times from arrival stamps"), so the velocities' dt
 *   is the mirror's; latency_ms is the clock when the line is written less
 *   time_s. --record FILE also writes the recording (as record does), and
 *   `lmsego replay FILE` prints the same CSV without latency_ms, byte for
 *   byte, when the run had no restart; --moving adds each scan's moving
 *   objects after its line ("o," lines, as `replay --moving`; ego_loop.h);
 * - record: writes every byte read while streaming, with its arrival time,
 *   to a recording (firmware/host/recording.h) that stats, scans and
 *   replay read.
 * A restart of the session (silence, power-on telegram, hang-up) is
 * reported on stderr and resets the estimator (ego_loop_gap). A hang-up
 * closes the port and reopens it every 200 ms until it comes back.
 * SIGINT / SIGTERM (or --scans N reached) stop cleanly: stream off (20 25)
 * and the scanner back at 9600 baud, where the next start finds it fast.
 * Both run the firmware's live core (firmware/ego_live.h) with the host as
 * its board: the bytes read go into the same receive ring a UART interrupt
 * fills on a target, and the same service and estimate steps run; see
 * live() below. After --scans N the scans still queued for the estimator
 * get their lines; after a signal they are dropped (counted on stderr), so
 * an interrupt never waits for a backlog.
 * Exit status: 0 after a clean stop, 1 when the port cannot be used or the
 * scanner refuses a setting, 2 for a bad command line. The last stderr line
 * holds the counters.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cli_options.h"
#include "commands.h"
#include "ego_live.h"
#include "ego_loop.h"
#include "lms_serial.h"
#include "live_common.h"
#include "lms_session.h"
#include "recording.h"

#define REOPEN_INTERVAL_MS 200
#define POLL_MAX_MS 100

typedef struct {
    lms_serial_t port;
    int out_failed;     /* stdout */
    uint64_t t0_us;
} live_io_t;

static void io_write(void *ctx, const uint8_t *bytes, size_t len)
{
    live_io_t *io = ctx;
    if (io->port.fd >= 0) {
        /* A failed write needs no handling here: the read side sees the
         * hang-up and recovers, and a lost command is retried. */
        (void)lms_serial_write(&io->port, bytes, len);
    }
}

static void io_set_baud(void *ctx, lms_baud_t baud)
{
    live_io_t *io = ctx;
    if (io->port.fd >= 0) {
        (void)lms_serial_set_baud(&io->port, baud);
    }
}

static void hal_write(void *ctx, const uint8_t *buf, size_t len)
{
    live_io_t *io = ctx;
    if (fwrite(buf, 1u, len, stdout) != len || fflush(stdout) != 0) {
        io->out_failed = 1;
    }
}

static uint32_t hal_now_us(void *ctx)
{
    const live_io_t *io = ctx;
    return (uint32_t)(live_monotonic_us() - io->t0_us);
}

/* "180,0.5" -> 180 deg, 50 cdeg; only the five legal pairs. */
static int parse_variant(const char *text, uint16_t *angle, uint16_t *res)
{
    static const struct {
        const char *name;
        uint16_t angle, res;
    } v[] = {{"180,1", 180u, 100u}, {"180,0.5", 180u, 50u}, {"100,1", 100u, 100u},
             {"100,0.5", 100u, 50u}, {"100,0.25", 100u, 25u}};
    for (size_t i = 0u; text != NULL && i < sizeof v / sizeof v[0]; i++) {
        if (strcmp(text, v[i].name) == 0) {
            *angle = v[i].angle;
            *res = v[i].res;
            return 0;
        }
    }
    return -1;
}

/* The help of run and record: their common bring-up options, then each
 * one's own. */
#define HELP_BRING_UP                                                                            \
    "input:\n"                                                                                   \
    "  a live LMS 2xx on a serial port (RS-232 / RS-422), found at any of its four rates\n"      \
    "options:\n"                                                                                 \
    "  --port DEV    the serial device (required), e.g. /dev/ttyUSB0\n"                         \
    "  --baud B      the rate to stream at: 9600, 19200, 38400 or 500000 (default)\n"           \
    "  --variant DEG,RES  scanning angle and resolution: 180,1 180,0.5 100,1 100,0.5 or\n"       \
    "                100,0.25 (deg; default: the scanner's own)\n"                               \
    "  --units cm|mm the unit of the values (default: the scanner's own)\n"                     \
    "  --mode HEX    measuring mode 00..06 or 0F (default: the scanner's own)\n"                \
    "  --partial     stream partial scans (interlaced halves; default: whole scans)\n"          \
    "  --address A   the scanner's address, 0..127 (default 0: any)\n"                          \
    "  --power-wait S  first wait up to S seconds, 0..120, for the power-on telegram\n"        \
    "                (default 0: probe at once)\n"                                               \
    "  --scans N     stop after N scans, 1..1000000000 (default: at SIGINT / SIGTERM)\n"

static const char help_run[] =
    HELP_BRING_UP
    "  --mount X,Y,DEG  the scanner's pose on the vehicle: m, m, deg (default 0,0,0)\n"
    "  --record FILE also writes the recording, as record does\n"
    "  --moving      each line is followed by its scan's moving objects, one line each:\n"
    "                'o,scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points' (m, m/s,\n"
    "                the scan's vehicle frame; nan until known; as replay --moving)\n";

static const char tail_run[] =
    "\nstderr: the link's events (streaming, link lost), then one line of counters\n"
    "exit status: 0 after a clean stop (signal or --scans), 1 when the port cannot be\n"
    "  used or the scanner refuses a setting, 2 bad command line\n";

static const char help_record[] =
    HELP_BRING_UP
    "  -o FILE       the recording to write (required)\n";

static const char tail_record[] =
    "\noutput: FILE, the line's bytes with their arrival times (the recording format of\n"
    "  docs/session.md), which stats, scans, replay and play read\n"
    "stderr: the link's events, then one line of counters\n"
    "exit status: 0 after a clean stop (signal or --scans), 1 when the port or FILE\n"
    "  cannot be used or the scanner refuses a setting, 2 bad command line\n";

void live_options_defaults(live_options_t *o)
{
    /* The options start from the live core's defaults (its session, and
     * its loop within the sensor-rate budget). */
    ego_live_config_t config;
    ego_live_defaults(&config);
    memset(o, 0, sizeof *o);
    o->session = config.session;
    o->loop = config.loop;
}

/* The options of run (record false) or record (cli_options.h). */
int live_parse_options(const cli_command_t *self, int argc, char **argv, bool record,
                       live_options_t *o)
{
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (arg == NULL) {
            break;
        }
        if (cli_is_help(arg)) {
            cli_print_command_usage(self, record ? help_record : help_run);
            if (!record) {
                cli_print_csv_columns("the scan's time (the mean of its beams' times) since\n"
                                      "                run started, from its bytes' arrival",
                                      true);
            }
            (void)fputs(record ? tail_record : tail_run, stdout);
            return cli_finish_stdout() ? CLI_PARSED_HELP : CLI_EXIT_RUNTIME;
        }
        if (strcmp(arg, "--port") == 0 && value != NULL) {
            o->port = value;
        } else if (strcmp(arg, "--baud") == 0) {
            if (live_parse_baud(value, &o->session.baud) != 0) {
                return cli_usage_error(self, "invalid --baud", value,
                                       "9600, 19200, 38400 or 500000");
            }
        } else if (strcmp(arg, "--variant") == 0) {
            if (parse_variant(value, &o->session.angle_deg, &o->session.resolution_cdeg) != 0) {
                return cli_usage_error(self, "invalid --variant", value,
                                       "180,1 180,0.5 100,1 100,0.5 or 100,0.25");
            }
        } else if (strcmp(arg, "--units") == 0) {
            lms_unit_t unit = LMS_UNIT_CM;
            if (live_parse_unit(value, &unit) != 0) {
                return cli_usage_error(self, "invalid --units", value, "cm or mm");
            }
            o->session.unit = (uint8_t)unit;
        } else if (strcmp(arg, "--mode") == 0) {
            if (value == NULL || cli_parse_meas_mode(value, &o->session.meas_mode) != 0) {
                return cli_usage_error(self, "invalid --mode", value, "expected 00..06 or 0F");
            }
            o->loop.lms.meas_mode = o->session.meas_mode;
        } else if (strcmp(arg, "--partial") == 0) {
            o->session.partial = true;
            continue;
        } else if (!record && strcmp(arg, "--moving") == 0) {
#if EGO_LOOP_OBJECTS
            o->loop.objects = true;
            continue;
#else
            return cli_usage_error(self, "this lmsego was built without", arg,
                                   "LMSEGO_LOOP_OBJECTS=ON");
#endif
        } else if (strcmp(arg, "--address") == 0) {
            unsigned long a = 0u;
            if (cli_parse_whole(value, 0u, 127u, &a) != 0) {
                return cli_usage_error(self, "invalid --address", value, "0..127");
            }
            o->session.address = (uint8_t)a;
        } else if (strcmp(arg, "--power-wait") == 0) {
            unsigned long s = 0u;
            if (cli_parse_whole(value, 0u, 120u, &s) != 0) {
                return cli_usage_error(self, "invalid --power-wait", value, "seconds, 0..120");
            }
            o->session.power_wait_us = (uint32_t)(s * 1000000u);
        } else if (strcmp(arg, "--scans") == 0) {
            if (cli_parse_whole(value, 1u, 1000000000u, &o->scans) != 0) {
                return cli_usage_error(self, "invalid --scans", value, "1..1000000000");
            }
        } else if (!record && strcmp(arg, "--mount") == 0) {
            if (value == NULL || cli_parse_mount(value, &o->loop.lms) != 0) {
                return cli_usage_error(self, "invalid --mount", value, "X,Y,THETA_DEG in m and deg");
            }
        } else if (record && strcmp(arg, "-o") == 0 && value != NULL) {
            o->out_path = value;
        } else if (!record && strcmp(arg, "--record") == 0 && value != NULL) {
            o->out_path = value;
            o->run_records = true;
        } else if (strcmp(arg, "--port") == 0 || strcmp(arg, "-o") == 0 ||
                   strcmp(arg, "--record") == 0) {
            return cli_usage_error(self, "missing value after", arg, NULL);
        } else {
            return cli_usage_error(self, "unknown option", arg, NULL);
        }
        i++; /* every option left here took a value */
    }
    if (o->port == NULL) {
        return cli_usage_error(self, "missing --port DEV", NULL, NULL);
    }
    if (record && o->out_path == NULL) {
        return cli_usage_error(self, "missing -o FILE", NULL, NULL);
    }
    return 0;
}

static void report_session(const lms_session_t *s, const char *what)
{
    const lms_session_stats_t *st = lms_session_stats(s);
    const lms_framer_stats_t *fs = lms_session_framer_stats(s);
    (void)fprintf(stderr,
                  "lmsego: %s: scans=%lu bring_ups=%lu restarts=%lu (silence %lu, power-on %lu, "
                  "link %lu) commands=%lu retries=%lu naks=%lu not_acks=%lu ack_timeouts=%lu "
                  "reply_timeouts=%lu probes=%lu crc_errors=%lu bytes_skipped=%lu\n",
                  what, (unsigned long)st->scans, (unsigned long)st->bring_ups,
                  (unsigned long)st->restarts, (unsigned long)st->restarts_silence,
                  (unsigned long)st->restarts_power_on, (unsigned long)st->restarts_link,
                  (unsigned long)st->commands, (unsigned long)st->retries,
                  (unsigned long)st->naks, (unsigned long)st->not_acks,
                  (unsigned long)st->ack_timeouts, (unsigned long)st->reply_timeouts,
                  (unsigned long)st->probes, (unsigned long)fs->crc_errors,
                  (unsigned long)fs->bytes_skipped);
}

static const char *cause_text(lms_session_cause_t c)
{
    switch (c) {
    case LMS_SESSION_CAUSE_SILENCE:
        return "no scans";
    case LMS_SESSION_CAUSE_POWER_ON:
        return "power-on telegram";
    case LMS_SESSION_CAUSE_LINK:
        return "line hung up";
    default:
        return "?";
    }
}

/* What the live core did since the last look, told on stderr: the
 * session's events are the core's, so `run` reads them off its counters. */
typedef struct {
    bool streaming;
    uint32_t restarts;
} seen_t;

static void report_changes(const char *name, const lms_session_t *s, seen_t *seen)
{
    const bool streaming = lms_session_state(s) == LMS_SESSION_STREAMING;
    const uint32_t restarts = lms_session_stats(s)->restarts;
    if (restarts != seen->restarts) {
        (void)fprintf(stderr, "lmsego: %s: link lost (%s); bringing the scanner up again\n", name,
                      cause_text(lms_session_cause(s)));
    }
    if (streaming && !seen->streaming) {
        const lms_session_info_t *in = lms_session_info(s);
        (void)fprintf(stderr,
                      "lmsego: %s: streaming: '%s' at %s baud, %u deg / %u.%02u deg, %s\n", name,
                      in->type_text, live_baud_name(in->baud), (unsigned)in->angle_deg,
                      in->resolution_cdeg / 100u, in->resolution_cdeg % 100u,
                      in->units == 1u ? "mm" : "cm");
    }
    seen->streaming = streaming;
    seen->restarts = restarts;
}

/* Scans waiting for the estimator, taken from the core as soon as the
 * service put them in its mailbox, so none is replaced there: 4096 hold 55 s
 * of 75 Hz scans; a scan that finds the queue full is dropped and counted. */
#define SCAN_QUEUE 4096u

typedef struct {
    ego_live_slot_t item[SCAN_QUEUE];
    uint32_t head;
    uint32_t count;
    uint32_t dropped;
    uint32_t deepest;      /* most entries waiting at once */
} scan_queue_t;

static void queue_push(scan_queue_t *q, const ego_live_slot_t *slot)
{
    if (q->count == SCAN_QUEUE) {
        q->dropped++;
        return;
    }
    q->item[(q->head + q->count) % SCAN_QUEUE] = *slot;
    q->count++;
    q->deepest = q->count > q->deepest ? q->count : q->deepest;
}

/* The oldest entry, or NULL; valid until the next push. */
static const ego_live_slot_t *queue_pop(scan_queue_t *q)
{
    if (q->count == 0u) {
        return NULL;
    }
    const ego_live_slot_t *e = &q->item[q->head];
    q->head = (q->head + 1u) % SCAN_QUEUE;
    q->count--;
    return e;
}

/* The whole live job; record selects the mode. The host is the firmware's
 * board here, and runs the firmware core (firmware/ego_live.h) in its
 * deferred mode, the code a microcontroller runs: what the port delivers
 * goes into the core's receive ring, stamped with the time of the read (the
 * receive interrupt's job on a target), and ego_live_service runs the
 * session at once. The estimator's half differs in one way: where a target
 * estimates only the newest scan, run takes every scan out of the mailbox
 * as it comes (one_scan_per_service, ego_live_take) into its own queue and
 * estimates them in order, one between two reads (ego_live_estimate_slot),
 * so the line and the session's timers are served however long a hard
 * scan takes and no scan is skipped: on a line that loses nothing the
 * output is byte for byte `lmsego replay`'s. record takes the scans and drops them, and
 * writes every read the session took while streaming. */
static int live(const cli_command_t *self, int argc, char **argv, bool record)
{
    static live_options_t o;
    static live_io_t io;
    static ego_live_t core;
    static uart_ring_t ring;
    static scan_queue_t queue;
    static uint8_t buf[UART_RING_SIZE];
    /* The read before, written first when the recording starts: the reply
     * that started the stream may have begun there, and replay needs all
     * of it (it is where a recording's scan times start counting bytes). */
    static uint8_t prev[UART_RING_SIZE];
    size_t prev_len = 0u;
    uint64_t prev_us = 0u;
    bool recorded = false;
    memset(&io, 0, sizeof io);
    queue.head = 0u;
    queue.count = 0u;
    queue.dropped = 0u;
    queue.deepest = 0u;
    ego_live_config_t config;
    ego_live_defaults(&config);
    live_options_defaults(&o);
    const int rc = live_parse_options(self, argc, argv, record, &o);
    if (rc == CLI_PARSED_HELP) {
        return CLI_EXIT_OK; /* --help */
    }
    if (rc != 0) {
        return rc;
    }
    const bool recording = record || o.run_records;
    recording_writer_t rec;
    memset(&rec, 0, sizeof rec);
    const int open_error = recording ? recording_writer_open(&rec, o.out_path) : 0;
    if (open_error != 0) {
        cli_file_error("cannot create ", o.out_path, strerror(open_error));
        return CLI_EXIT_RUNTIME;
    }
    io.port.fd = -1;
    io.t0_us = live_monotonic_us();
    lms_serial_status_t ps = lms_serial_open(&io.port, o.port, LMS_BAUD_9600);
    if (ps != LMS_SERIAL_OK) {
        cli_file_error("cannot open ", o.port, lms_serial_status_name(ps));
        if (recording) {
            (void)recording_writer_close(&rec);
        }
        return CLI_EXIT_RUNTIME;
    }
    live_catch_stop_signals();

    config.session = o.session;
    config.loop = o.loop;
    config.max_scans = (uint32_t)o.scans;
    config.loop.latency = !record; /* run: the latency_ms column */
    config.deferred = true;
    config.one_scan_per_service = true;
    const ego_live_hal_t hal = {io_write, io_set_baud, hal_now_us, hal_write, &io};
    uart_ring_init(&ring);
    if (ego_live_init(&core, &config, &hal, &ring) != LMS_OK) {
        cli_error("invalid session settings");
        lms_serial_close(&io.port);
        if (recording) {
            (void)recording_writer_close(&rec);
        }
        return CLI_EXIT_RUNTIME;
    }
    const lms_session_t *session = ego_live_session(&core);
    seen_t seen = {false, 0u};
    int status = CLI_EXIT_OK;
    bool stopping = false;
    uint64_t next_reopen_us = 0u;
    while (ego_live_status(&core) == EGO_LIVE_RUNNING) {
        if (live_stop_requested() && !stopping) {
            stopping = true;
            ego_live_stop(&core);
        }
        size_t got = 0u;
        uint64_t read_us = live_monotonic_us() - io.t0_us;
        if (io.port.fd < 0) {
            /* Hung up: try the device again every REOPEN_INTERVAL_MS. */
            const uint64_t t = live_monotonic_us();
            if (stopping) {
                break;
            }
            if (t >= next_reopen_us) {
                next_reopen_us = t + REOPEN_INTERVAL_MS * 1000u;
                if (lms_serial_open(&io.port, o.port, LMS_BAUD_9600) == LMS_SERIAL_OK) {
                    (void)fprintf(stderr, "lmsego: %s: port reopened\n", self->name);
                    ego_live_link_lost(&core);
                }
            }
            if (io.port.fd < 0) {
                struct timespec nap = {0, 20 * 1000000L}; /* waiting for a device, not for data */
                (void)nanosleep(&nap, NULL);
                continue;
            }
        } else {
            const uint32_t wait = ego_live_wait_us(&core);
            int timeout_ms = (int)(wait / 1000u) + (wait % 1000u != 0u ? 1 : 0);
            timeout_ms = timeout_ms > POLL_MAX_MS ? POLL_MAX_MS : timeout_ms;
            if (queue.count > 0u) {
                timeout_ms = 0; /* scans are waiting: only take what is there */
            }
            const size_t room = UART_RING_SIZE - uart_ring_count(&ring);
            ps = lms_serial_read(&io.port, buf, room, timeout_ms, &got);
            read_us = live_monotonic_us() - io.t0_us;
            if (ps == LMS_SERIAL_HANGUP) {
                (void)fprintf(stderr, "lmsego: %s: %s hung up; reopening\n", self->name, o.port);
                lms_serial_close(&io.port);
                ego_live_link_lost(&core);
                got = 0u;
            } else if (ps < 0) {
                cli_file_error("error reading ", o.port, lms_serial_status_name(ps));
                status = CLI_EXIT_RUNTIME;
                break;
            }
        }
        (void)uart_ring_write(&ring, buf, got, (uint32_t)read_us);
        /* Every scan out of the mailbox as the service puts it there. */
        do {
            ego_live_service(&core);
            const ego_live_slot_t *s = ego_live_take(&core);
            if (s != NULL && !record) {
                queue_push(&queue, s);
            }
        } while (uart_ring_count(&ring) > 0u && ego_live_status(&core) == EGO_LIVE_RUNNING);
        const bool was_streaming = seen.streaming;
        report_changes(self->name, session, &seen);
        /* A recording holds the stream: every read whose bytes the session
         * took while streaming, from the one that started it (and the one
         * before) to the one that ended it (its last scan, --scans N). */
        int rec_error = 0;
        if (recording && got > 0u && (was_streaming || seen.streaming)) {
            if (!recorded && prev_len > 0u) {
                rec_error = recording_writer_append(&rec, prev_us, prev, prev_len);
            }
            recorded = true;
            if (rec_error == 0) {
                rec_error = recording_writer_append(&rec, read_us, buf, got);
            }
        } else if (got > 0u) {
            memcpy(prev, buf, got);
            prev_len = got;
            prev_us = read_us;
        }
        if (rec_error != 0) {
            cli_file_error("error writing ", o.out_path, strerror(rec_error));
            status = CLI_EXIT_RUNTIME;
            break;
        }
        /* One queued scan per round, then the line again. */
        const ego_live_slot_t *e = queue_pop(&queue);
        if (e != NULL) {
            ego_live_estimate_slot(&core, e);
        }
        if (io.out_failed) {
            cli_error("write error on standard output");
            status = CLI_EXIT_RUNTIME;
            break;
        }
    }
    /* --scans N reached: the scans queued still get their lines; after a
     * signal they are dropped (counted), so an interrupt never waits for a
     * backlog. */
    while (status == CLI_EXIT_OK && !live_stop_requested() && !io.out_failed) {
        const ego_live_slot_t *e = queue_pop(&queue);
        if (e == NULL) {
            break;
        }
        ego_live_estimate_slot(&core, e);
    }
    queue.dropped += queue.count;
    if (ego_live_status(&core) == EGO_LIVE_FAILED) {
        cli_error(lms_session_error_name(lms_session_error(session)));
        status = CLI_EXIT_RUNTIME;
    }
    if (!record) {
        (void)fprintf(stderr, "lmsego: %s: queue deepest=%lu dropped=%lu\n", self->name,
                      (unsigned long)queue.deepest, (unsigned long)queue.dropped);
    }
    report_session(session, self->name);
    lms_serial_close(&io.port);
    const int close_error = recording ? recording_writer_close(&rec) : 0;
    if (close_error != 0) {
        cli_file_error("error writing ", o.out_path, strerror(close_error));
        status = CLI_EXIT_RUNTIME;
    }
    return status;
}

int cmd_run(const cli_command_t *self, int argc, char **argv)
{
    return live(self, argc, argv, false);
}

int cmd_record(const cli_command_t *self, int argc, char **argv)
{
    return live(self, argc, argv, true);
}
