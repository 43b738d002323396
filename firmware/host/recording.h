/* recording.h - the recording file format: the raw bytes read from a
 * scanner's serial line, with their arrival times (host-only).
 *
 * Format ("LMSREC1"), all integers little-endian:
 *
 *   magic   8 bytes   "LMSREC1\n" (4C 4D 53 52 45 43 31 0A)
 *   then blocks, each:
 *     time_us   u64   arrival time of the block's bytes, microseconds
 *                     since the recording started; never less than the
 *                     previous block's time
 *     length    u16   1 .. RECORDING_BLOCK_MAX (4096)
 *     bytes     length bytes exactly as read from the line
 *
 * The file ends after the last complete block; there is no trailer, so a
 * recording cut short by a crash still reads up to its last whole block.
 * A file that does not start with the magic is a raw stream (the line's
 * bytes with no times), which every reader also accepts: the LMS never
 * sends "LMSREC1\n" as the first bytes of a stream (a telegram starts with
 * STX 0x02, an ACK/NAK is 0x06/0x15).
 *
 * Readers (stream_file.c) refuse a block whose header or bytes are cut
 * short, whose length is 0 or above 4096, or whose time is less than the
 * previous block's: the error is EBADMSG, with the reason in words.
 *
 * The writer below wraps a stdio FILE: one fwrite per block header and one
 * per payload, so memory use is constant.
 */
#ifndef LMSEGO_RECORDING_H
#define LMSEGO_RECORDING_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define RECORDING_MAGIC "LMSREC1\n"
#define RECORDING_MAGIC_SIZE 8u
/* Block header: time_us (8) + length (2). */
#define RECORDING_HEADER_SIZE 10u
/* Largest block payload; longer appends are split. */
#define RECORDING_BLOCK_MAX 4096u

typedef struct {
    FILE *fp;             /* NULL when closed */
    uint64_t last_time_us; /* time of the last block written */
    int error;            /* errno of the first failure, 0 if none; sticky */
} recording_writer_t;

/* Creates (or truncates) path and writes the magic. Returns 0, or an errno
 * value with nothing left open. */
int recording_writer_open(recording_writer_t *w, const char *path);

/* Appends len bytes that arrived at time_us (microseconds since the
 * recording started): one block, or several of at most RECORDING_BLOCK_MAX
 * bytes with the same time. len 0 writes nothing. Returns 0, or an errno
 * value: EINVAL for a time below the previous block's or a NULL buffer
 * (nothing written; the writer stays usable), else the write error, which
 * is sticky (every later call returns it). */
int recording_writer_append(recording_writer_t *w, uint64_t time_us, const uint8_t *bytes,
                            size_t len);

/* Hands buffered blocks to the OS (fflush). 0 or an errno value (sticky). */
int recording_writer_flush(recording_writer_t *w);

/* Closes the file. Returns 0 when every block reached the OS, else the
 * first errno seen (a failed append, flush or fclose). Safe on a closed
 * writer (returns its last error). */
int recording_writer_close(recording_writer_t *w);

/* Block header encoding, shared with the reader. */
void recording_put_header(uint8_t out[RECORDING_HEADER_SIZE], uint64_t time_us, uint16_t len);
void recording_get_header(const uint8_t in[RECORDING_HEADER_SIZE], uint64_t *time_us,
                          uint16_t *len);

/* True when the n bytes at p are the full magic. */
bool recording_is_magic(const uint8_t *p, size_t n);

#endif /* LMSEGO_RECORDING_H */
