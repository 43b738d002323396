/* cmd_scans.c - `lmsego scans [--mode HEX] FILE`: one line per B0 scan
 * that lms_decode_scan accepts:
 *
 *   <index> <unit_mm> <n> <v1> ... <vn>
 *
 * index counts the printed scans from 0, unit_mm is 1 or 10, and each
 * value is its distance in mm (lms_value_decode in the measuring mode
 * given by --mode, default 00), or for a special value the negative
 * lms_value_kind_t number (-1 no return, -2 dazzle, -3 overflow, -4 low
 * SNR, -5 channel error, -7 beyond max, -8 other reserved codes). Other
 * telegrams, and B0 telegrams the decoder rejects, are skipped silently;
 * a stream without a single scan is an error (stream_frames_no_scan).
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "lms_decode.h"
#include "stream_frames.h"

typedef struct {
    uint8_t meas_mode;
    unsigned long index; /* of the next printed scan */
    unsigned long refused; /* B0 telegrams the decoder rejected */
    lms_scan_t scan;     /* scratch for the decoder */
} scans_print_t;

static int print_scan(void *ctx, const uint8_t *telegram, size_t len, uint64_t time_us)
{
    (void)time_us;
    scans_print_t *p = ctx;
    if (len <= LMS_HEADER_SIZE || telegram[LMS_HEADER_SIZE] != LMS_REPLY_VALUES) {
        return 0;
    }
    if (lms_decode_scan(telegram, len, &p->scan) != LMS_OK) {
        p->refused++;
        return 0;
    }
    const lms_scan_t *scan = &p->scan;
    const unsigned unit_mm = (scan->unit == LMS_UNIT_MM) ? 1u : 10u;
    (void)printf("%lu %u %u", p->index, unit_mm, (unsigned)scan->count);
    for (uint16_t i = 0u; i < scan->count && i < LMS_SCAN_MAX_VALUES; i++) {
        lms_value_t value;
        if (lms_value_decode(scan->values[i], p->meas_mode, scan->unit, &value) != LMS_OK) {
            cli_error("internal error: lms_value_decode refused a checked mode and unit");
            return 1;
        }
        if (value.kind == LMS_VALUE_RANGE) {
            (void)printf(" %lu", (unsigned long)value.distance_mm);
        } else {
            (void)printf(" %d", (int)value.kind);
        }
    }
    (void)putchar('\n');
    p->index++;
    return ferror(stdout) ? 1 : 0;
}

static const char help[] =
    CLI_HELP_STREAM_INPUT
    "options:\n"
    "  --mode HEX    measuring mode the values were taken in: 00..06 or 0F, one or two\n"
    "                hex digits, optional 0x (default 00); it decides which codes are\n"
    "                special values (import-carmen's millimetre streams: 0F)\n"
    "\n"
    "output: one line per B0 scan that decodes, single spaces:\n"
    "  <index> <unit_mm> <n> <v1> ... <vn>\n"
    "  index         counts the printed scans from 0\n"
    "  unit_mm       1 or 10: the unit the scanner sent the values in\n"
    "  n             values in the scan\n"
    "  v1 .. vn      the distance in mm, or a special value: -1 no return, -2 dazzle,\n"
    "                -3 overflow, -4 low SNR, -5 channel error, -7 beyond the maximum\n"
    "                range, -8 another reserved code\n"
    "other telegrams (ACK, replies) and scans that do not decode are skipped\n"
    "\nstderr: a line when the input ends inside a telegram (left out; a recording\n"
    "  stopped by hand does: exit 0)\n"
    "\n" CLI_HELP_EXIT_STATUS;

int cmd_scans(const cli_command_t *self, int argc, char **argv)
{
    const char *path = NULL;
    uint8_t meas_mode = LMS_MEAS_8M_FIELDS_DAZZLE;
    int options_done = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!options_done && strcmp(arg, "--") == 0) {
            options_done = 1;
        } else if (!options_done && cli_is_help(arg)) {
            cli_print_command_usage(self, help);
            return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
        } else if (!options_done && strcmp(arg, "--mode") == 0) {
            if (i + 1 >= argc) {
                return cli_usage_error(self, "--mode needs a value", NULL, NULL);
            }
            i++;
            if (cli_parse_meas_mode(argv[i], &meas_mode) != 0) {
                return cli_usage_error(self, "invalid --mode", argv[i], "expected 00..06 or 0F");
            }
        } else if (!options_done && strncmp(arg, "--mode=", 7u) == 0) {
            if (cli_parse_meas_mode(arg + 7, &meas_mode) != 0) {
                return cli_usage_error(self, "invalid --mode", arg + 7, "expected 00..06 or 0F");
            }
        } else if (!options_done && arg[0] == '-' && arg[1] != '\0') {
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

    static lms_framer_t framer;
    static scans_print_t printer;
    memset(&printer, 0, sizeof printer);
    printer.meas_mode = meas_mode;
    const int rc = stream_frames_run_path(path, &framer, print_scan, &printer);
    if (!cli_finish_stdout()) {
        return CLI_EXIT_RUNTIME;
    }
    const char *shown = (strcmp(path, "-") == 0) ? "<stdin>" : path;
    if (rc == CLI_EXIT_OK && printer.index == 0u) {
        stream_frames_no_scan(self->name, shown, lms_framer_stats(&framer), printer.refused);
        return CLI_EXIT_RUNTIME;
    }
    if (rc == CLI_EXIT_OK && lms_framer_stats(&framer)->truncated > 0u) {
        /* As replay says it: a recording stopped by hand usually ends so. */
        cli_file_error("scans: ", shown, "ends inside a telegram, which is left out");
    }
    return rc;
}
