/* stream_file.h - a recorded byte stream read from a file or stdin in
 * fixed-size chunks (host-only).
 *
 * Memory use does not depend on the input: the caller owns the chunk
 * buffer and reads until STREAM_READ_END. A directory is refused at open
 * time, and a read error in the middle of the file is reported as such
 * (never mistaken for the end of the stream).
 *
 * Two formats, told apart by the first 8 bytes on the first read: a
 * recording (recording.h: magic, then timed blocks), of which only the
 * line's bytes are returned, at most one block's worth per call, with the
 * block's arrival time in time_us; or else a raw stream, returned as is
 * (the peeked bytes first: stdin cannot seek back). A malformed recording
 * is STREAM_READ_ERROR with error EBADMSG and the reason in bad.
 */
#ifndef LMSEGO_STREAM_FILE_H
#define LMSEGO_STREAM_FILE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "recording.h"

/* Chunk size the subcommands read with. */
#define STREAM_FILE_CHUNK 4096u

typedef struct {
    FILE *fp;
    const char *name; /* as given; "-" means stdin */
    int is_stdin;     /* nonzero: fp is stdin and must not be closed */
    int error;        /* errno of the last failure, 0 if none */
    /* Known after the first stream_file_read: */
    int is_recording; /* nonzero: a recording, 0: a raw stream */
    uint64_t time_us; /* recording: arrival time (us) of the block the last
                         bytes returned came from; raw: always 0 */
    const char *bad;  /* malformed recording: why, in words (error is
                         EBADMSG); NULL otherwise */
    uint64_t bad_offset; /* ... and the file offset of the bad block */
    /* Private: */
    int format_known;
    uint8_t peek[RECORDING_MAGIC_SIZE];
    size_t peek_len;
    size_t peek_pos;
    uint64_t offset;     /* recording: bytes consumed from the file */
    size_t block_left;   /* recording: payload bytes not yet returned */
    uint64_t block_offset; /* recording: where the current block starts */
    uint64_t block_time_us;
    int had_block;
} stream_file_t;

typedef enum {
    STREAM_READ_DATA = 0, /* *got > 0 bytes were read */
    STREAM_READ_END = 1,  /* end of the stream, *got == 0 */
    STREAM_READ_ERROR = 2 /* read failed; sf->error holds errno */
} stream_read_t;

/* Opens path for reading ("-" = stdin). Returns 0, or an errno value
 * (EISDIR for a directory) with nothing left open. */
int stream_file_open(stream_file_t *sf, const char *path);

/* Reads up to cap bytes (cap > 0, else STREAM_READ_ERROR with EINVAL)
 * into buf. */
stream_read_t stream_file_read(stream_file_t *sf, uint8_t *buf, size_t cap, size_t *got);

/* Words for the last failure, for a one-line message: for a malformed
 * recording the reason and where ("block time goes backwards at byte 20",
 * formatted into buf of cap bytes), else strerror(error). Still valid
 * after stream_file_close. Callers print it as
 *   (sf->bad != NULL ? "bad recording " : "error reading ") FILE: text. */
const char *stream_file_problem(const stream_file_t *sf, char *buf, size_t cap);

/* Closes the file (never stdin). */
void stream_file_close(stream_file_t *sf);

#endif /* LMSEGO_STREAM_FILE_H */
