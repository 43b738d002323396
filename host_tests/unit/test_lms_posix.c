/* test_lms_posix.c - the POSIX serial port (lms_serial.h) over real
 * pseudo-terminals made by lms_pty.h: every LMS rate set by the port and
 * read back from the master (termios2 on Linux, 500000 included), bytes
 * both ways, timeouts, exclusive access, refusals (missing path, not a
 * terminal), stale input discarded on a rate change, and a hang-up and
 * reconnect through the link.
 *
 * No sleeps for synchronisation: every wait is a poll() with a timeout,
 * and a timeout fails the test.
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "lms_pty.h"
#include "lms_serial.h"
#include "unity.h"

/* Generous: only a broken implementation waits this long. */
#define WAIT_MS 2000

static char g_dir[64];
static char g_link[128];
static lms_pty_t g_pty;
static lms_serial_t g_port;
static lms_serial_t g_port2;

/* A name inside the temporary directory. */
static void dir_path(char *out, size_t cap, const char *name)
{
    const int n = snprintf(out, cap, "%s/%s", g_dir, name);
    TEST_ASSERT_TRUE(n > 0 && (size_t)n < cap);
}

void setUp(void)
{
    g_pty.master = -1;
    g_pty.slave_keep = -1;
    g_pty.slave_path[0] = '\0';
    g_pty.link_path[0] = '\0';
    g_port.fd = -1;
    g_port2.fd = -1;
    (void)snprintf(g_dir, sizeof g_dir, "/tmp/lms_posix_XXXXXX");
    TEST_ASSERT_NOT_NULL(mkdtemp(g_dir));
    dir_path(g_link, sizeof g_link, "scanner");
}

void tearDown(void)
{
    lms_serial_close(&g_port2);
    lms_serial_close(&g_port);
    lms_pty_close(&g_pty);
    static const char *const names[] = {"scanner", "plain", "subdir"};
    char path[128];
    for (size_t i = 0u; i < sizeof names / sizeof names[0]; i++) {
        (void)snprintf(path, sizeof path, "%s/%s", g_dir, names[i]);
        (void)unlink(path);
        (void)rmdir(path);
    }
    (void)rmdir(g_dir);
}

/* Reads exactly n bytes from the master, polling; fails on a timeout. */
static void master_read_exact(uint8_t *buf, size_t n)
{
    size_t have = 0u;
    while (have < n) {
        struct pollfd p = {g_pty.master, POLLIN, 0};
        const int r = poll(&p, 1u, WAIT_MS);
        if (r < 0 && errno == EINTR) {
            continue;
        }
        TEST_ASSERT_EQUAL_INT_MESSAGE(1, r, "master: no data in time");
        const ssize_t got = read(g_pty.master, buf + have, n - have);
        if (got < 0 && (errno == EINTR || errno == EAGAIN)) {
            continue;
        }
        TEST_ASSERT_TRUE_MESSAGE(got > 0, "master read failed");
        have += (size_t)got;
    }
}

static void master_write_all(const uint8_t *buf, size_t n)
{
    size_t done = 0u;
    while (done < n) {
        const ssize_t w = write(g_pty.master, buf + done, n - done);
        if (w > 0) {
            done += (size_t)w;
            continue;
        }
        TEST_ASSERT_TRUE_MESSAGE(errno == EINTR || errno == EAGAIN, "master write failed");
        struct pollfd p = {g_pty.master, POLLOUT, 0};
        TEST_ASSERT_TRUE_MESSAGE(poll(&p, 1u, WAIT_MS) != 0, "master: no room in time");
    }
}

/* Reads exactly n bytes through the port. */
static void port_read_exact(lms_serial_t *port, uint8_t *buf, size_t n)
{
    size_t have = 0u;
    while (have < n) {
        size_t got = 0u;
        const lms_serial_status_t s = lms_serial_read(port, buf + have, n - have, WAIT_MS, &got);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_SERIAL_OK, s, lms_serial_status_name(s));
        TEST_ASSERT_TRUE(got > 0u && got <= n - have);
        have += got;
    }
}

static int64_t now_us(void)
{
    struct timespec ts;
    TEST_ASSERT_EQUAL_INT(0, clock_gettime(CLOCK_MONOTONIC, &ts));
    return (int64_t)ts.tv_sec * 1000000 + (int64_t)(ts.tv_nsec / 1000);
}

static void fill_pattern(uint8_t *buf, size_t n, uint8_t seed)
{
    for (size_t i = 0u; i < n; i++) {
        buf[i] = (uint8_t)(seed + i * 7u);
    }
}

/* Both directions, with a telegram-sized and a scan-sized block. */
static void check_bytes_flow(lms_serial_t *port)
{
    uint8_t out[40];
    uint8_t in[sizeof out];
    fill_pattern(out, sizeof out, 0x02u);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_write(port, out, sizeof out));
    master_read_exact(in, sizeof in);
    TEST_ASSERT_EQUAL_UINT8_ARRAY(out, in, sizeof out);

    uint8_t scan[1000];
    uint8_t back[sizeof scan];
    fill_pattern(scan, sizeof scan, 0x80u);
    master_write_all(scan, sizeof scan);
    port_read_exact(port, back, sizeof back);
    TEST_ASSERT_EQUAL_UINT8_ARRAY(scan, back, sizeof scan);
}

static void test_lms_serial_status_names(void)
{
    static const lms_serial_status_t all[] = {
        LMS_SERIAL_OK,     LMS_SERIAL_TIMEOUT, LMS_SERIAL_MISSING, LMS_SERIAL_BUSY,
        LMS_SERIAL_DENIED, LMS_SERIAL_NOT_TTY, LMS_SERIAL_BAUD,    LMS_SERIAL_HANGUP,
        LMS_SERIAL_IO};
    for (size_t i = 0u; i < sizeof all / sizeof all[0]; i++) {
        const char *name = lms_serial_status_name(all[i]);
        TEST_ASSERT_NOT_NULL(name);
        TEST_ASSERT_TRUE(name[0] != '\0');
    }
    TEST_ASSERT_NOT_NULL(lms_serial_status_name((lms_serial_status_t)42));
}

static void test_lms_pty_without_link(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, NULL));
    TEST_ASSERT_TRUE(g_pty.master >= 0);
    TEST_ASSERT_EQUAL_STRING(g_pty.slave_path, lms_pty_path(&g_pty));
    TEST_ASSERT_EQUAL_INT(0, strncmp(g_pty.slave_path, "/dev/", 5u));
    lms_baud_t baud = LMS_BAUD_500000;
    TEST_ASSERT_TRUE(lms_pty_host_baud(&g_pty, &baud));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, baud); /* raw at 9600 from the start */

    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK,
                          lms_serial_open(&g_port, lms_pty_path(&g_pty), LMS_BAUD_38400));
    TEST_ASSERT_TRUE(g_port.fd >= 0);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_38400, g_port.baud);
    TEST_ASSERT_EQUAL_STRING(g_pty.slave_path, g_port.path);
    TEST_ASSERT_TRUE(lms_pty_host_baud(&g_pty, &baud));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_38400, baud);
    check_bytes_flow(&g_port);
}

static void test_lms_pty_with_link(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, g_link));
    TEST_ASSERT_EQUAL_STRING(g_link, lms_pty_path(&g_pty));
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, lstat(g_link, &st));
    TEST_ASSERT_TRUE(S_ISLNK(st.st_mode));
    char target[256];
    const ssize_t n = readlink(g_link, target, sizeof target - 1u);
    TEST_ASSERT_TRUE(n > 0);
    target[n] = '\0';
    TEST_ASSERT_EQUAL_STRING(g_pty.slave_path, target);

    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_open(&g_port, g_link, LMS_BAUD_9600));
    check_bytes_flow(&g_port);

    lms_serial_close(&g_port);
    lms_pty_close(&g_pty);
    TEST_ASSERT_EQUAL_INT(-1, lstat(g_link, &st)); /* the link went with it */
    lms_pty_close(&g_pty);                         /* twice is harmless */
}

/* An older link is replaced; a file that is not a link is not. */
static void test_lms_pty_link_replaces_only_links(void)
{
    TEST_ASSERT_EQUAL_INT(0, symlink("/nonexistent", g_link));
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, g_link));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_open(&g_port, g_link, LMS_BAUD_9600));
    lms_serial_close(&g_port);
    lms_pty_close(&g_pty);

    char plain[128];
    dir_path(plain, sizeof plain, "plain");
    FILE *f = fopen(plain, "w");
    TEST_ASSERT_NOT_NULL(f);
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
    TEST_ASSERT_EQUAL_INT(EEXIST, lms_pty_open(&g_pty, plain));
    TEST_ASSERT_EQUAL_INT(-1, g_pty.master);
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, lstat(plain, &st));
    TEST_ASSERT_TRUE(S_ISREG(st.st_mode));
}

static void test_lms_serial_every_rate_reads_back(void)
{
    static const lms_baud_t rates[] = {LMS_BAUD_9600, LMS_BAUD_19200, LMS_BAUD_38400,
                                       LMS_BAUD_500000, LMS_BAUD_9600};
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, g_link));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_open(&g_port, g_link, LMS_BAUD_19200));
    for (size_t i = 0u; i < sizeof rates / sizeof rates[0]; i++) {
        TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_set_baud(&g_port, rates[i]));
        TEST_ASSERT_EQUAL_INT(rates[i], g_port.baud);
        lms_baud_t seen = (lms_baud_t)99;
        TEST_ASSERT_TRUE(lms_pty_host_baud(&g_pty, &seen));
        TEST_ASSERT_EQUAL_INT(rates[i], seen);
        /* Input and output both changed (a stale input rate is the trap
         * when BOTHER and the B constants are mixed). */
        struct termios t;
        TEST_ASSERT_EQUAL_INT(0, tcgetattr(g_port.fd, &t));
        const speed_t in = cfgetispeed(&t);
        const speed_t out = cfgetospeed(&t);
        TEST_ASSERT_TRUE(in == out);
        check_bytes_flow(&g_port);
    }
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_BAUD, lms_serial_set_baud(&g_port, (lms_baud_t)7));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, g_port.baud);
}

/* Opening straight at 500000, and the raw line settings. */
static void test_lms_serial_open_at_500000_is_raw(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, NULL));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK,
                          lms_serial_open(&g_port, lms_pty_path(&g_pty), LMS_BAUD_500000));
    lms_baud_t seen = LMS_BAUD_9600;
    TEST_ASSERT_TRUE(lms_pty_host_baud(&g_pty, &seen));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_500000, seen);
    struct termios t;
    TEST_ASSERT_EQUAL_INT(0, tcgetattr(g_port.fd, &t));
    TEST_ASSERT_EQUAL_INT(CS8, (int)(t.c_cflag & CSIZE));
    TEST_ASSERT_TRUE((t.c_cflag & (PARENB | CSTOPB | CRTSCTS)) == 0u);
    TEST_ASSERT_TRUE((t.c_cflag & (CLOCAL | CREAD)) == (CLOCAL | CREAD));
    TEST_ASSERT_TRUE((t.c_iflag & (IXON | IXOFF | ICRNL | ISTRIP)) == 0u);
    TEST_ASSERT_TRUE((t.c_lflag & (ICANON | ECHO | ISIG)) == 0u);
    TEST_ASSERT_TRUE((t.c_oflag & OPOST) == 0u);
    TEST_ASSERT_EQUAL_INT(0, t.c_cc[VMIN]);
    TEST_ASSERT_EQUAL_INT(0, t.c_cc[VTIME]);
    const int fl = fcntl(g_port.fd, F_GETFL);
    TEST_ASSERT_TRUE(fl >= 0 && (fl & O_NONBLOCK) != 0);
    /* Every byte value passes untouched (CR, LF, XON, XOFF, ^C, 0xFF). */
    uint8_t all[256];
    uint8_t in[sizeof all];
    for (size_t i = 0u; i < sizeof all; i++) {
        all[i] = (uint8_t)i;
    }
    /* Paced at 500000: at least 60 us after each byte. */
    const int64_t t0 = now_us();
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_write(&g_port, all, sizeof all));
    TEST_ASSERT_TRUE(now_us() - t0 >= (int64_t)(60u * sizeof all));
    master_read_exact(in, sizeof in);
    TEST_ASSERT_EQUAL_UINT8_ARRAY(all, in, sizeof all);
    master_write_all(all, sizeof all);
    port_read_exact(&g_port, in, sizeof in);
    TEST_ASSERT_EQUAL_UINT8_ARRAY(all, in, sizeof all);
}

/* A rate that is none of the four reads as unknown. */
static void test_lms_pty_unknown_rate(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, NULL));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK,
                          lms_serial_open(&g_port, lms_pty_path(&g_pty), LMS_BAUD_9600));
    struct termios t;
    TEST_ASSERT_EQUAL_INT(0, tcgetattr(g_port.fd, &t));
    TEST_ASSERT_EQUAL_INT(0, cfsetispeed(&t, B115200));
    TEST_ASSERT_EQUAL_INT(0, cfsetospeed(&t, B115200));
    TEST_ASSERT_EQUAL_INT(0, tcsetattr(g_port.fd, TCSANOW, &t));
    lms_baud_t seen = LMS_BAUD_19200;
    TEST_ASSERT_FALSE(lms_pty_host_baud(&g_pty, &seen));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_19200, seen); /* left alone */
}

static void test_lms_serial_read_timeout(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, NULL));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK,
                          lms_serial_open(&g_port, lms_pty_path(&g_pty), LMS_BAUD_9600));
    uint8_t buf[16];
    size_t got = 99u;
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_TIMEOUT, lms_serial_read(&g_port, buf, sizeof buf, 30, &got));
    TEST_ASSERT_EQUAL_UINT(0u, got);
    got = 99u;
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_TIMEOUT, lms_serial_read(&g_port, buf, sizeof buf, 0, &got));
    TEST_ASSERT_EQUAL_UINT(0u, got);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_TIMEOUT, lms_serial_read(&g_port, buf, sizeof buf, -5, &got));
    /* Bad arguments are errors, not waits. */
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_IO, lms_serial_read(&g_port, buf, 0u, 10, &got));
    TEST_ASSERT_EQUAL_INT(EINVAL, g_port.error);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_IO, lms_serial_read(&g_port, NULL, 4u, 10, &got));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_write(&g_port, buf, 0u));
}

static void test_lms_serial_second_open_is_busy(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, g_link));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_open(&g_port, g_link, LMS_BAUD_9600));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_BUSY, lms_serial_open(&g_port2, g_link, LMS_BAUD_9600));
    TEST_ASSERT_EQUAL_INT(-1, g_port2.fd);
    TEST_ASSERT_TRUE(g_port2.error != 0);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_BUSY,
                          lms_serial_open(&g_port2, g_pty.slave_path, LMS_BAUD_9600));
#ifdef TIOCGEXCL
    /* The refused opener left the first one's exclusive mode alone. */
    int excl = 0;
    TEST_ASSERT_EQUAL_INT(0, ioctl(g_pty.slave_keep, TIOCGEXCL, &excl));
    TEST_ASSERT_TRUE(excl != 0);
#endif
    check_bytes_flow(&g_port);
    lms_serial_close(&g_port);
    lms_serial_close(&g_port); /* twice is harmless */
#ifdef TIOCGEXCL
    TEST_ASSERT_EQUAL_INT(0, ioctl(g_pty.slave_keep, TIOCGEXCL, &excl));
    TEST_ASSERT_EQUAL_INT(0, excl); /* cleared on close */
#endif
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_open(&g_port2, g_link, LMS_BAUD_9600));
    /* A closed port refuses politely. */
    uint8_t b = 0u;
    size_t got = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_IO, lms_serial_read(&g_port, &b, 1u, 0, &got));
    TEST_ASSERT_EQUAL_INT(EBADF, g_port.error);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_IO, lms_serial_write(&g_port, &b, 1u));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_IO, lms_serial_set_baud(&g_port, LMS_BAUD_9600));
}

static void test_lms_serial_refusals(void)
{
    char path[128];
    dir_path(path, sizeof path, "scanner");
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_MISSING, lms_serial_open(&g_port, path, LMS_BAUD_9600));
    TEST_ASSERT_EQUAL_INT(ENOENT, g_port.error);
    TEST_ASSERT_EQUAL_INT(-1, g_port.fd);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_MISSING, lms_serial_open(&g_port, "", LMS_BAUD_9600));

    dir_path(path, sizeof path, "plain");
    FILE *f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    TEST_ASSERT_EQUAL_INT(3, (int)fwrite("abc", 1u, 3u, f));
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_NOT_TTY, lms_serial_open(&g_port, path, LMS_BAUD_9600));
    TEST_ASSERT_EQUAL_INT(-1, g_port.fd);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_NOT_TTY, lms_serial_open(&g_port, g_dir, LMS_BAUD_9600));

    char longpath[300];
    (void)memset(longpath, 'a', sizeof longpath - 1u);
    longpath[sizeof longpath - 1u] = '\0';
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_IO, lms_serial_open(&g_port, longpath, LMS_BAUD_9600));
    TEST_ASSERT_EQUAL_INT(ENAMETOOLONG, g_port.error);

    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, NULL));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_BAUD,
                          lms_serial_open(&g_port, lms_pty_path(&g_pty), (lms_baud_t)9));
    TEST_ASSERT_EQUAL_INT(-1, g_port.fd);
    /* ... and the failed open did not leave the tty locked. */
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK,
                          lms_serial_open(&g_port, lms_pty_path(&g_pty), LMS_BAUD_9600));

    lms_pty_t other;
    TEST_ASSERT_EQUAL_INT(ENAMETOOLONG, lms_pty_open(&other, longpath));
    TEST_ASSERT_EQUAL_INT(-1, other.master);
    lms_pty_close(&other);
}

/* Bytes that arrived before a rate change are gone after it. */
static void test_lms_serial_set_baud_discards_input(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, NULL));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK,
                          lms_serial_open(&g_port, lms_pty_path(&g_pty), LMS_BAUD_9600));
    const uint8_t stale[] = {0x02u, 0x80u, 0xAAu, 0x55u};
    master_write_all(stale, sizeof stale);
    struct pollfd p = {g_port.fd, POLLIN, 0};
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, poll(&p, 1u, WAIT_MS), "stale bytes never arrived");
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_set_baud(&g_port, LMS_BAUD_38400));
    uint8_t buf[8];
    size_t got = 99u;
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_TIMEOUT, lms_serial_read(&g_port, buf, sizeof buf, 0, &got));
    TEST_ASSERT_EQUAL_UINT(0u, got);
    check_bytes_flow(&g_port); /* fresh bytes still flow */
}

/* Input queued before the driver opened the line is discarded too. */
static void test_lms_serial_open_discards_input(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, NULL));
    const uint8_t early[] = {0x90u, 0x91u};
    master_write_all(early, sizeof early);
    struct pollfd p = {g_pty.slave_keep, POLLIN, 0};
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, poll(&p, 1u, WAIT_MS), "early bytes never arrived");
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK,
                          lms_serial_open(&g_port, lms_pty_path(&g_pty), LMS_BAUD_9600));
    uint8_t buf[8];
    size_t got = 99u;
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_TIMEOUT, lms_serial_read(&g_port, buf, sizeof buf, 0, &got));
}

/* Hang-up and reconnect: the open port sees LMS_SERIAL_HANGUP, the link
 * then leads to a new, working line. */
static void test_lms_pty_reopen_hangs_up(void)
{
    TEST_ASSERT_EQUAL_INT(0, lms_pty_open(&g_pty, g_link));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_open(&g_port, g_link, LMS_BAUD_500000));
    check_bytes_flow(&g_port);
    char old_slave[sizeof g_pty.slave_path];
    (void)memcpy(old_slave, g_pty.slave_path, sizeof old_slave);

    TEST_ASSERT_EQUAL_INT(0, lms_pty_reopen(&g_pty));
    TEST_ASSERT_TRUE(g_pty.master >= 0);
    uint8_t buf[8];
    size_t got = 99u;
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_HANGUP,
                          lms_serial_read(&g_port, buf, sizeof buf, WAIT_MS, &got));
    TEST_ASSERT_EQUAL_UINT(0u, got);
    TEST_ASSERT_TRUE(g_port.error != 0);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_HANGUP, lms_serial_write(&g_port, buf, 1u));
    lms_serial_close(&g_port);

    char target[256];
    const ssize_t n = readlink(g_link, target, sizeof target - 1u);
    TEST_ASSERT_TRUE(n > 0);
    target[n] = '\0';
    TEST_ASSERT_EQUAL_STRING(g_pty.slave_path, target);

    /* The new line starts at 9600, like a scanner after a power cycle. */
    lms_baud_t seen = LMS_BAUD_500000;
    TEST_ASSERT_TRUE(lms_pty_host_baud(&g_pty, &seen));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, seen);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_open(&g_port, g_link, LMS_BAUD_19200));
    TEST_ASSERT_TRUE(lms_pty_host_baud(&g_pty, &seen));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_19200, seen);
    check_bytes_flow(&g_port);

    /* Again, with the port reading when it happens. */
    TEST_ASSERT_EQUAL_INT(0, lms_pty_reopen(&g_pty));
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_HANGUP,
                          lms_serial_read(&g_port, buf, sizeof buf, 0, &got));
    lms_serial_close(&g_port);
    TEST_ASSERT_EQUAL_INT(LMS_SERIAL_OK, lms_serial_open(&g_port, g_link, LMS_BAUD_9600));
    check_bytes_flow(&g_port);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_serial_status_names);
    RUN_TEST(test_lms_pty_without_link);
    RUN_TEST(test_lms_pty_with_link);
    RUN_TEST(test_lms_pty_link_replaces_only_links);
    RUN_TEST(test_lms_serial_every_rate_reads_back);
    RUN_TEST(test_lms_serial_open_at_500000_is_raw);
    RUN_TEST(test_lms_pty_unknown_rate);
    RUN_TEST(test_lms_serial_read_timeout);
    RUN_TEST(test_lms_serial_second_open_is_busy);
    RUN_TEST(test_lms_serial_refusals);
    RUN_TEST(test_lms_serial_set_baud_discards_input);
    RUN_TEST(test_lms_serial_open_discards_input);
    RUN_TEST(test_lms_pty_reopen_hangs_up);
    return UNITY_END();
}
