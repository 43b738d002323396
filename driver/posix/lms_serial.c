/* lms_serial.c - see lms_serial.h. */
#include "lms_serial.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdbool.h>
#include <string.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "lms_serial_termios2.h"

/* Gap after each byte of a host telegram at 500000 baud (the LMS wants at
 * least 55 us, protocol notes 6.2). */
#define PACE_GAP_NS 60000L

/* A rate read back from the driver may differ by this fraction (1/50 = 2 %,
 * the tolerance of an 8N1 line) before it counts as refused. */
#define BAUD_TOLERANCE_DIV 50u

const char *lms_serial_status_name(lms_serial_status_t status)
{
    switch (status) {
    case LMS_SERIAL_OK:
        return "ok";
    case LMS_SERIAL_TIMEOUT:
        return "timed out";
    case LMS_SERIAL_MISSING:
        return "no such device";
    case LMS_SERIAL_BUSY:
        return "device busy";
    case LMS_SERIAL_DENIED:
        return "permission denied";
    case LMS_SERIAL_NOT_TTY:
        return "not a serial device";
    case LMS_SERIAL_BAUD:
        return "baud rate refused";
    case LMS_SERIAL_HANGUP:
        return "line hung up";
    case LMS_SERIAL_IO:
        return "input/output error";
    }
    return "unknown serial status";
}

static lms_serial_status_t fail(lms_serial_t *port, lms_serial_status_t status, int error)
{
    port->error = (error != 0) ? error : EIO;
    return status;
}

/* errno values that mean the device went away under an open descriptor. */
static bool is_hangup_errno(int error)
{
    return error == EIO || error == ENXIO || error == ENODEV || error == EPIPE;
}

static int64_t now_ms(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0) {
        return 0; /* cannot happen with CLOCK_MONOTONIC; waits then end early */
    }
    return (int64_t)ts.tv_sec * 1000 + (int64_t)(ts.tv_nsec / 1000000L);
}

static int ms_until(int64_t deadline)
{
    const int64_t left = deadline - now_ms();
    if (left <= 0) {
        return 0;
    }
    return (left > 1000000) ? 1000000 : (int)left;
}

/* Line rate: termios2 on Linux, the B constants elsewhere. */
static lms_serial_status_t apply_speed(lms_serial_t *port, uint32_t bps)
{
#ifdef __linux__
    uint32_t actual = 0u;
    const int error = lms_termios2_set_speed(port->fd, bps, &actual);
    if (error != 0) {
        if (is_hangup_errno(error)) {
            return fail(port, LMS_SERIAL_HANGUP, error);
        }
        return fail(port, (error == EINVAL) ? LMS_SERIAL_BAUD : LMS_SERIAL_IO, error);
    }
    const uint32_t diff = (actual > bps) ? actual - bps : bps - actual;
    if (diff > bps / BAUD_TOLERANCE_DIV) {
        return fail(port, LMS_SERIAL_BAUD, EINVAL);
    }
    return LMS_SERIAL_OK;
#else
    speed_t code;
    switch (bps) {
    case 9600u:
        code = B9600;
        break;
    case 19200u:
        code = B19200;
        break;
    case 38400u:
        code = B38400;
        break;
#ifdef B500000
    case 500000u:
        code = B500000;
        break;
#endif
    default:
        return fail(port, LMS_SERIAL_BAUD, EINVAL);
    }
    struct termios t;
    if (tcgetattr(port->fd, &t) != 0) {
        return fail(port, is_hangup_errno(errno) ? LMS_SERIAL_HANGUP : LMS_SERIAL_IO, errno);
    }
    if (cfsetispeed(&t, code) != 0 || cfsetospeed(&t, code) != 0) {
        return fail(port, LMS_SERIAL_BAUD, errno);
    }
    while (tcsetattr(port->fd, TCSANOW, &t) != 0) {
        if (errno != EINTR) {
            return fail(port, (errno == EINVAL) ? LMS_SERIAL_BAUD : LMS_SERIAL_IO, errno);
        }
    }
    /* tcsetattr succeeds when any part of the change took: check. */
    if (tcgetattr(port->fd, &t) != 0) {
        return fail(port, LMS_SERIAL_IO, errno);
    }
    if (cfgetospeed(&t) != code) {
        return fail(port, LMS_SERIAL_BAUD, EINVAL);
    }
    return LMS_SERIAL_OK;
#endif
}

/* Raw 8N1, no flow control, reads never block in the driver. */
static lms_serial_status_t make_raw(lms_serial_t *port)
{
    struct termios t;
    if (tcgetattr(port->fd, &t) != 0) {
        return fail(port, (errno == ENOTTY) ? LMS_SERIAL_NOT_TTY : LMS_SERIAL_IO, errno);
    }
    cfmakeraw(&t);
    t.c_iflag &= ~(tcflag_t)(IXON | IXOFF | IXANY | INPCK | ISTRIP);
    t.c_cflag &= ~(tcflag_t)(CSIZE | PARENB | CSTOPB);
#ifdef CRTSCTS
    t.c_cflag &= ~(tcflag_t)CRTSCTS;
#endif
    t.c_cflag |= (tcflag_t)(CS8 | CLOCAL | CREAD);
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    while (tcsetattr(port->fd, TCSANOW, &t) != 0) {
        if (errno != EINTR) {
            return fail(port, LMS_SERIAL_IO, errno);
        }
    }
    return LMS_SERIAL_OK;
}

static lms_serial_status_t flush_both(lms_serial_t *port)
{
    while (tcflush(port->fd, TCIOFLUSH) != 0) {
        if (errno != EINTR) {
            return fail(port, is_hangup_errno(errno) ? LMS_SERIAL_HANGUP : LMS_SERIAL_IO, errno);
        }
    }
    return LMS_SERIAL_OK;
}

static lms_serial_status_t open_status(int error)
{
    switch (error) {
    case ENOENT:
    case ENODEV:
    case ENXIO:
    case ENOTDIR:
        return LMS_SERIAL_MISSING;
    case EBUSY:
    case EWOULDBLOCK:
        return LMS_SERIAL_BUSY;
    case EACCES:
    case EPERM:
    case EROFS:
        return LMS_SERIAL_DENIED;
    case EISDIR:
    case ENOTTY:
        return LMS_SERIAL_NOT_TTY;
    default:
        return LMS_SERIAL_IO;
    }
}

/* Opens, checks for a terminal and takes the locks. On failure the
 * descriptor is closed here, before any TIOCEXCL of ours: a second opener
 * must not clear the first one's exclusive mode on its way out. */
static lms_serial_status_t open_locked(lms_serial_t *port)
{
    int fd;
    do {
        fd = open(port->path, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    } while (fd < 0 && errno == EINTR);
    if (fd < 0) {
        return fail(port, open_status(errno), errno);
    }

    lms_serial_status_t status = LMS_SERIAL_OK;
    struct termios t;
    if (tcgetattr(fd, &t) != 0) {
        status = fail(port, open_status(errno), errno);
    }
    /* flock as well as TIOCEXCL: TIOCEXCL does not stop root, the lock
     * stops every process that also takes it (lms_serial does). */
    while (status == LMS_SERIAL_OK && flock(fd, LOCK_EX | LOCK_NB) != 0) {
        if (errno != EINTR) {
            status = fail(port, (errno == EWOULDBLOCK) ? LMS_SERIAL_BUSY : LMS_SERIAL_IO, errno);
        }
    }
    if (status == LMS_SERIAL_OK && ioctl(fd, TIOCEXCL) != 0) {
        status = fail(port, LMS_SERIAL_IO, errno);
    }
    if (status != LMS_SERIAL_OK) {
        (void)close(fd);
        return status;
    }
    port->fd = fd;
    return LMS_SERIAL_OK;
}

lms_serial_status_t lms_serial_open(lms_serial_t *port, const char *path, lms_baud_t baud)
{
    if (port == NULL) {
        return LMS_SERIAL_IO;
    }
    port->fd = -1;
    port->baud = baud;
    port->error = 0;
    port->path[0] = '\0';
    if (path == NULL || path[0] == '\0') {
        return fail(port, LMS_SERIAL_MISSING, ENOENT);
    }
    const size_t len = strlen(path);
    if (len >= sizeof port->path) {
        return fail(port, LMS_SERIAL_IO, ENAMETOOLONG);
    }
    (void)memcpy(port->path, path, len + 1u);

    lms_serial_status_t status = open_locked(port);
    if (status == LMS_SERIAL_OK) {
        status = make_raw(port);
    }
    if (status == LMS_SERIAL_OK) {
        status = lms_serial_set_baud(port, baud);
    }
    if (status != LMS_SERIAL_OK) {
        const int error = port->error;
        lms_serial_close(port);
        port->error = error;
    }
    return status;
}

lms_serial_status_t lms_serial_set_baud(lms_serial_t *port, lms_baud_t baud)
{
    if (port == NULL) {
        return LMS_SERIAL_IO;
    }
    if (port->fd < 0) {
        return fail(port, LMS_SERIAL_IO, EBADF);
    }
    const uint32_t bps = lms_baud_bps(baud);
    if (bps == 0u) {
        return fail(port, LMS_SERIAL_BAUD, EINVAL);
    }
    lms_serial_status_t status = apply_speed(port, bps);
    if (status != LMS_SERIAL_OK) {
        return status;
    }
    port->baud = baud;
    /* Whatever is queued was sent or received at the old rate. */
    status = flush_both(port);
    return status;
}

lms_serial_status_t lms_serial_read(lms_serial_t *port, uint8_t *buf, size_t cap,
                                    int timeout_ms, size_t *got)
{
    if (got != NULL) {
        *got = 0u;
    }
    if (port == NULL) {
        return LMS_SERIAL_IO;
    }
    if (buf == NULL || cap == 0u || got == NULL) {
        return fail(port, LMS_SERIAL_IO, EINVAL);
    }
    if (port->fd < 0) {
        return fail(port, LMS_SERIAL_IO, EBADF);
    }
    const int64_t deadline = now_ms() + ((timeout_ms > 0) ? timeout_ms : 0);
    for (;;) {
        struct pollfd p = {port->fd, POLLIN, 0};
        const int n = poll(&p, 1u, ms_until(deadline));
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return fail(port, LMS_SERIAL_IO, errno);
        }
        if (n == 0) {
            return LMS_SERIAL_TIMEOUT;
        }
        if ((p.revents & POLLNVAL) != 0) {
            return fail(port, LMS_SERIAL_IO, EBADF);
        }
        /* POLLIN, POLLHUP or POLLERR: the read tells which. */
        const ssize_t r = read(port->fd, buf, cap);
        if (r > 0) {
            *got = (size_t)r;
            return LMS_SERIAL_OK;
        }
        if (r == 0) {
            /* VMIN 0 gives 0 only when nothing is there, and poll said
             * something was: the line is gone. */
            return fail(port, LMS_SERIAL_HANGUP, EIO);
        }
        const int error = errno;
        if (error == EINTR || error == EAGAIN || error == EWOULDBLOCK) {
            if ((p.revents & POLLHUP) != 0) {
                return fail(port, LMS_SERIAL_HANGUP, EIO);
            }
            if (ms_until(deadline) == 0) {
                return LMS_SERIAL_TIMEOUT; /* woken for nothing, time is up */
            }
            continue;
        }
        return fail(port, is_hangup_errno(error) ? LMS_SERIAL_HANGUP : LMS_SERIAL_IO, error);
    }
}

/* Writes len bytes, waiting for room when the driver's queue is full. */
static lms_serial_status_t write_all(lms_serial_t *port, const uint8_t *buf, size_t len)
{
    size_t done = 0u;
    int64_t deadline = now_ms() + LMS_SERIAL_WRITE_STALL_MS;
    while (done < len) {
        const ssize_t w = write(port->fd, buf + done, len - done);
        if (w > 0) {
            done += (size_t)w;
            deadline = now_ms() + LMS_SERIAL_WRITE_STALL_MS;
            continue;
        }
        const int error = (w == 0) ? EAGAIN : errno;
        if (error == EINTR) {
            continue;
        }
        if (error != EAGAIN && error != EWOULDBLOCK) {
            return fail(port, is_hangup_errno(error) ? LMS_SERIAL_HANGUP : LMS_SERIAL_IO, error);
        }
        const int wait_ms = ms_until(deadline);
        if (wait_ms == 0) {
            return fail(port, LMS_SERIAL_IO, ETIMEDOUT);
        }
        struct pollfd p = {port->fd, POLLOUT, 0};
        const int n = poll(&p, 1u, wait_ms);
        if (n < 0 && errno != EINTR) {
            return fail(port, LMS_SERIAL_IO, errno);
        }
        if (n > 0 && (p.revents & POLLNVAL) != 0) {
            return fail(port, LMS_SERIAL_IO, EBADF);
        }
        if (n > 0 && (p.revents & (POLLHUP | POLLERR)) != 0 && (p.revents & POLLOUT) == 0) {
            return fail(port, LMS_SERIAL_HANGUP, EIO);
        }
    }
    return LMS_SERIAL_OK;
}

/* The inter-byte gap at 500000 baud: wait until the byte has left the
 * driver's queue (tcdrain; a USB adapter may still hold it, which only
 * makes the gap longer), then 60 us more. */
static lms_serial_status_t pace(lms_serial_t *port)
{
    while (tcdrain(port->fd) != 0) {
        if (errno != EINTR) {
            return fail(port, is_hangup_errno(errno) ? LMS_SERIAL_HANGUP : LMS_SERIAL_IO, errno);
        }
    }
    struct timespec left = {0, PACE_GAP_NS};
    while (nanosleep(&left, &left) != 0) {
        if (errno != EINTR) {
            return fail(port, LMS_SERIAL_IO, errno);
        }
    }
    return LMS_SERIAL_OK;
}

lms_serial_status_t lms_serial_write(lms_serial_t *port, const uint8_t *buf, size_t len)
{
    if (port == NULL) {
        return LMS_SERIAL_IO;
    }
    if (len == 0u) {
        return LMS_SERIAL_OK;
    }
    if (buf == NULL) {
        return fail(port, LMS_SERIAL_IO, EINVAL);
    }
    if (port->fd < 0) {
        return fail(port, LMS_SERIAL_IO, EBADF);
    }
    if (port->baud != LMS_BAUD_500000) {
        return write_all(port, buf, len);
    }
    for (size_t i = 0u; i < len; i++) {
        lms_serial_status_t status = write_all(port, buf + i, 1u);
        if (status == LMS_SERIAL_OK) {
            status = pace(port);
        }
        if (status != LMS_SERIAL_OK) {
            return status;
        }
    }
    return LMS_SERIAL_OK;
}

void lms_serial_close(lms_serial_t *port)
{
    if (port == NULL || port->fd < 0) {
        return;
    }
    /* Exclusive mode belongs to the tty, not to this descriptor, and would
     * outlive us on a tty someone else keeps open (a pty's slave). */
    (void)ioctl(port->fd, TIOCNXCL);
    /* close() releases the flock. Not retried on EINTR: on Linux the
     * descriptor is gone either way. */
    (void)close(port->fd);
    port->fd = -1;
}
