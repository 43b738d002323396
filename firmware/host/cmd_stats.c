/* cmd_stats.c - `lmsego stats FILE`: runs the stream through the framer
 * and the B0 decoder and prints one line of counters:
 *
 *   telegrams=N scans=S crc_errors=E length_errors=L bytes_skipped=B
 *   resyncs=R truncated=T acks=A naks=K bytes=X decode_errors=D
 *
 * (one line, single spaces). Everything except scans and decode_errors is
 * the framer's own statistics; scans counts the B0 telegrams that
 * lms_decode_scan accepts, decode_errors those it rejects.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "lms_decode.h"
#include "stream_frames.h"

typedef struct {
    uint32_t scans;
    uint32_t decode_errors;
    lms_scan_t scan; /* scratch for the decoder */
} stats_count_t;

static int count_telegram(void *ctx, const uint8_t *telegram, size_t len, uint64_t time_us)
{
    (void)time_us;
    stats_count_t *count = ctx;
    if (len <= LMS_HEADER_SIZE || telegram[LMS_HEADER_SIZE] != LMS_REPLY_VALUES) {
        return 0;
    }
    if (lms_decode_scan(telegram, len, &count->scan) == LMS_OK) {
        count->scans++;
    } else {
        count->decode_errors++;
    }
    return 0;
}

static const char help[] =
    CLI_HELP_STREAM_INPUT
    "options: none\n"
    "\n"
    "output: one line of counters, single spaces:\n"
    "  telegrams=N scans=S crc_errors=E length_errors=L bytes_skipped=B resyncs=R\n"
    "  truncated=T acks=A naks=K bytes=X decode_errors=D\n"
    "  telegrams     CRC-valid telegrams       scans          B0 scans that decode\n"
    "  crc_errors    telegrams with a bad CRC  length_errors  impossible length fields\n"
    "  bytes_skipped bytes in no telegram      resyncs        telegrams after skipped bytes\n"
    "  truncated     telegrams cut short by the end of the input\n"
    "  acks, naks    lone 06 and 15 bytes      bytes          bytes read\n"
    "  decode_errors B0 telegrams that do not decode\n"
    "a stream without telegrams is no error here: its counters say so\n"
    "\n"
    "exit status: 0 ok; 1 the input cannot be read or output failed; 2 bad command line\n";

int cmd_stats(const cli_command_t *self, int argc, char **argv)
{
    const char *path = NULL;
    int options_done = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!options_done && strcmp(arg, "--") == 0) {
            options_done = 1;
        } else if (!options_done && cli_is_help(arg)) {
            cli_print_command_usage(self, help);
            return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
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
    static stats_count_t count;
    memset(&count, 0, sizeof count);
    const int rc = stream_frames_run_path(path, &framer, count_telegram, &count);
    if (rc != CLI_EXIT_OK) {
        return rc;
    }

    const lms_framer_stats_t *st = lms_framer_stats(&framer);
    (void)printf("telegrams=%lu scans=%lu crc_errors=%lu length_errors=%lu bytes_skipped=%lu"
                 " resyncs=%lu truncated=%lu acks=%lu naks=%lu bytes=%lu decode_errors=%lu\n",
                 (unsigned long)st->telegrams, (unsigned long)count.scans,
                 (unsigned long)st->crc_errors, (unsigned long)st->length_errors,
                 (unsigned long)st->bytes_skipped, (unsigned long)st->resyncs,
                 (unsigned long)st->truncated, (unsigned long)st->acks, (unsigned long)st->naks,
                 (unsigned long)st->bytes_in, (unsigned long)count.decode_errors);
    return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
}
