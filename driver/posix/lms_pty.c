/* lms_pty.c - see lms_pty.h. */
#include "lms_pty.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include "lms_serial_termios2.h"

static void close_fd(int *fd)
{
    if (*fd >= 0) {
        (void)close(*fd); /* not retried: on Linux the descriptor is gone anyway */
        *fd = -1;
    }
}

static void close_pair(lms_pty_t *pty)
{
    close_fd(&pty->master);
    close_fd(&pty->slave_keep);
    pty->slave_path[0] = '\0';
}

static int add_fd_flags(int fd, int status_flags, int fd_flags)
{
    const int fl = fcntl(fd, F_GETFL);
    if (fl < 0 || fcntl(fd, F_SETFL, fl | status_flags) != 0) {
        return errno;
    }
    const int fdf = fcntl(fd, F_GETFD);
    if (fdf < 0 || fcntl(fd, F_SETFD, fdf | fd_flags) != 0) {
        return errno;
    }
    return 0;
}

/* Raw 8N1 at 9600 (the scanner's power-up rate) from the start, so that
 * nothing the simulator writes is echoed or translated before a driver
 * has configured the line. */
static int make_slave_raw(int fd)
{
    struct termios t;
    if (tcgetattr(fd, &t) != 0) {
        return errno;
    }
    cfmakeraw(&t);
    t.c_cflag |= (tcflag_t)(CLOCAL | CREAD);
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    if (cfsetispeed(&t, B9600) != 0 || cfsetospeed(&t, B9600) != 0) {
        return errno;
    }
    while (tcsetattr(fd, TCSANOW, &t) != 0) {
        if (errno != EINTR) {
            return errno;
        }
    }
    return 0;
}

/* A new master/slave pair in pty->master, pty->slave_keep, pty->slave_path.
 * On failure the caller closes what was opened. */
static int open_pair(lms_pty_t *pty)
{
    int fd;
    do {
        fd = posix_openpt(O_RDWR | O_NOCTTY);
    } while (fd < 0 && errno == EINTR);
    if (fd < 0) {
        return errno;
    }
    pty->master = fd;
    int error = add_fd_flags(fd, O_NONBLOCK, FD_CLOEXEC);
    if (error != 0) {
        return error;
    }
    if (grantpt(fd) != 0 || unlockpt(fd) != 0) {
        return errno;
    }
    error = ptsname_r(fd, pty->slave_path, sizeof pty->slave_path);
    if (error != 0) {
        return error;
    }
    do {
        fd = open(pty->slave_path, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    } while (fd < 0 && errno == EINTR);
    if (fd < 0) {
        return errno;
    }
    pty->slave_keep = fd;
    return make_slave_raw(fd);
}

/* True when path is a symbolic link to target. */
static bool links_to(const char *path, const char *target)
{
    char buf[256]; /* a slave path is shorter; a longer target is not ours */
    const ssize_t n = readlink(path, buf, sizeof buf);
    if (n < 0 || (size_t)n >= sizeof buf) {
        return false;
    }
    buf[n] = '\0';
    return strcmp(buf, target) == 0;
}

/* Points pty->link_path at the slave: a new link under a temporary name,
 * renamed over the old one, so the name never points nowhere. Anything at
 * the name that is not a symbolic link is left alone (EEXIST). */
static int point_link(const lms_pty_t *pty)
{
    if (pty->link_path[0] == '\0') {
        return 0;
    }
    struct stat st;
    if (lstat(pty->link_path, &st) == 0) {
        if (!S_ISLNK(st.st_mode)) {
            return EEXIST;
        }
    } else if (errno != ENOENT) {
        return errno;
    }
    char tmp[sizeof pty->link_path + 32u];
    const int n = snprintf(tmp, sizeof tmp, "%s.%ld.new", pty->link_path, (long)getpid());
    if (n < 0 || (size_t)n >= sizeof tmp) {
        return ENAMETOOLONG;
    }
    if (unlink(tmp) != 0 && errno != ENOENT) { /* left over from a crash */
        return errno;
    }
    if (symlink(pty->slave_path, tmp) != 0) {
        return errno;
    }
    if (rename(tmp, pty->link_path) != 0) {
        const int error = errno;
        (void)unlink(tmp);
        return error;
    }
    return 0;
}

/* Removes the link if it still points at our slave (another simulator may
 * have taken the name over since). */
static void remove_link(const lms_pty_t *pty)
{
    if (pty->link_path[0] != '\0' && pty->slave_path[0] != '\0' &&
        links_to(pty->link_path, pty->slave_path)) {
        (void)unlink(pty->link_path);
    }
}

/* Pair + link, or everything closed again. */
static int start(lms_pty_t *pty)
{
    int error = open_pair(pty);
    if (error == 0) {
        error = point_link(pty);
    }
    if (error != 0) {
        close_pair(pty);
        pty->error = error;
    }
    return error;
}

int lms_pty_open(lms_pty_t *pty, const char *link)
{
    if (pty == NULL) {
        return EINVAL;
    }
    pty->master = -1;
    pty->slave_keep = -1;
    pty->slave_path[0] = '\0';
    pty->link_path[0] = '\0';
    pty->error = 0;
    if (link != NULL) {
        const size_t len = strlen(link);
        if (len >= sizeof pty->link_path) {
            pty->error = ENAMETOOLONG;
            return pty->error;
        }
        (void)memcpy(pty->link_path, link, len + 1u);
    }
    const int error = start(pty);
    if (error != 0) {
        pty->link_path[0] = '\0';
    }
    return error;
}

const char *lms_pty_path(const lms_pty_t *pty)
{
    return (pty->link_path[0] != '\0') ? pty->link_path : pty->slave_path;
}

bool lms_pty_host_baud(const lms_pty_t *pty, lms_baud_t *baud)
{
    if (pty == NULL || baud == NULL || pty->master < 0) {
        return false;
    }
    uint32_t bps = 0u;
#ifdef __linux__
    /* On a master, TCGETS2 answers with the slave's termios. */
    if (lms_termios2_get_speed(pty->master, &bps) != 0) {
        return false;
    }
#else
    struct termios t;
    if (tcgetattr(pty->master, &t) != 0) {
        return false;
    }
    const speed_t code = cfgetospeed(&t);
    if (code == B9600) {
        bps = 9600u;
    } else if (code == B19200) {
        bps = 19200u;
    } else if (code == B38400) {
        bps = 38400u;
#ifdef B500000
    } else if (code == B500000) {
        bps = 500000u;
#endif
    }
#endif
    static const lms_baud_t rates[] = {LMS_BAUD_9600, LMS_BAUD_19200, LMS_BAUD_38400,
                                       LMS_BAUD_500000};
    for (size_t i = 0u; i < sizeof rates / sizeof rates[0]; i++) {
        if (lms_baud_bps(rates[i]) == bps) {
            *baud = rates[i];
            return true;
        }
    }
    return false;
}

int lms_pty_reopen(lms_pty_t *pty)
{
    if (pty == NULL) {
        return EINVAL;
    }
    /* Closing the master hangs up every descriptor of the slave. The link
     * keeps pointing at the dead slave until the new one exists. */
    char old_slave[sizeof pty->slave_path];
    (void)memcpy(old_slave, pty->slave_path, sizeof old_slave);
    close_pair(pty);
    const int error = start(pty);
    if (error != 0 && pty->link_path[0] != '\0') {
        /* The link would point at a dead slave (whose name the kernel may
         * give to somebody else's terminal): the device is missing now. */
        if (old_slave[0] != '\0' && links_to(pty->link_path, old_slave)) {
            (void)unlink(pty->link_path);
        }
        pty->link_path[0] = '\0';
    }
    return error;
}

void lms_pty_close(lms_pty_t *pty)
{
    if (pty == NULL) {
        return;
    }
    remove_link(pty);
    pty->link_path[0] = '\0';
    close_pair(pty);
}
