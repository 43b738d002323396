/* stream_file.c - see stream_file.h. POSIX is used for two things only:
 * fstat() to refuse directories, which fopen() happily opens on Linux, and
 * the errno EBADMSG for a malformed recording. The build defines
 * _POSIX_C_SOURCE (firmware/host/CMakeLists.txt). */
#include "stream_file.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

int stream_file_open(stream_file_t *sf, const char *path)
{
    (void)memset(sf, 0, sizeof *sf);
    sf->fp = NULL;
    sf->name = path;
    sf->bad = NULL;

    if (strcmp(path, "-") == 0) {
        sf->fp = stdin;
        sf->is_stdin = 1;
    } else {
        errno = 0;
        sf->fp = fopen(path, "rb");
        if (sf->fp == NULL) {
            sf->error = (errno != 0) ? errno : EIO;
            return sf->error;
        }
    }

    struct stat st;
    if (fstat(fileno(sf->fp), &st) != 0) {
        sf->error = errno;
    } else if (S_ISDIR(st.st_mode)) {
        sf->error = EISDIR;
    }
    if (sf->error != 0) {
        const int error = sf->error;
        stream_file_close(sf);
        sf->error = error;
        return error;
    }
    return 0;
}

/* fread that records a stdio failure in sf->error; returns the count. */
static size_t read_some(stream_file_t *sf, uint8_t *buf, size_t n)
{
    errno = 0;
    const size_t got = fread(buf, 1u, n, sf->fp);
    if (ferror(sf->fp)) {
        sf->error = (errno != 0) ? errno : EIO;
    }
    return got;
}

/* The first 8 bytes decide the format. */
static void detect(stream_file_t *sf)
{
    sf->peek_len = read_some(sf, sf->peek, sizeof sf->peek);
    sf->peek_pos = 0u;
    sf->format_known = 1;
    if (sf->error == 0 && recording_is_magic(sf->peek, sf->peek_len)) {
        sf->is_recording = 1;
        sf->peek_len = 0u;
        sf->offset = RECORDING_MAGIC_SIZE;
    }
}

static stream_read_t read_raw(stream_file_t *sf, uint8_t *buf, size_t cap, size_t *got)
{
    size_t n = sf->peek_len - sf->peek_pos;
    if (n > cap) {
        n = cap;
    }
    (void)memcpy(buf, sf->peek + sf->peek_pos, n);
    sf->peek_pos += n;
    if (n < cap && sf->error == 0) {
        n += read_some(sf, buf + n, cap - n);
    }
    *got = n;
    if (sf->error != 0) {
        /* Bytes read before the failure are still given out and the error
         * is reported on the next call. */
        return (n > 0u) ? STREAM_READ_DATA : STREAM_READ_ERROR;
    }
    return (n > 0u) ? STREAM_READ_DATA : STREAM_READ_END;
}

static stream_read_t malformed(stream_file_t *sf, const char *why, uint64_t at)
{
    sf->error = EBADMSG;
    sf->bad = why;
    sf->bad_offset = at;
    return STREAM_READ_ERROR;
}

static stream_read_t read_recording(stream_file_t *sf, uint8_t *buf, size_t cap, size_t *got)
{
    if (sf->block_left == 0u) {
        uint8_t header[RECORDING_HEADER_SIZE];
        const size_t n = read_some(sf, header, sizeof header);
        if (sf->error != 0) {
            return STREAM_READ_ERROR;
        }
        if (n == 0u) {
            return STREAM_READ_END; /* after a whole block: a clean end */
        }
        const uint64_t at = sf->offset;
        if (n < sizeof header) {
            return malformed(sf, "block header cut short", at);
        }
        uint64_t time_us = 0u;
        uint16_t len = 0u;
        recording_get_header(header, &time_us, &len);
        if (len == 0u) {
            return malformed(sf, "block of length 0", at);
        }
        if (len > RECORDING_BLOCK_MAX) {
            return malformed(sf, "block longer than 4096 bytes", at);
        }
        if (sf->had_block && time_us < sf->block_time_us) {
            return malformed(sf, "block time goes backwards", at);
        }
        sf->offset += sizeof header;
        sf->block_offset = at;
        sf->had_block = 1;
        sf->block_time_us = time_us;
        sf->block_left = len;
    }
    const size_t want = (cap < sf->block_left) ? cap : sf->block_left;
    const size_t n = read_some(sf, buf, want);
    *got = n;
    sf->block_left -= n;
    sf->offset += n;
    if (n > 0u) {
        sf->time_us = sf->block_time_us;
    }
    if (sf->error == 0 && n < want) {
        /* The bytes that are there are real line bytes: give them out and
         * refuse on the next call. */
        (void)malformed(sf, "block cut short", sf->block_offset);
    }
    if (sf->error != 0) {
        return (n > 0u) ? STREAM_READ_DATA : STREAM_READ_ERROR;
    }
    return STREAM_READ_DATA;
}

stream_read_t stream_file_read(stream_file_t *sf, uint8_t *buf, size_t cap, size_t *got)
{
    *got = 0u;
    if (sf->error != 0) {
        return STREAM_READ_ERROR; /* an earlier read failed: no retry */
    }
    if (cap == 0u || buf == NULL || sf->fp == NULL) {
        sf->error = (sf->fp == NULL) ? EBADF : EINVAL;
        return STREAM_READ_ERROR;
    }
    if (!sf->format_known) {
        detect(sf);
        if (sf->error != 0) {
            return STREAM_READ_ERROR;
        }
    }
    return sf->is_recording ? read_recording(sf, buf, cap, got) : read_raw(sf, buf, cap, got);
}

const char *stream_file_problem(const stream_file_t *sf, char *buf, size_t cap)
{
    if (sf->bad == NULL || buf == NULL || cap == 0u) {
        return strerror(sf->error);
    }
    (void)snprintf(buf, cap, "%s at byte %llu", sf->bad, (unsigned long long)sf->bad_offset);
    return buf;
}

void stream_file_close(stream_file_t *sf)
{
    if (sf->fp != NULL && !sf->is_stdin) {
        (void)fclose(sf->fp);
    }
    sf->fp = NULL;
}
