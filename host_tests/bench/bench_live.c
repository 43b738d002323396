/* bench_live.c - latency and CPU use of `lmsego run` on a live line
 * (host-only; figures in docs/session.md).
 *
 *   bench_live LMSEGO STREAM [SECONDS]
 *
 * Opens a pseudo-terminal and acts as the scanner on it itself (the
 * lms_sim model, streaming the B0 telegrams of STREAM in a loop, in the
 * stream's own variant), starts `LMSEGO run --port PTY --variant V` with
 * its stdout on a pipe, and for every scan notes two instants on the same
 * clock: when the last byte of the scan's telegram was written to the
 * pseudo-terminal, and when run's CSV line for that scan was read from the
 * pipe. Latency = line - last byte (scan k of the stream is line k; the
 * first scan has no line). After SECONDS of streaming (default 20) it
 * sends SIGINT and takes run's CPU time (user + system, from wait4) over
 * its whole life. Prints the latency median, p99 and max, and the CPU use
 * as a share of one core over the streaming time.
 *
 * Not a test: timings depend on the machine. The ctest smoke test runs it
 * for 2 s and checks only that lines came back.
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "lms_decode.h"
#include "lms_framer.h"
#include "lms_pty.h"
#include "lms_sim.h"

#define MAX_SCANS 20000u
#define MAX_TELEGRAMS 4096u

static uint64_t now_us(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

/* The stream's B0 telegrams. */
static uint8_t *tel_bytes;
static size_t tel_off[MAX_TELEGRAMS + 1u];
static size_t tel_count;
static uint16_t tel_values;

static int load_stream(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        (void)fprintf(stderr, "bench_live: cannot open %s: %s\n", path, strerror(errno));
        return -1;
    }
    static uint8_t chunk[4096];
    static lms_framer_t fr;
    lms_framer_init(&fr, LMS_FROM_SCANNER);
    size_t cap = 0u;
    size_t used_bytes = 0u;
    size_t got;
    while ((got = fread(chunk, 1u, sizeof chunk, f)) > 0u && tel_count < MAX_TELEGRAMS) {
        size_t off = 0u;
        for (;;) {
            size_t used = 0u;
            const lms_framer_event_t ev = lms_framer_feed(&fr, chunk + off, got - off, &used);
            off += used;
            if (ev == LMS_FRAMER_NEED_MORE) {
                break;
            }
            size_t len = 0u;
            const uint8_t *t = lms_framer_telegram(&fr, &len);
            if (ev != LMS_FRAMER_TELEGRAM || t[LMS_HEADER_SIZE] != LMS_REPLY_VALUES ||
                tel_count >= MAX_TELEGRAMS) {
                continue;
            }
            static lms_scan_t scan;
            if (lms_decode_scan(t, len, &scan) != LMS_OK) {
                continue;
            }
            if (used_bytes + len > cap) {
                cap = (cap + len) * 2u;
                uint8_t *b = realloc(tel_bytes, cap);
                if (b == NULL) {
                    (void)fclose(f);
                    return -1;
                }
                tel_bytes = b;
            }
            memcpy(tel_bytes + used_bytes, t, len);
            tel_off[tel_count++] = used_bytes;
            used_bytes += len;
            tel_values = scan.count;
        }
    }
    tel_off[tel_count] = used_bytes;
    (void)fclose(f);
    if (tel_count == 0u) {
        (void)fprintf(stderr, "bench_live: no scans in %s\n", path);
        return -1;
    }
    return 0;
}

static bool source(void *ctx, uint32_t k, uint16_t angle_deg, uint16_t resolution_cdeg,
                   bool partial, lms_unit_t unit, uint8_t reply_address, uint8_t *out, size_t cap,
                   size_t *len, uint32_t *gap_us)
{
    (void)ctx;
    (void)angle_deg;
    (void)resolution_cdeg;
    (void)partial;
    (void)unit;
    (void)reply_address;
    const size_t i = k % tel_count;
    const size_t n = tel_off[i + 1u] - tel_off[i];
    if (n > cap) {
        return false;
    }
    memcpy(out, tel_bytes + tel_off[i], n);
    *len = n;
    *gap_us = 0u;
    return true;
}

/* Until the simulator's next event, 1 .. 50 ms: at least 1 ms, as lmsego
 * sim does, so the line's bytes come in chunks of up to a millisecond (like
 * a USB serial adapter) instead of a wake-up per 20-us byte. */
static int poll_timeout_ms(uint64_t now, uint64_t next)
{
    if (next == UINT64_MAX || next >= now + 50000u) {
        return 50;
    }
    const uint64_t ms = next > now ? (next - now) / 1000u : 0u;
    return ms < 1u ? 1 : (int)ms;
}

/* Writes all n bytes, waiting (up to 2 s) while the pseudo-terminal is
 * full: a slow reader must show as latency here, not as lost scans. */
static ssize_t write_all(int fd, const uint8_t *b, size_t n)
{
    size_t off = 0u;
    while (off < n) {
        const ssize_t w = write(fd, b + off, n - off);
        if (w > 0) {
            off += (size_t)w;
            continue;
        }
        if (w < 0 && errno != EAGAIN && errno != EINTR) {
            break;
        }
        struct pollfd p = {fd, POLLOUT, 0};
        if (poll(&p, 1u, 2000) <= 0) {
            break;
        }
    }
    return (ssize_t)off;
}

static uint64_t last_byte_us[MAX_SCANS];
static uint64_t line_us[MAX_SCANS];

static int cmp_u64(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a;
    const uint64_t y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 4) {
        (void)fprintf(stderr, "usage: bench_live LMSEGO STREAM [SECONDS]\n");
        return 2;
    }
    double seconds = 20.0;
    if (argc == 4) {
        char *end = NULL;
        seconds = strtod(argv[3], &end);
        if (end == argv[3] || *end != '\0') {
            seconds = -1.0;
        }
    }
    if (!(seconds > 0.0 && seconds < 3600.0) || load_stream(argv[2]) != 0) {
        return 2;
    }
    const char *variant = NULL;
    uint16_t angle = 180u;
    uint16_t res = 50u;
    switch (tel_values) {
    case 181u: variant = "180,1"; res = 100u; break;
    case 361u: variant = "180,0.5"; break;
    case 101u: variant = "100,1"; angle = 100u; res = 100u; break;
    case 201u: variant = "100,0.5"; angle = 100u; break;
    case 401u: variant = "100,0.25"; angle = 100u; res = 25u; break;
    default:
        (void)fprintf(stderr, "bench_live: %u values per scan is not an LMS variant\n",
                      (unsigned)tel_values);
        return 2;
    }
    static lms_pty_t pty;
    if (lms_pty_open(&pty, NULL) != 0) {
        (void)fprintf(stderr, "bench_live: no pseudo-terminal: %s\n", strerror(pty.error));
        return 1;
    }
    int out_pipe[2];
    if (pipe(out_pipe) != 0) {
        return 1;
    }
    const pid_t child = fork();
    if (child < 0) {
        return 1;
    }
    if (child == 0) {
        (void)dup2(out_pipe[1], STDOUT_FILENO);
        (void)close(out_pipe[0]);
        (void)close(out_pipe[1]);
        const int devnull = open("/dev/null", O_WRONLY);
        if (devnull >= 0) {
            (void)dup2(devnull, STDERR_FILENO);
        }
        execl(argv[1], argv[1], "run", "--port", lms_pty_path(&pty), "--variant", variant,
              (char *)NULL);
        _exit(127);
    }
    (void)close(out_pipe[1]);
    (void)signal(SIGPIPE, SIG_IGN);

    static lms_sim_t sim;
    lms_sim_config_t sc;
    lms_sim_defaults(&sc);
    sc.scan_source = source;
    sc.fixed_angle_deg = angle;
    sc.fixed_resolution_cdeg = res;
    const uint64_t t0 = now_us();
    lms_sim_init(&sim, &sc, 0u);
    static lms_framer_t tap; /* what we write, to time each B0's last byte */
    lms_framer_init(&tap, LMS_FROM_SCANNER);
    uint32_t scans_out = 0u;
    uint32_t lines_in = 0u;
    uint64_t stream_start = 0u;
    uint64_t stream_end = 0u;
    static char linebuf[65536];
    size_t line_len = 0u;
    bool stopping = false;
    bool child_done = false;
    static uint8_t buf[4096];
    for (;;) {
        const uint64_t t = now_us() - t0;
        lms_baud_t host = lms_sim_baud(&sim);
        if (!lms_pty_host_baud(&pty, &host)) {
            host = lms_sim_baud(&sim) == LMS_BAUD_9600 ? LMS_BAUD_19200 : LMS_BAUD_9600;
        }
        const size_t n = lms_sim_transmit(&sim, host, t, buf, sizeof buf);
        if (n > 0u) {
            const ssize_t w = write_all(pty.master, buf, n);
            const uint64_t tw = now_us();
            size_t off = 0u;
            for (; w > 0;) {
                size_t used = 0u;
                const lms_framer_event_t ev = lms_framer_feed(&tap, buf + off, (size_t)w - off, &used);
                off += used;
                if (ev == LMS_FRAMER_NEED_MORE) {
                    break;
                }
                size_t len = 0u;
                const uint8_t *tt = lms_framer_telegram(&tap, &len);
                if (ev == LMS_FRAMER_TELEGRAM && tt[LMS_HEADER_SIZE] == LMS_REPLY_VALUES &&
                    scans_out < MAX_SCANS) {
                    if (scans_out == 0u) {
                        stream_start = tw;
                    }
                    last_byte_us[scans_out++] = tw;
                }
            }
        }
        if (!stopping && scans_out > 0u && (double)(now_us() - stream_start) > seconds * 1e6) {
            stream_end = now_us();
            (void)kill(child, SIGINT);
            stopping = true;
        }
        const uint64_t next = lms_sim_next_event_us(&sim, t);
        struct pollfd p[2] = {{pty.master, POLLIN, 0}, {out_pipe[0], POLLIN, 0}};
        const int pr = poll(p, 2u, poll_timeout_ms(t, next));
        if (pr < 0 && errno != EINTR) {
            break;
        }
        if ((p[0].revents & POLLIN) != 0) {
            const ssize_t r = read(pty.master, buf, sizeof buf);
            if (r > 0) {
                lms_sim_receive(&sim, buf, (size_t)r, host, now_us() - t0);
            }
        }
        if ((p[1].revents & (POLLIN | POLLHUP)) != 0) {
            const ssize_t r = read(out_pipe[0], linebuf + line_len, sizeof linebuf - line_len - 1u);
            const uint64_t tr = now_us();
            if (r <= 0) {
                child_done = true;
                break;
            }
            line_len += (size_t)r;
            char *start = linebuf;
            char *nl;
            while ((nl = memchr(start, '\n', (size_t)(linebuf + line_len - start))) != NULL) {
                *nl = '\0';
                const unsigned long k = strtoul(start, NULL, 10);
                if (start[0] >= '0' && start[0] <= '9' && k < MAX_SCANS) {
                    line_us[k] = tr;
                    lines_in++;
                }
                start = nl + 1;
            }
            line_len = (size_t)(linebuf + line_len - start);
            memmove(linebuf, start, line_len);
        }
    }
    int status = 0;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    if (wait4(child, &status, 0, &ru) < 0) {
        return 1;
    }
    (void)child_done;
    lms_pty_close(&pty);
    static uint64_t lat[MAX_SCANS];
    size_t m = 0u;
    for (uint32_t k = 1u; k < scans_out && k < MAX_SCANS; k++) {
        if (line_us[k] != 0u && line_us[k] >= last_byte_us[k]) {
            lat[m++] = line_us[k] - last_byte_us[k];
        }
    }
    if (m == 0u) {
        (void)fprintf(stderr, "bench_live: no output lines came back\n");
        return 1;
    }
    qsort(lat, m, sizeof lat[0], cmp_u64);
    const double cpu_s = (double)ru.ru_utime.tv_sec + (double)ru.ru_utime.tv_usec * 1e-6 +
                         (double)ru.ru_stime.tv_sec + (double)ru.ru_stime.tv_usec * 1e-6;
    const double stream_s = (double)(stream_end - stream_start) * 1e-6;
    /* Lines later than one scan period: the estimator fell behind. */
    const uint64_t period = res == 25u ? 53333u : (res == 50u ? 26667u : 13333u);
    size_t late = 0u;
    for (size_t i = 0u; i < m; i++) {
        late += lat[i] > period ? 1u : 0u;
    }
    (void)printf("variant=%s scans_sent=%u lines=%u latency_us median=%llu p90=%llu p99=%llu "
                 "max=%llu later_than_a_period=%zu cpu_s=%.3f streaming_s=%.2f cpu_share=%.2f%% "
                 "exit=%d\n",
                 variant, scans_out, lines_in, (unsigned long long)lat[m / 2u],
                 (unsigned long long)lat[(m * 90u) / 100u],
                 (unsigned long long)lat[(m * 99u) / 100u], (unsigned long long)lat[m - 1u], late,
                 cpu_s, stream_s, stream_s > 0.0 ? 100.0 * cpu_s / stream_s : 0.0,
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    free(tel_bytes);
    return 0;
}
