/* stream_file.c - see stream_file.h. POSIX is used for one thing only:
 * fstat() to refuse directories, which fopen() happily opens on Linux.
 * The build defines _POSIX_C_SOURCE (firmware/host/CMakeLists.txt). */
#include "stream_file.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

int stream_file_open(stream_file_t *sf, const char *path)
{
    sf->fp = NULL;
    sf->name = path;
    sf->is_stdin = 0;
    sf->error = 0;

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

stream_read_t stream_file_read(stream_file_t *sf, uint8_t *buf, size_t cap, size_t *got)
{
    *got = 0u;
    if (sf->error != 0) {
        return STREAM_READ_ERROR; /* an earlier read failed: no retry */
    }
    errno = 0;
    *got = fread(buf, 1u, cap, sf->fp);
    if (ferror(sf->fp)) {
        /* Keep errno now; bytes read before the failure are still given out
         * and the error is reported on the next call. */
        sf->error = (errno != 0) ? errno : EIO;
        return (*got > 0u) ? STREAM_READ_DATA : STREAM_READ_ERROR;
    }
    return (*got > 0u) ? STREAM_READ_DATA : STREAM_READ_END;
}

void stream_file_close(stream_file_t *sf)
{
    if (sf->fp != NULL && !sf->is_stdin) {
        (void)fclose(sf->fp);
    }
    sf->fp = NULL;
}
