/* cmd_replay.c - `lmsego replay FILE [--period S] [--mount X,Y,THETA_DEG]
 * [--mode HEX] [--icp] [--hist AH|LAH|HAH|HTAH]`: runs the firmware loop (firmware/ego_loop.h) over a
 * recorded telegram stream, through a host HAL that reads the file, and
 * prints its CSV on stdout. A summary line goes to stderr at the end:
 *
 *   lmsego: replay: scans=N lines=L predicted=P restarts=R decode_errors=D
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "ego_loop.h"
#include "stream_file.h"

typedef struct {
    stream_file_t file;
    int failed; /* a read error happened */
    int write_failed;
} replay_io_t;

static int32_t hal_read(void *ctx, uint8_t *buf, size_t cap)
{
    replay_io_t *io = ctx;
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
    if (fwrite(buf, 1u, len, stdout) != len) {
        io->write_failed = 1;
    }
}

static uint32_t hal_now_us(void *ctx)
{
    (void)ctx;
    return 0u; /* replay times scans by their index and the period */
}

/* A finite double from text, the whole text. */
static int parse_double(const char *text, double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(text, &end);
    if (end == text || *end != '\0' || errno != 0 || !isfinite(v)) {
        return -1;
    }
    *out = v;
    return 0;
}

/* "X,Y,THETA_DEG" -> the mounting pose. */
static int parse_mount(const char *text, ego_prep_params_t *prep)
{
    char buf[96];
    if (strlen(text) >= sizeof buf) {
        return -1;
    }
    (void)memcpy(buf, text, strlen(text) + 1u);
    char *parts[3];
    char *p = buf;
    for (int i = 0; i < 3; i++) {
        parts[i] = p;
        char *comma = strchr(p, ',');
        if ((i < 2) != (comma != NULL)) {
            return -1;
        }
        if (comma != NULL) {
            *comma = '\0';
            p = comma + 1;
        }
    }
    double x;
    double y;
    double deg;
    if (parse_double(parts[0], &x) != 0 || parse_double(parts[1], &y) != 0 ||
        parse_double(parts[2], &deg) != 0 || fabs(x) > 100.0 || fabs(y) > 100.0) {
        return -1;
    }
    prep->mount_x = (fx_q16_16_t)lround(x * 65536.0);
    prep->mount_y = (fx_q16_16_t)lround(y * 65536.0);
    double turns = deg / 360.0;
    turns -= floor(turns);
    prep->mount_theta = (fx_bam32_t)(uint64_t)llround(turns * 4294967296.0);
    return 0;
}

static int parse_mode(const char *text, uint8_t *mode)
{
    char *end = NULL;
    const unsigned long v = strtoul(text, &end, 16);
    if (end == text || *end != '\0' || v > 0xFFu || lms_meas_mode_bits((uint8_t)v) == 0u ||
        v == LMS_MEAS_REFLECTIVITY) {
        return -1;
    }
    *mode = (uint8_t)v;
    return 0;
}

static int parse_hist(const char *text, hist_kind_t *kind)
{
    static const struct {
        const char *name;
        hist_kind_t kind;
    } kinds[] = {{"AH", HIST_AH}, {"LAH", HIST_LAH}, {"HAH", HIST_HAH}, {"HTAH", HIST_HTAH}};
    for (size_t k = 0u; k < sizeof kinds / sizeof kinds[0]; k++) {
        if (strcmp(text, kinds[k].name) == 0) {
            *kind = kinds[k].kind;
            return 0;
        }
    }
    return -1;
}

int cmd_replay(const cli_command_t *self, int argc, char **argv)
{
    static ego_loop_config_t config;
    static ego_loop_t loop;
    ego_loop_defaults(&config);
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (cli_is_help(arg)) {
            cli_print_command_usage(self);
            return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
        }
        if (strcmp(arg, "--period") == 0) {
            double s;
            if (value == NULL || parse_double(value, &s) != 0 || s <= 0.0 || s > 10.0) {
                return cli_usage_error(self, "invalid --period", value, "seconds, 0 < S <= 10");
            }
            config.period_us = (uint32_t)lround(s * 1e6);
            i++;
        } else if (strcmp(arg, "--mount") == 0) {
            if (value == NULL || parse_mount(value, &config.ego.prep) != 0) {
                return cli_usage_error(self, "invalid --mount", value, "X,Y,THETA_DEG in m and deg");
            }
            i++;
        } else if (strcmp(arg, "--icp") == 0) {
            config.ego.itcp.weighted = false; /* plain ICP, for comparison */
        } else if (strcmp(arg, "--hist") == 0) {
            if (value == NULL || parse_hist(value, &config.ego.hist.kind) != 0) {
                return cli_usage_error(self, "invalid --hist", value, "AH, LAH, HAH or HTAH");
            }
            i++;
        } else if (strcmp(arg, "--mode") == 0) {
            if (value == NULL || parse_mode(value, &config.ego.prep.meas_mode) != 0) {
                return cli_usage_error(self, "invalid --mode", value, "expected 00..06 or 0F");
            }
            i++;
        } else if (arg[0] == '-' && arg[1] != '\0') {
            return cli_usage_error(self, "unknown option", arg, NULL);
        } else if (path != NULL) {
            return cli_usage_error(self, "unexpected argument", arg, NULL);
        } else {
            path = arg;
        }
    }
    if (path == NULL) {
        return cli_usage_error(self, "missing FILE", NULL, NULL);
    }

    replay_io_t io;
    memset(&io, 0, sizeof io);
    const char *shown = (strcmp(path, "-") == 0) ? "<stdin>" : path;
    const int open_error = stream_file_open(&io.file, path);
    if (open_error != 0) {
        cli_file_error("cannot open ", shown, strerror(open_error));
        return CLI_EXIT_RUNTIME;
    }
    const ego_hal_t hal = {hal_read, hal_write, hal_now_us, &io};
    ego_loop_init(&loop, &config);
    while (ego_loop_step(&loop, &hal) != EGO_LOOP_END) {
    }
    const int read_error = io.file.error;
    stream_file_close(&io.file);
    if (io.failed) {
        cli_file_error("error reading ", shown, strerror(read_error));
        return CLI_EXIT_RUNTIME;
    }
    const ego_loop_stats_t *st = ego_loop_stats(&loop);
    (void)fprintf(stderr,
                  "lmsego: replay: scans=%lu lines=%lu predicted=%lu restarts=%lu "
                  "decode_errors=%lu\n",
                  (unsigned long)st->scans, (unsigned long)st->lines,
                  (unsigned long)st->predicted, (unsigned long)st->restarts,
                  (unsigned long)st->decode_errors);
    if (io.write_failed) {
        cli_error("write error on standard output");
        return CLI_EXIT_RUNTIME;
    }
    return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
}
