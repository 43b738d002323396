/* recording.c - see recording.h. */
#include "recording.h"

#include <errno.h>
#include <string.h>

void recording_put_header(uint8_t out[RECORDING_HEADER_SIZE], uint64_t time_us, uint16_t len)
{
    for (unsigned i = 0u; i < 8u; i++) {
        out[i] = (uint8_t)(time_us >> (8u * i));
    }
    out[8] = (uint8_t)(len & 0xFFu);
    out[9] = (uint8_t)(len >> 8);
}

void recording_get_header(const uint8_t in[RECORDING_HEADER_SIZE], uint64_t *time_us,
                          uint16_t *len)
{
    uint64_t t = 0u;
    for (unsigned i = 8u; i > 0u; i--) {
        t = (t << 8) | in[i - 1u];
    }
    *time_us = t;
    *len = (uint16_t)(in[8] | ((unsigned)in[9] << 8));
}

bool recording_is_magic(const uint8_t *p, size_t n)
{
    return n == RECORDING_MAGIC_SIZE && memcmp(p, RECORDING_MAGIC, RECORDING_MAGIC_SIZE) == 0;
}

/* Remembers the first failure; errno 0 (a stdio that set none) is EIO. */
static int failed(recording_writer_t *w, int error)
{
    if (w->error == 0) {
        w->error = (error != 0) ? error : EIO;
    }
    return w->error;
}

static int put(recording_writer_t *w, const void *p, size_t n)
{
    errno = 0;
    if (fwrite(p, 1u, n, w->fp) != n) {
        return failed(w, errno);
    }
    return 0;
}

int recording_writer_open(recording_writer_t *w, const char *path)
{
    w->fp = NULL;
    w->last_time_us = 0u;
    w->error = 0;
    errno = 0;
    w->fp = fopen(path, "wb");
    if (w->fp == NULL) {
        return failed(w, errno);
    }
    if (put(w, RECORDING_MAGIC, RECORDING_MAGIC_SIZE) != 0) {
        const int error = w->error;
        (void)fclose(w->fp);
        w->fp = NULL;
        return error;
    }
    return 0;
}

int recording_writer_append(recording_writer_t *w, uint64_t time_us, const uint8_t *bytes,
                            size_t len)
{
    if (w->error != 0) {
        return w->error;
    }
    if (w->fp == NULL) {
        return EBADF; /* not sticky: a caller bug, not a lost block */
    }
    if (len == 0u) {
        return 0;
    }
    if (bytes == NULL || time_us < w->last_time_us) {
        return EINVAL; /* nothing written, the file is still well formed */
    }
    w->last_time_us = time_us;
    size_t done = 0u;
    while (done < len) {
        const size_t n = (len - done < RECORDING_BLOCK_MAX) ? len - done : RECORDING_BLOCK_MAX;
        uint8_t header[RECORDING_HEADER_SIZE];
        recording_put_header(header, time_us, (uint16_t)n);
        if (put(w, header, sizeof header) != 0 || put(w, bytes + done, n) != 0) {
            return w->error;
        }
        done += n;
    }
    return 0;
}

int recording_writer_flush(recording_writer_t *w)
{
    if (w->error != 0 || w->fp == NULL) {
        return w->error;
    }
    errno = 0;
    if (fflush(w->fp) != 0) {
        return failed(w, errno);
    }
    return 0;
}

int recording_writer_close(recording_writer_t *w)
{
    if (w->fp == NULL) {
        return w->error;
    }
    errno = 0;
    const int rc = fclose(w->fp);
    w->fp = NULL;
    if (rc != 0) {
        (void)failed(w, errno);
    }
    return w->error;
}
