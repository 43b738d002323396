/* stream_frames.h - runs a recorded stream through lms_framer (host-only).
 *
 * Reads the file in STREAM_FILE_CHUNK-byte chunks, feeds every byte to the
 * framer, flushes it at the end of the input until it has nothing left,
 * and hands every CRC-valid telegram to a callback. The other framer
 * events (ACK, NAK, CRC / length errors, truncation) are only counted, in
 * the framer's own statistics.
 */
#ifndef LMSEGO_STREAM_FRAMES_H
#define LMSEGO_STREAM_FRAMES_H

#include <stddef.h>
#include <stdint.h>

#include "lms_framer.h"
#include "stream_file.h"

/* Called for each telegram (STX .. CRC, valid until the callback returns).
 * time_us: in a recording, the arrival time of the block that held the
 * telegram's last byte; 0 in a raw stream. Return 0 to go on, nonzero to
 * stop reading. */
typedef int (*stream_telegram_fn)(void *ctx, const uint8_t *telegram, size_t len,
                                  uint64_t time_us);

typedef enum {
    STREAM_FRAMES_DONE = 0,       /* the whole input was read and flushed */
    STREAM_FRAMES_READ_ERROR = 1, /* reading failed; in->error holds errno */
    STREAM_FRAMES_STOPPED = 2,    /* the callback asked to stop */
    STREAM_FRAMES_STUCK = 3       /* the framer broke its contract (no progress) */
} stream_frames_result_t;

/* framer must be initialised (lms_framer_init) by the caller, who reads
 * the statistics afterwards. */
stream_frames_result_t stream_frames_run(stream_file_t *in, lms_framer_t *framer,
                                         stream_telegram_fn on_telegram, void *ctx);

/* The whole job of a subcommand that reads one FILE: opens path ("-" =
 * stdin), initialises framer for the scanner direction, runs it and
 * closes the file. Problems are reported on stderr as one line naming the
 * file. Returns CLI_EXIT_OK, or CLI_EXIT_RUNTIME when the file could not
 * be opened or read, or the callback stopped the run. */
int stream_frames_run_path(const char *path, lms_framer_t *framer, stream_telegram_fn on_telegram,
                           void *ctx);

/* The one-line message for a read of in that failed (STREAM_READ_ERROR):
 * "bad recording 'FILE': <why, where>" for a malformed recording, else
 * "error reading 'FILE': <errno text>". shown is the name to print. */
void stream_frames_read_error(const stream_file_t *in, const char *shown);

/* The one-line message for a stream read to its end without a single
 * scan: "<cmd>: no scan in 'FILE': N bytes, no valid LMS telegram" (an
 * empty file, noise, zeros), or how many telegrams there were and how many
 * B0 telegrams were refused (refused). The commands that exist to print
 * scans or their motion exit CLI_EXIT_RUNTIME after it: an empty output
 * with exit 0 would look like success. */
void stream_frames_no_scan(const char *cmd, const char *shown, const lms_framer_stats_t *st,
                           unsigned long refused);

#endif /* LMSEGO_STREAM_FRAMES_H */
