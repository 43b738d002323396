/* fuzz_carmen.c - libFuzzer target over the CARMEN importer (`lmsego
 * import-carmen`, firmware/host/cmd_import_carmen.c), whole: the log is
 * written to a file, plain or gzip'd, and the command runs on it as from
 * the command line.
 *
 * Input: byte 0 picks the options: bit 0 gzip the log; bits 1-2 --stride
 * 1..4, bits 3-4 --offset (taken modulo the stride); bits 5-6 --no-return
 * (the default, none, 50, 5 m); bit 7 --odometry. The rest is the log.
 * The files live in a directory of their own under $TMPDIR (or /tmp),
 * made once per process and reused.
 *
 * Checks (abort on violation):
 *  - the exit status is 0 or 1 (the command line is always good: never
 *    2), and with 0 the stream and the odometry file are complete:
 *  - the stream starts with the ACK and A0 of `20 24`, then only B0
 *    telegrams, back to back: the framer skips nothing, finds no CRC or
 *    length error and no partial telegram, every telegram decodes
 *    (lms_decode_scan) to 181 or 361 values, all in the same unit, and
 *    there is at least one;
 *  - every odometry line is "i j dx dy dtheta" with j == i + stride and
 *    finite numbers, at most one per scan after the first;
 *  - no crash, no undefined behaviour (ASan, UBSan), no file descriptor
 *    left open (the next open gets the same number).
 * Run it with -close_fd_mask=3: the command prints a summary on stderr.
 */
#include <fcntl.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "commands.h"
#include "fuzz_check.h"
#include "lms_decode.h"
#include "lms_framer.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char dir[256];
static char log_path[300];
static char out_path[300];
static char odom_path[300];

static void make_paths(void)
{
    if (dir[0] != '\0') {
        return;
    }
    const char *tmp = getenv("TMPDIR");
    (void)snprintf(dir, sizeof dir, "%s/fuzz_carmen.XXXXXX", (tmp != NULL) ? tmp : "/tmp");
    FUZZ_CHECK(mkdtemp(dir) != NULL);
    (void)snprintf(log_path, sizeof log_path, "%s/log", dir);
    (void)snprintf(out_path, sizeof out_path, "%s/stream", dir);
    (void)snprintf(odom_path, sizeof odom_path, "%s/odom", dir);
}

static void write_log(const uint8_t *bytes, size_t n, bool gz)
{
    if (gz) {
        gzFile f = gzopen(log_path, "wb");
        FUZZ_CHECK(f != NULL);
        FUZZ_CHECK(n == 0u || gzwrite(f, bytes, (unsigned)n) == (int)n);
        FUZZ_CHECK(gzclose(f) == Z_OK);
        return;
    }
    FILE *f = fopen(log_path, "wb");
    FUZZ_CHECK(f != NULL);
    FUZZ_CHECK(fwrite(bytes, 1u, n, f) == n);
    FUZZ_CHECK(fclose(f) == 0);
}

/* The stream import-carmen wrote; returns the number of scans. */
static unsigned long check_stream(void)
{
    static uint8_t buf[1u << 20];
    static lms_framer_t framer;
    static lms_scan_t scan;
    static const uint8_t start[] = {0x06, 0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A};
    FILE *f = fopen(out_path, "rb");
    FUZZ_CHECK(f != NULL);
    const size_t n = fread(buf, 1u, sizeof buf, f);
    FUZZ_CHECK(fclose(f) == 0);
    FUZZ_CHECK(n >= sizeof start && memcmp(buf, start, sizeof start) == 0);
    lms_framer_init(&framer, LMS_FROM_SCANNER);
    size_t pos = sizeof start;
    unsigned long scans = 0u;
    int unit = -1;
    while (pos < n) {
        size_t used = 0u;
        const lms_framer_event_t ev = lms_framer_feed(&framer, &buf[pos], n - pos, &used);
        pos += used;
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        FUZZ_CHECK(ev == LMS_FRAMER_TELEGRAM);
        size_t len = 0u;
        const uint8_t *t = lms_framer_telegram(&framer, &len);
        FUZZ_CHECK(t != NULL && lms_decode_scan(t, len, &scan) == LMS_OK);
        FUZZ_CHECK(scan.count == 181u || scan.count == 361u);
        FUZZ_CHECK(unit < 0 || unit == (int)scan.unit);
        unit = (int)scan.unit;
        scans++;
    }
    const lms_framer_stats_t *st = lms_framer_stats(&framer);
    FUZZ_CHECK(pos == n && lms_framer_pending(&framer) == 0u);
    FUZZ_CHECK(st->bytes_skipped == 0u && st->crc_errors == 0u && st->length_errors == 0u);
    FUZZ_CHECK(scans >= 1u);
    return scans;
}

static void check_odometry(unsigned long stride, unsigned long scans)
{
    FILE *f = fopen(odom_path, "r");
    FUZZ_CHECK(f != NULL);
    char line[256];
    unsigned long lines = 0u;
    while (fgets(line, sizeof line, f) != NULL) {
        FUZZ_CHECK(strchr(line, '\n') != NULL);
        char *p = line;
        char *end = NULL;
        const unsigned long i = strtoul(p, &end, 10);
        FUZZ_CHECK(end != p && *end == ' ');
        p = end;
        const unsigned long j = strtoul(p, &end, 10);
        FUZZ_CHECK(end != p && *end == ' ' && j == i + stride);
        for (unsigned k = 0u; k < 3u; k++) {
            p = end;
            const double v = strtod(p, &end);
            FUZZ_CHECK(end != p && isfinite(v) && *end == ((k < 2u) ? ' ' : '\n'));
        }
        lines++;
    }
    FUZZ_CHECK(fclose(f) == 0);
    FUZZ_CHECK(lines < scans);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const no_return[4] = {NULL, "none", "50", "5"};
    static const cli_command_t self = {"import-carmen", "", "", cmd_import_carmen};
    if (size < 1u) {
        return 0;
    }
    make_paths();
    const uint8_t opt = data[0];
    const bool gz = (opt & 1u) != 0u;
    const unsigned long stride = 1u + ((opt >> 1) & 3u);
    const unsigned long offset = ((opt >> 3) & 3u) % stride;
    const char *nr = no_return[(opt >> 5) & 3u];
    const bool odometry = (opt & 0x80u) != 0u;
    write_log(data + 1, size - 1u, gz);
    (void)remove(out_path);
    (void)remove(odom_path);

    char stride_text[8];
    char offset_text[8];
    (void)snprintf(stride_text, sizeof stride_text, "%lu", stride);
    (void)snprintf(offset_text, sizeof offset_text, "%lu", offset);
    /* argv as main gets it: writable strings. */
    static char name[] = "import-carmen";
    static char opt_o[] = "-o";
    static char opt_stride[] = "--stride";
    static char opt_offset[] = "--offset";
    static char opt_no_return[] = "--no-return";
    static char opt_odometry[] = "--odometry";
    char nr_text[8];
    char *argv[16];
    int argc = 0;
    argv[argc++] = name;
    argv[argc++] = log_path;
    argv[argc++] = opt_o;
    argv[argc++] = out_path;
    argv[argc++] = opt_stride;
    argv[argc++] = stride_text;
    argv[argc++] = opt_offset;
    argv[argc++] = offset_text;
    if (nr != NULL) {
        (void)snprintf(nr_text, sizeof nr_text, "%s", nr);
        argv[argc++] = opt_no_return;
        argv[argc++] = nr_text;
    }
    if (odometry) {
        argv[argc++] = opt_odometry;
        argv[argc++] = odom_path;
    }
    argv[argc] = NULL;

    const int fd_before = open("/dev/null", O_RDONLY);
    FUZZ_CHECK(fd_before >= 0 && close(fd_before) == 0);
    const int rc = cmd_import_carmen(&self, argc, argv);
    const int fd_after = open("/dev/null", O_RDONLY);
    FUZZ_CHECK(fd_after == fd_before && close(fd_after) == 0);
    FUZZ_CHECK(rc == CLI_EXIT_OK || rc == CLI_EXIT_RUNTIME);
    if (rc == CLI_EXIT_OK) {
        const unsigned long scans = check_stream();
        if (odometry) {
            check_odometry(stride, scans);
        }
    }
    return 0;
}
