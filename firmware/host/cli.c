/* cli.c - see cli.h. */
#include "cli.h"

#include "lms_proto.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Writes text to stderr with bytes outside printable ASCII shown as '?'. */
static void put_printable(const char *text)
{
    for (const char *p = text; *p != '\0'; p++) {
        const unsigned char c = (unsigned char)*p;
        (void)fputc((c >= 0x20u && c < 0x7Fu) ? (int)c : '?', stderr);
    }
}

void cli_error(const char *text)
{
    (void)fputs("lmsego: ", stderr);
    put_printable(text);
    (void)fputc('\n', stderr);
}

void cli_file_error(const char *context, const char *file, const char *problem)
{
    (void)fputs("lmsego: ", stderr);
    put_printable(context);
    (void)fputc('\'', stderr);
    put_printable(file);
    (void)fputs("': ", stderr);
    put_printable(problem);
    (void)fputc('\n', stderr);
}

int cli_usage_error(const cli_command_t *cmd, const char *problem, const char *arg,
                    const char *detail)
{
    (void)fputs("lmsego: ", stderr);
    if (cmd != NULL) {
        put_printable(cmd->name);
        (void)fputs(": ", stderr);
    }
    put_printable(problem);
    if (arg != NULL) {
        (void)fputs(" '", stderr);
        put_printable(arg);
        (void)fputc('\'', stderr);
    }
    if (detail != NULL) {
        (void)fputs(" (", stderr);
        put_printable(detail);
        (void)fputc(')', stderr);
    }
    (void)fputs("; try 'lmsego ", stderr);
    if (cmd != NULL) {
        put_printable(cmd->name);
        (void)fputc(' ', stderr);
    }
    (void)fputs("--help'\n", stderr);
    return CLI_EXIT_USAGE;
}

void cli_print_command_usage(const cli_command_t *cmd, const char *help)
{
    (void)printf("usage: lmsego %s %s\n  %s\n", cmd->name, cmd->synopsis, cmd->summary);
    if (help != NULL) {
        (void)printf("\n%s", help);
    }
}

void cli_print_csv_columns(const char *time_text, bool latency)
{
    (void)printf(
        "\noutput: CSV on stdout, a header line, then one line per scan after the first:\n"
        "  scan          scan index, counted from 0 (the first scan has no line)\n"
        "  time_s        s: %s\n"
        "  dx_m, dy_m    m: this scan's position in the frame of the previous scan\n"
        "  dtheta_rad    rad, in [-pi, pi): its heading there (counter-clockwise)\n"
        "  vx_mps, vy_mps, omega_radps\n"
        "                m/s, m/s, rad/s: the motion over the time since the previous line's scan\n"
        "  flags         EGO_FLAG_* bits (estimator/ego.h), summed: 1 first scan, reset or\n"
        "                gap (no motion), 2 aperture (a corridor), 4 not converged, 8 low\n"
        "                correlation, 16 too few points, 32 predicted (not matched), 64\n"
        "                recovering (a search runs), 128 recovered, 256 weak rotation, 512\n"
        "                weak translation (a corridor's length: the covariance's largest\n"
        "                axis), 1024 weak translation with a turn, 2048 suspect (a speed\n"
        "                change beyond 1.5 g, a speed over 150 m/s, or a search's answer\n"
        "                holding under half the scan), 4096 on objects (the motion along a\n"
        "                direction rests on short things standing in front, such as the\n"
        "                backs of vehicles, which may be moving: 1 m^2 more variance along\n"
        "                it); docs/estimator.md, \"Trust\"\n"
        "  iterations    registration iterations\n"
        "  matches       matched point pairs\n"
        "  cov_xx, cov_xy, cov_xt, cov_yy, cov_yt, cov_tt\n"
        "                m^2, m^2, m rad, m^2, m rad, rad^2: covariance of (dx, dy, dtheta); inf:\n"
        "                not measured (the velocities' is this over dt^2)\n",
        time_text);
    if (latency) {
        (void)puts("  latency_ms    ms: the clock when the line was written less time_s");
    }
}

bool cli_is_help(const char *arg)
{
    return strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0;
}

bool cli_finish_stdout(void)
{
    if (fflush(stdout) != 0 || ferror(stdout)) {
        cli_error("error writing standard output");
        return false;
    }
    return true;
}

int cli_parse_meas_mode(const char *text, uint8_t *mode)
{
    if (text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
        text += 2;
    }
    const size_t digits = strlen(text);
    if (digits == 0u || digits > 2u) {
        return -1;
    }
    unsigned value = 0u;
    for (size_t i = 0u; i < digits; i++) {
        const char c = text[i];
        unsigned digit;
        if (c >= '0' && c <= '9') {
            digit = (unsigned)(c - '0');
        } else if (c >= 'a' && c <= 'f') {
            digit = (unsigned)(c - 'a') + 10u;
        } else if (c >= 'A' && c <= 'F') {
            digit = (unsigned)(c - 'A') + 10u;
        } else {
            return -1;
        }
        value = value * 16u + digit;
    }
    if (value > (unsigned)LMS_MEAS_32M_FIELD_A && value != (unsigned)LMS_MEAS_32M_IMMEDIATE) {
        return -1;
    }
    *mode = (uint8_t)value;
    return 0;
}

int cli_take_file(const cli_command_t *cmd, const char *arg, const char **path)
{
    if (arg[0] == '-' && arg[1] != '\0') {
        return cli_usage_error(cmd, "unknown option", arg, NULL);
    }
    if (*path != NULL) {
        return cli_usage_error(cmd, "unexpected argument", arg, NULL);
    }
    *path = arg;
    return CLI_EXIT_OK;
}

int cli_parse_whole(const char *text, unsigned long min, unsigned long max, unsigned long *out)
{
    if (text == NULL || text[0] < '0' || text[0] > '9') {
        return -1;
    }
    char *end = NULL;
    errno = 0;
    const unsigned long k = strtoul(text, &end, 10);
    if (*end != '\0' || errno != 0 || k < min || k > max) {
        return -1;
    }
    *out = k;
    return 0;
}

/* A finite double from text, the whole text. */
int cli_parse_double(const char *text, double *out)
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
int cli_parse_mount(const char *text, ego_lms_params_t *lms)
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
    if (cli_parse_double(parts[0], &x) != 0 || cli_parse_double(parts[1], &y) != 0 ||
        cli_parse_double(parts[2], &deg) != 0 || fabs(x) > 100.0 || fabs(y) > 100.0) {
        return -1;
    }
    lms->mount_x = (fx_q16_16_t)lround(x * 65536.0);
    lms->mount_y = (fx_q16_16_t)lround(y * 65536.0);
    double turns = deg / 360.0;
    turns -= floor(turns);
    lms->mount_theta = (fx_bam32_t)(uint64_t)llround(turns * 4294967296.0);
    return 0;
}
