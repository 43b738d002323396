/* cmd_frames.c - `lmsego frames FILE`: decodes a captured stream of binary
 * ego-motion frames (ego_frame.h; what `replay --frames` or a firmware
 * with config.frames writes) and prints the CSV of `lmsego replay`, byte
 * for byte: the header before the first line, one line per frame, through
 * the loop's own ego_format_line. FILE '-' is stdin. Corrupt frames and
 * stray bytes are skipped and counted; a summary goes to stderr:
 *
 *   lmsego: frames: frames=N crc_errors=E length_errors=L truncated=T bytes_skipped=B
 *
 * Exit 0 however damaged the stream as long as one frame decodes; 1 when
 * none does (an empty file, or not a frame stream: that line instead of
 * the summary), when it cannot be read or stdout fails; 2 for a bad
 * command line.
 */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "ego_frame.h"
#include "ego_loop.h"
#include "stream_file.h"
#include "stream_frames.h"

/* Prints one decoded frame; false on a write error. */
static bool print_frame(const ego_frame_t *f, bool *header_written)
{
    char line[EGO_LOOP_LINE_MAX];
    const size_t n = ego_format_line(line, sizeof line, f->scan, f->time_us, &f->out);
    if (!*header_written) {
        *header_written = true;
        if (fputs(EGO_LOOP_CSV_HEADER, stdout) == EOF) {
            return false;
        }
    }
    return fwrite(line, 1u, n, stdout) == n;
}

static const char help[] =
    "input:\n"
    "  FILE          binary ego-motion frames (docs/firmware.md, \"Binary ego-motion\n"
    "                frames\") as `lmsego replay --frames OUT` or the firmware write\n"
    "                them, not a telegram stream; '-' reads standard input\n"
    "options: none\n";

static const char help_tail[] =
    "\nstderr: frames=N crc_errors=E length_errors=L truncated=T bytes_skipped=B (damaged\n"
    "  frames and stray bytes are skipped and counted)\n"
    "exit status: 0 ok; 1 no frame decodes (an empty file, or not a frame stream), the\n"
    "  input cannot be read or output failed; 2 bad command line\n";

int cmd_frames(const cli_command_t *self, int argc, char **argv)
{
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            cli_print_command_usage(self, help);
            cli_print_csv_columns("the scan's time the frame carries (replay's time_s)", false);
            (void)fputs(help_tail, stdout);
            return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
        }
        const int rc = cli_take_file(self, argv[i], &path);
        if (rc != CLI_EXIT_OK) {
            return rc;
        }
    }
    if (path == NULL) {
        return cli_usage_error(self, "missing FILE", NULL, NULL);
    }
    const char *shown = (strcmp(path, "-") == 0) ? "<stdin>" : path;
    static stream_file_t file;
    const int open_error = stream_file_open(&file, path);
    if (open_error != 0) {
        cli_file_error("cannot open ", shown, strerror(open_error));
        return CLI_EXIT_RUNTIME;
    }
    static ego_frame_decoder_t dec;
    static uint8_t chunk[STREAM_FILE_CHUNK];
    ego_frame_decoder_init(&dec);
    bool header_written = false;
    bool write_failed = false;
    uint64_t bytes = 0u; /* read */
    stream_read_t r;
    for (;;) { /* ends at the end of the input or a read error */
        size_t got = 0u;
        r = stream_file_read(&file, chunk, sizeof chunk, &got);
        if (r != STREAM_READ_DATA) {
            break;
        }
        bytes += got;
        size_t offset = 0u;
        while (offset < got) { /* each feed uses at least one byte */
            size_t used = 0u;
            ego_frame_t frame;
            if (ego_frame_feed(&dec, &chunk[offset], got - offset, &used, &frame) ==
                    EGO_FRAME_READY &&
                !write_failed) {
                write_failed = !print_frame(&frame, &header_written);
            }
            offset += used;
        }
    }
    ego_frame_flush(&dec);
    stream_file_close(&file);
    if (r == STREAM_READ_ERROR) {
        stream_frames_read_error(&file, shown);
        return CLI_EXIT_RUNTIME;
    }
    const ego_frame_stats_t *st = ego_frame_stats(&dec);
    if (st->frames == 0u) {
        char problem[96];
        (void)snprintf(problem, sizeof problem,
                       "%llu bytes, none a valid frame (a telegram stream? replay reads those)",
                       (unsigned long long)bytes);
        cli_file_error("frames: no frame in ", shown, problem);
        return CLI_EXIT_RUNTIME;
    }
    (void)fprintf(stderr,
                  "lmsego: frames: frames=%lu crc_errors=%lu length_errors=%lu truncated=%lu "
                  "bytes_skipped=%lu\n",
                  (unsigned long)st->frames, (unsigned long)st->crc_errors,
                  (unsigned long)st->length_errors, (unsigned long)st->truncated,
                  (unsigned long)st->bytes_skipped);
    if (write_failed) {
        cli_error("write error");
        return CLI_EXIT_RUNTIME;
    }
    return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
}
