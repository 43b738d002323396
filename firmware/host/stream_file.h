/* stream_file.h - a recorded byte stream read from a file or stdin in
 * fixed-size chunks (host-only).
 *
 * Memory use does not depend on the input: the caller owns the chunk
 * buffer and reads until STREAM_READ_END. A directory is refused at open
 * time, and a read error in the middle of the file is reported as such
 * (never mistaken for the end of the stream).
 */
#ifndef LMSEGO_STREAM_FILE_H
#define LMSEGO_STREAM_FILE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Chunk size the subcommands read with. */
#define STREAM_FILE_CHUNK 4096u

typedef struct {
    FILE *fp;
    const char *name; /* as given; "-" means stdin */
    int is_stdin;     /* nonzero: fp is stdin and must not be closed */
    int error;        /* errno of the last failure, 0 if none */
} stream_file_t;

typedef enum {
    STREAM_READ_DATA = 0, /* *got > 0 bytes were read */
    STREAM_READ_END = 1,  /* end of the stream, *got == 0 */
    STREAM_READ_ERROR = 2 /* read failed; sf->error holds errno */
} stream_read_t;

/* Opens path for reading ("-" = stdin). Returns 0, or an errno value
 * (EISDIR for a directory) with nothing left open. */
int stream_file_open(stream_file_t *sf, const char *path);

/* Reads up to cap bytes into buf. */
stream_read_t stream_file_read(stream_file_t *sf, uint8_t *buf, size_t cap, size_t *got);

/* Closes the file (never stdin). */
void stream_file_close(stream_file_t *sf);

#endif /* LMSEGO_STREAM_FILE_H */
