/* lms_serial_termios2.c - see lms_serial_termios2.h. Includes only the
 * kernel's termbits and <sys/ioctl.h>, never <termios.h>. */
#include "lms_serial_termios2.h"

#include <errno.h>

#ifdef __linux__

#include <asm/termbits.h>
#include <sys/ioctl.h>

static int get2(int fd, struct termios2 *t)
{
    for (;;) {
        if (ioctl(fd, TCGETS2, t) == 0) {
            return 0;
        }
        if (errno != EINTR) {
            return errno;
        }
    }
}

int lms_termios2_get_speed(int fd, uint32_t *bps)
{
    struct termios2 t;
    const int error = get2(fd, &t);
    if (error == 0) {
        *bps = (uint32_t)t.c_ospeed;
    }
    return error;
}

int lms_termios2_set_speed(int fd, uint32_t bps, uint32_t *actual)
{
    struct termios2 t;
    int error = get2(fd, &t);
    if (error != 0) {
        return error;
    }
    tcflag_t code;
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
    default:
        code = BOTHER;
        break;
    }
    /* Both the output (CBAUD) and the input (CIBAUD) field: an input field
     * left at an old BOTHER would keep the old input rate. */
    t.c_cflag &= ~(tcflag_t)(CBAUD | ((tcflag_t)CBAUD << IBSHIFT));
    t.c_cflag |= code | (code << IBSHIFT);
    t.c_ispeed = (speed_t)bps;
    t.c_ospeed = (speed_t)bps;
    for (;;) {
        if (ioctl(fd, TCSETS2, &t) == 0) {
            break;
        }
        if (errno != EINTR) {
            return errno;
        }
    }
    return lms_termios2_get_speed(fd, actual);
}

#else /* not Linux: no termios2 */

int lms_termios2_get_speed(int fd, uint32_t *bps)
{
    (void)fd;
    (void)bps;
    return ENOTSUP;
}

int lms_termios2_set_speed(int fd, uint32_t bps, uint32_t *actual)
{
    (void)fd;
    (void)bps;
    (void)actual;
    return ENOTSUP;
}

#endif
