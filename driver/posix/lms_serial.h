/* lms_serial.h - a serial port for the LMS 2xx through POSIX termios
 * (host-only: with lms_pty and lms_serial_termios2.c, the only code that
 * includes OS headers).
 *
 * Raw 8N1, no flow control, CLOCAL | CREAD, VMIN 0 / VTIME 0, opened
 * O_NONBLOCK | O_NOCTTY and locked for exclusive use (TIOCEXCL and
 * flock(LOCK_EX | LOCK_NB)): a second user gets LMS_SERIAL_BUSY. The four
 * LMS rates; 500000 baud through Linux termios2 / BOTHER (TCSETS2), with
 * the B500000 constant as the fallback where termios2 is missing. Never the
 * ASYNC_SPD_CUST divisor trick (see docs/session.md).
 *
 * Reads wait with poll() up to a timeout. A hang-up (POLLHUP, or read
 * returning EIO or 0 bytes on a readable descriptor) is reported as
 * LMS_SERIAL_HANGUP; the caller closes and reopens the port.
 *
 * Writes: whole buffers, retrying short writes and EAGAIN (poll for
 * POLLOUT); a write that makes no progress for LMS_SERIAL_WRITE_STALL_MS
 * fails with LMS_SERIAL_IO (error ETIMEDOUT), so a stuck line never hangs
 * the caller. At 500000 baud the LMS wants at least 55 us between the bytes
 * of a host telegram: lms_serial_write then writes one byte at a time,
 * draining the output (tcdrain) and waiting 60 us between bytes. Below
 * 500000 it writes the buffer at once.
 *
 * Every call retries EINTR. A NULL buffer (or cap 0 for a read), or a
 * closed port, is LMS_SERIAL_IO with error EINVAL / EBADF (a NULL port: LMS_SERIAL_IO and
 * nothing else). Closing clears TIOCEXCL again (it belongs to the tty and
 * would outlive the descriptor on a tty someone else keeps open).
 */
#ifndef LMS_SERIAL_H
#define LMS_SERIAL_H

#include <stddef.h>
#include <stdint.h>

#include "lms_proto.h"

/* A write that cannot hand a single byte to the driver for this long
 * fails (ms). */
#define LMS_SERIAL_WRITE_STALL_MS 1000

typedef enum {
    LMS_SERIAL_OK = 0,
    LMS_SERIAL_TIMEOUT = 1,    /* read: nothing arrived in time (not an error) */
    LMS_SERIAL_MISSING = -1,   /* no such device (ENOENT, ENODEV, ENXIO) */
    LMS_SERIAL_BUSY = -2,      /* in use by another process (EBUSY, lock held) */
    LMS_SERIAL_DENIED = -3,    /* permission denied */
    LMS_SERIAL_NOT_TTY = -4,   /* not a terminal device */
    LMS_SERIAL_BAUD = -5,      /* the driver refused the rate */
    LMS_SERIAL_HANGUP = -6,    /* the line hung up (cable pulled, pty closed) */
    LMS_SERIAL_IO = -7         /* any other system error; errno kept */
} lms_serial_status_t;

typedef struct {
    int fd;              /* -1 when closed */
    lms_baud_t baud;     /* current rate */
    int error;           /* errno of the last failure, 0 if none */
    char path[256];
} lms_serial_t;

/* One-line English text for a status ("device busy"). */
const char *lms_serial_status_name(lms_serial_status_t status);

/* Opens and configures path at baud, then discards whatever the driver
 * had queued (as lms_serial_set_baud does). On failure nothing stays open
 * and port->error holds the errno (a path of 256 bytes or more:
 * LMS_SERIAL_IO, ENAMETOOLONG). */
lms_serial_status_t lms_serial_open(lms_serial_t *port, const char *path, lms_baud_t baud);

/* Changes the rate (input and output); discards what is buffered in both
 * directions, since those bytes belong to the old rate. Linux: the rate
 * read back must be within 2 % of the one asked for. On LMS_SERIAL_BAUD
 * the line's rate is undefined (port->baud keeps the old value): set one
 * again. */
lms_serial_status_t lms_serial_set_baud(lms_serial_t *port, lms_baud_t baud);

/* Waits up to timeout_ms (0 or negative: do not wait) and reads what is
 * there, up to cap bytes (cap > 0). *got = bytes read. LMS_SERIAL_TIMEOUT
 * with *got 0 when nothing came. */
lms_serial_status_t lms_serial_read(lms_serial_t *port, uint8_t *buf, size_t cap,
                                    int timeout_ms, size_t *got);

/* Writes all len bytes (paced at 500000 baud, see above). */
lms_serial_status_t lms_serial_write(lms_serial_t *port, const uint8_t *buf, size_t len);

/* Closes the port (releases the lock). Safe on a closed port. */
void lms_serial_close(lms_serial_t *port);

#endif /* LMS_SERIAL_H */
