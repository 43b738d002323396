/* test_recording.c - the recording file format (firmware/host/recording.h)
 * and its reader (stream_file.c): shipped raw streams written as recordings
 * in random chunks with rising times, read back through stream_file with
 * random read sizes (bytes equal to the raw file, each read's time the time
 * of the block its bytes came from), the same through a pipe on stdin,
 * raw streams still read as before, malformed recordings refused with
 * EBADMSG and a reason, and the writer's splitting and error reporting.
 * And how `lmsego play` times and orders a recording's scans
 * (play_timing.h): a busy recorder's late reads are not played as
 * silence, a real outage is, and a restarted stream resumes.
 *
 * It also leaves recordings in LMSEGO_REC_OUT_DIR for the CLI tests in
 * posix_tests.cmake (lmsego stats / scans / replay on a recording).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "play_timing.h"
#include "recording.h"
#include "stream_file.h"
#include "unity.h"

#ifndef LMSEGO_DATA_DIR
#error "LMSEGO_DATA_DIR (host_tests/data) must be defined by the build"
#endif
#ifndef LMSEGO_REC_OUT_DIR
#error "LMSEGO_REC_OUT_DIR must be defined by the build"
#endif

typedef struct {
    size_t start;     /* offset of the block's first byte in the raw stream */
    uint64_t time_us; /* its time */
} block_t;

static char g_dir[64];
static uint8_t *g_raw;
static block_t *g_blocks;

static uint32_t rnd(uint32_t *s)
{
    /* xorshift32: reproducible from the seed */
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

static uint32_t rnd_range(uint32_t *s, uint32_t lo, uint32_t hi)
{
    return lo + rnd(s) % (hi - lo + 1u);
}

void setUp(void)
{
    (void)snprintf(g_dir, sizeof g_dir, "/tmp/lms_rec_XXXXXX");
    TEST_ASSERT_NOT_NULL(mkdtemp(g_dir));
    g_raw = NULL;
    g_blocks = NULL;
}

void tearDown(void)
{
    static const char *const names[] = {"a.rec", "b.rec", "raw.lms"};
    char path[128];
    for (size_t i = 0u; i < sizeof names / sizeof names[0]; i++) {
        (void)snprintf(path, sizeof path, "%s/%s", g_dir, names[i]);
        (void)unlink(path);
    }
    (void)rmdir(g_dir);
    free(g_raw);
    free(g_blocks);
}

static void tmp_path(char *out, size_t cap, const char *name)
{
    const int n = snprintf(out, cap, "%s/%s", g_dir, name);
    TEST_ASSERT_TRUE(n > 0 && (size_t)n < cap);
}

/* The whole file, malloc'd (kept in g_raw, freed by tearDown). */
static size_t load(const char *path)
{
    FILE *f = fopen(path, "rb");
    TEST_ASSERT_TRUE_MESSAGE(f != NULL, path);
    size_t cap = 1024u;
    size_t len = 0u;
    g_raw = malloc(cap);
    TEST_ASSERT_NOT_NULL(g_raw);
    for (;;) {
        if (len == cap) {
            cap *= 2u;
            uint8_t *bigger = realloc(g_raw, cap);
            TEST_ASSERT_NOT_NULL(bigger);
            g_raw = bigger;
        }
        const size_t n = fread(g_raw + len, 1u, cap - len, f);
        len += n;
        if (n == 0u) {
            break;
        }
    }
    TEST_ASSERT_FALSE(ferror(f));
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
    return len;
}

static void write_file(const char *path, const uint8_t *bytes, size_t len)
{
    FILE *f = fopen(path, "wb");
    TEST_ASSERT_TRUE_MESSAGE(f != NULL, path);
    TEST_ASSERT_TRUE(len == 0u || fwrite(bytes, 1u, len, f) == len);
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
}

static void assert_time(uint64_t expected, uint64_t actual, const char *what)
{
    TEST_ASSERT_EQUAL_UINT_MESSAGE((uint32_t)(expected >> 32), (uint32_t)(actual >> 32), what);
    TEST_ASSERT_EQUAL_UINT_MESSAGE((uint32_t)expected, (uint32_t)actual, what);
}

/* Writes raw[0..len) to path as a recording in random chunks (many small
 * ones, as a serial read gives, and some above the block limit) at rising,
 * sometimes equal, times. g_blocks gets the blocks as the format splits
 * them; returns their number. */
static size_t record(const char *path, size_t len, uint32_t seed)
{
    g_blocks = malloc((len + 1u) * sizeof *g_blocks);
    TEST_ASSERT_NOT_NULL(g_blocks);
    recording_writer_t w;
    TEST_ASSERT_EQUAL_INT(0, recording_writer_open(&w, path));
    size_t nblocks = 0u;
    size_t done = 0u;
    uint64_t t = (uint64_t)rnd_range(&seed, 0u, 100000u) * 1000u;
    while (done < len) {
        size_t n = (rnd(&seed) % 16u == 0u) ? rnd_range(&seed, 4000u, 9000u)
                                            : rnd_range(&seed, 1u, 64u);
        if (n > len - done) {
            n = len - done;
        }
        TEST_ASSERT_EQUAL_INT(0, recording_writer_append(&w, t, g_raw + done, n));
        for (size_t off = 0u; off < n; off += RECORDING_BLOCK_MAX) {
            g_blocks[nblocks].start = done + off;
            g_blocks[nblocks].time_us = t;
            nblocks++;
        }
        done += n;
        t += (rnd(&seed) % 5u == 0u) ? 0u : rnd_range(&seed, 1u, 20000u);
    }
    TEST_ASSERT_EQUAL_INT(0, recording_writer_close(&w));
    g_blocks[nblocks].start = len; /* sentinel */
    return nblocks;
}

/* Reads sf to the end with random read sizes (max_cap 1: byte by byte) and
 * checks bytes and times against g_raw and g_blocks (NULL: a raw stream,
 * time 0). */
static void check_read_back(stream_file_t *sf, size_t len, size_t nblocks, size_t max_cap,
                            uint32_t seed)
{
    static uint8_t buf[STREAM_FILE_CHUNK + 100u];
    size_t pos = 0u;
    size_t b = 0u;
    for (;;) {
        const size_t cap = rnd_range(&seed, 1u, (uint32_t)max_cap);
        size_t got = 12345u;
        const stream_read_t r = stream_file_read(sf, buf, cap, &got);
        if (r == STREAM_READ_END) {
            TEST_ASSERT_EQUAL_UINT(0u, got);
            break;
        }
        TEST_ASSERT_EQUAL_INT_MESSAGE(STREAM_READ_DATA, r, "read failed");
        TEST_ASSERT_TRUE(got > 0u && got <= cap && got <= len - pos);
        TEST_ASSERT_EQUAL_MEMORY(g_raw + pos, buf, got);
        if (g_blocks == NULL) {
            TEST_ASSERT_EQUAL_INT(0, sf->is_recording);
            assert_time(0u, sf->time_us, "raw time");
        } else {
            TEST_ASSERT_EQUAL_INT(1, sf->is_recording);
            while (b + 1u < nblocks && g_blocks[b + 1u].start <= pos) {
                b++;
            }
            /* One block per read at most, and its time. */
            TEST_ASSERT_TRUE(pos + got <= g_blocks[b + 1u].start);
            assert_time(g_blocks[b].time_us, sf->time_us, "block time");
        }
        pos += got;
    }
    TEST_ASSERT_EQUAL_UINT(len, pos);
    TEST_ASSERT_NULL(sf->bad);
    TEST_ASSERT_EQUAL_INT(0, sf->error);
    /* The end stays the end. */
    size_t got = 1u;
    TEST_ASSERT_EQUAL_INT(STREAM_READ_END, stream_file_read(sf, buf, 16u, &got));
}

static void read_file_back(const char *path, size_t len, size_t nblocks, size_t max_cap,
                           uint32_t seed)
{
    stream_file_t sf;
    TEST_ASSERT_EQUAL_INT(0, stream_file_open(&sf, path));
    check_read_back(&sf, len, nblocks, max_cap, seed);
    stream_file_close(&sf);
}

static void test_recording_round_trip(void)
{
    const size_t len = load(LMSEGO_DATA_DIR "/recordings/room_181_mm.lms");
    TEST_ASSERT_TRUE(len > 10000u);
    /* Kept for the CLI tests. */
    const char *path = LMSEGO_REC_OUT_DIR "/room_181_mm.lmsrec";
    const size_t nblocks = record(path, len, 0x1234567u);
    TEST_ASSERT_TRUE(nblocks > 100u);
    read_file_back(path, len, nblocks, STREAM_FILE_CHUNK, 1u);
    read_file_back(path, len, nblocks, 1u, 2u);
    read_file_back(path, len, nblocks, 700u, 3u);
    read_file_back(path, len, nblocks, STREAM_FILE_CHUNK + 100u, 4u);
    /* Always the chunk size, as the subcommands read. */
    stream_file_t sf;
    TEST_ASSERT_EQUAL_INT(0, stream_file_open(&sf, path));
    uint8_t chunk[STREAM_FILE_CHUNK];
    size_t total = 0u;
    size_t got = 0u;
    while (stream_file_read(&sf, chunk, sizeof chunk, &got) == STREAM_READ_DATA) {
        total += got;
    }
    TEST_ASSERT_EQUAL_INT(0, sf.error);
    TEST_ASSERT_EQUAL_UINT(len, total);
    stream_file_close(&sf);

    /* The file is exactly magic + blocks. */
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(path, &st));
    TEST_ASSERT_EQUAL_UINT(RECORDING_MAGIC_SIZE + nblocks * RECORDING_HEADER_SIZE + len,
                           (size_t)st.st_size);
}

/* A second stream, for lmsego replay in the CLI tests. */
static void test_recording_round_trip_sequence(void)
{
    const size_t len = load(LMSEGO_DATA_DIR "/sequences/table2_361_cm.lms");
    const char *path = LMSEGO_REC_OUT_DIR "/table2_361_cm.lmsrec";
    const size_t nblocks = record(path, len, 99u);
    read_file_back(path, len, nblocks, STREAM_FILE_CHUNK, 5u);
}

/* stdin is a pipe here: nothing can seek back over the peeked magic. */
static void test_recording_through_stdin_pipe(void)
{
    char path[128];
    tmp_path(path, sizeof path, "a.rec");
    const size_t small = 3000u; /* the whole recording fits in a pipe */
    TEST_ASSERT_TRUE(load(LMSEGO_DATA_DIR "/recordings/room_181_mm.lms") > small);
    const size_t nblocks = record(path, small, 7u);
    FILE *f = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL(f);
    uint8_t file[8192];
    const size_t flen = fread(file, 1u, sizeof file, f);
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
    TEST_ASSERT_TRUE(flen > small && flen < sizeof file);

    int fds[2];
    TEST_ASSERT_EQUAL_INT(0, pipe(fds));
    TEST_ASSERT_EQUAL_INT((int)flen, (int)write(fds[1], file, flen));
    TEST_ASSERT_EQUAL_INT(0, close(fds[1]));
    TEST_ASSERT_EQUAL_INT(0, dup2(fds[0], 0));
    TEST_ASSERT_EQUAL_INT(0, close(fds[0]));
    clearerr(stdin);

    stream_file_t sf;
    TEST_ASSERT_EQUAL_INT(0, stream_file_open(&sf, "-"));
    TEST_ASSERT_TRUE(sf.is_stdin != 0);
    check_read_back(&sf, small, nblocks, 100u, 8u);
    stream_file_close(&sf);
}

static void test_recording_raw_streams_unchanged(void)
{
    const size_t len = load(LMSEGO_DATA_DIR "/recordings/room_181_mm.lms");
    read_file_back(LMSEGO_DATA_DIR "/recordings/room_181_mm.lms", len, 0u, STREAM_FILE_CHUNK, 9u);
    read_file_back(LMSEGO_DATA_DIR "/recordings/room_181_mm.lms", len, 0u, 5u, 10u);

    /* Short files, and files that look almost like a recording. */
    static const struct {
        const char *name;
        const char *bytes;
        size_t len;
    } cases[] = {
        {"empty", "", 0u},
        {"three bytes", "\x02\x80\x03", 3u},
        {"magic less one byte", "LMSREC1", 7u},
        {"other version", "LMSREC2\n\x02\x80", 10u},
        {"magic without newline", "LMSREC1\r\x00\x00", 10u},
    };
    char path[128];
    tmp_path(path, sizeof path, "raw.lms");
    for (size_t i = 0u; i < sizeof cases / sizeof cases[0]; i++) {
        write_file(path, (const uint8_t *)cases[i].bytes, cases[i].len);
        for (size_t cap = 1u; cap <= 12u; cap += 11u) {
            stream_file_t sf;
            TEST_ASSERT_EQUAL_INT(0, stream_file_open(&sf, path));
            uint8_t buf[16];
            size_t pos = 0u;
            size_t got = 0u;
            stream_read_t r;
            while ((r = stream_file_read(&sf, buf, cap, &got)) == STREAM_READ_DATA) {
                TEST_ASSERT_TRUE_MESSAGE(pos + got <= cases[i].len, cases[i].name);
                TEST_ASSERT_EQUAL_MEMORY_MESSAGE(cases[i].bytes + pos, buf, got, cases[i].name);
                pos += got;
            }
            TEST_ASSERT_EQUAL_INT_MESSAGE(STREAM_READ_END, r, cases[i].name);
            TEST_ASSERT_EQUAL_UINT_MESSAGE(cases[i].len, pos, cases[i].name);
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, sf.is_recording, cases[i].name);
            stream_file_close(&sf);
        }
    }
}

/* Block header bytes. */
static size_t put_block(uint8_t *out, uint64_t t, uint16_t len)
{
    recording_put_header(out, t, len);
    for (size_t i = 0u; i < len; i++) {
        out[RECORDING_HEADER_SIZE + i] = (uint8_t)(0xA0u + i);
    }
    return RECORDING_HEADER_SIZE + len;
}

typedef struct {
    const char *name;
    size_t data_bytes;  /* payload handed out before the refusal */
    uint64_t at;        /* bad_offset */
} bad_case_t;

/* Reads path to its refusal and checks it. */
static void expect_refusal(const char *path, const bad_case_t *c)
{
    stream_file_t sf;
    TEST_ASSERT_EQUAL_INT(0, stream_file_open(&sf, path));
    uint8_t buf[STREAM_FILE_CHUNK];
    size_t total = 0u;
    size_t got = 0u;
    stream_read_t r;
    while ((r = stream_file_read(&sf, buf, sizeof buf, &got)) == STREAM_READ_DATA) {
        total += got;
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(STREAM_READ_ERROR, r, c->name);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, got, c->name);
    TEST_ASSERT_EQUAL_INT_MESSAGE(EBADMSG, sf.error, c->name);
    TEST_ASSERT_TRUE_MESSAGE(sf.bad != NULL, c->name);
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, sf.is_recording, c->name);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(c->data_bytes, total, c->name);
    TEST_ASSERT_EQUAL_UINT_MESSAGE((uint32_t)c->at, (uint32_t)sf.bad_offset, c->name);
    /* The refusal sticks. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(STREAM_READ_ERROR, stream_file_read(&sf, buf, 8u, &got),
                                  c->name);
    stream_file_close(&sf);
}

static void test_recording_malformed_refused(void)
{
    char path[128];
    tmp_path(path, sizeof path, "b.rec");
    uint8_t file[2 * (RECORDING_HEADER_SIZE + RECORDING_BLOCK_MAX) + 64u];
    const size_t m = RECORDING_MAGIC_SIZE;
    (void)memcpy(file, RECORDING_MAGIC, m);
    size_t n;

    n = m + put_block(file + m, 0u, 0u);
    const bad_case_t zero = {"length 0", 0u, 8u};
    write_file(path, file, n);
    expect_refusal(path, &zero);

    n = m + put_block(file + m, 0u, 5u);
    recording_put_header(file + m, 0u, (uint16_t)(RECORDING_BLOCK_MAX + 1u));
    const bad_case_t too_long = {"length 4097", 0u, 8u};
    write_file(path, file, n);
    expect_refusal(path, &too_long);

    recording_put_header(file + m, 0u, 0xFFFFu);
    const bad_case_t huge = {"length 65535", 0u, 8u};
    write_file(path, file, n);
    expect_refusal(path, &huge);

    n = m + put_block(file + m, 100u, 2u);
    n += put_block(file + n, 99u, 1u);
    const bad_case_t backwards = {"time going backwards", 2u, 20u};
    write_file(path, file, n);
    expect_refusal(path, &backwards);
    /* Also for the CLI test. */
    write_file(LMSEGO_REC_OUT_DIR "/backwards.lmsrec", file, n);

    n = m + put_block(file + m, 5u, 3u);
    n += put_block(file + n, 6u, 3u) - 8u; /* 5 header bytes of 10 */
    const bad_case_t header_cut = {"header cut short", 3u, 21u};
    write_file(path, file, n);
    expect_refusal(path, &header_cut);

    n = m + put_block(file + m, 5u, 3u) + 1u; /* one byte of a header */
    file[n - 1u] = 0x00u;
    const bad_case_t one_byte = {"one header byte", 3u, 21u};
    write_file(path, file, n);
    expect_refusal(path, &one_byte);

    n = m + put_block(file + m, 7u, 10u) - 6u; /* 4 of 10 payload bytes */
    const bad_case_t payload_cut = {"payload cut short", 4u, 8u};
    write_file(path, file, n);
    expect_refusal(path, &payload_cut);
}

/* Edges that are fine: no blocks at all, a full 4096-byte block, the
 * largest time, equal times. */
static void test_recording_edges_accepted(void)
{
    char path[128];
    tmp_path(path, sizeof path, "b.rec");
    uint8_t file[2 * (RECORDING_HEADER_SIZE + RECORDING_BLOCK_MAX) + 64u];
    const size_t m = RECORDING_MAGIC_SIZE;
    (void)memcpy(file, RECORDING_MAGIC, m);

    write_file(path, file, m);
    stream_file_t sf;
    TEST_ASSERT_EQUAL_INT(0, stream_file_open(&sf, path));
    uint8_t buf[STREAM_FILE_CHUNK + 8u];
    size_t got = 0u;
    TEST_ASSERT_EQUAL_INT(STREAM_READ_END, stream_file_read(&sf, buf, sizeof buf, &got));
    TEST_ASSERT_EQUAL_INT(1, sf.is_recording);
    stream_file_close(&sf);

    size_t n = m + put_block(file + m, 3u, (uint16_t)RECORDING_BLOCK_MAX);
    n += put_block(file + n, UINT64_MAX, 2u);
    n += put_block(file + n, UINT64_MAX, 1u);
    write_file(path, file, n);
    TEST_ASSERT_EQUAL_INT(0, stream_file_open(&sf, path));
    TEST_ASSERT_EQUAL_INT(STREAM_READ_DATA, stream_file_read(&sf, buf, sizeof buf, &got));
    TEST_ASSERT_EQUAL_UINT(RECORDING_BLOCK_MAX, got); /* one block per read */
    assert_time(3u, sf.time_us, "first");
    TEST_ASSERT_EQUAL_INT(STREAM_READ_DATA, stream_file_read(&sf, buf, sizeof buf, &got));
    TEST_ASSERT_EQUAL_UINT(2u, got);
    assert_time(UINT64_MAX, sf.time_us, "second");
    TEST_ASSERT_EQUAL_INT(STREAM_READ_DATA, stream_file_read(&sf, buf, sizeof buf, &got));
    TEST_ASSERT_EQUAL_UINT(1u, got);
    TEST_ASSERT_EQUAL_INT(STREAM_READ_END, stream_file_read(&sf, buf, sizeof buf, &got));
    stream_file_close(&sf);

    TEST_ASSERT_EQUAL_INT(0, stream_file_open(&sf, path));
    TEST_ASSERT_EQUAL_INT(STREAM_READ_ERROR, stream_file_read(&sf, buf, 0u, &got));
    TEST_ASSERT_EQUAL_INT(EINVAL, sf.error);
    stream_file_close(&sf);
}

static void test_recording_writer_splits_and_refuses(void)
{
    char path[128];
    tmp_path(path, sizeof path, "a.rec");
    static uint8_t data[10000];
    for (size_t i = 0u; i < sizeof data; i++) {
        data[i] = (uint8_t)(i * 13u);
    }
    recording_writer_t w;
    TEST_ASSERT_EQUAL_INT(0, recording_writer_open(&w, path));
    TEST_ASSERT_EQUAL_INT(0, recording_writer_append(&w, 0x0102030405060708u, data, sizeof data));
    TEST_ASSERT_EQUAL_INT(EINVAL, recording_writer_append(&w, 5u, data, 1u)); /* backwards */
    TEST_ASSERT_EQUAL_INT(0, recording_writer_append(&w, 6u, data, 0u));      /* nothing */
    TEST_ASSERT_EQUAL_INT(EINVAL, recording_writer_append(&w, 0x0102030405060709u, NULL, 3u));
    TEST_ASSERT_EQUAL_INT(0, recording_writer_append(&w, 0x0102030405060708u, data, 1u));
    TEST_ASSERT_EQUAL_INT(0, recording_writer_flush(&w));
    TEST_ASSERT_EQUAL_INT(0, recording_writer_close(&w));
    TEST_ASSERT_EQUAL_INT(0, recording_writer_close(&w)); /* twice is harmless */
    TEST_ASSERT_EQUAL_INT(EBADF, recording_writer_append(&w, 9u, data, 1u));

    const size_t len = load(path);
    const size_t parts[] = {4096u, 4096u, 1808u, 1u};
    TEST_ASSERT_EQUAL_UINT(8u + 4u * 10u + sizeof data + 1u, len);
    TEST_ASSERT_EQUAL_MEMORY("LMSREC1\n", g_raw, 8u);
    size_t at = 8u;
    size_t from = 0u;
    for (size_t i = 0u; i < 4u; i++) {
        const uint8_t header[10] = {8, 7, 6, 5, 4, 3, 2, 1, (uint8_t)(parts[i] & 0xFFu),
                                    (uint8_t)(parts[i] >> 8)};
        TEST_ASSERT_EQUAL_HEX8_ARRAY(header, g_raw + at, 10u);
        TEST_ASSERT_EQUAL_MEMORY(data + (i < 3u ? from : 0u), g_raw + at + 10u, parts[i]);
        at += 10u + parts[i];
        from += parts[i];
    }
}

static void test_recording_writer_reports_errors(void)
{
    recording_writer_t w;
    TEST_ASSERT_EQUAL_INT(ENOENT, recording_writer_open(&w, "/nonexistent-dir/x.rec"));
    TEST_ASSERT_NULL(w.fp);
    TEST_ASSERT_EQUAL_INT(ENOENT, recording_writer_close(&w));

    if (access("/dev/full", W_OK) != 0) {
        return; /* no /dev/full here: nothing to fill */
    }
    /* Small writes stay in the stdio buffer: the flush sees the error. */
    static uint8_t data[20000];
    TEST_ASSERT_EQUAL_INT(0, recording_writer_open(&w, "/dev/full"));
    TEST_ASSERT_EQUAL_INT(0, recording_writer_append(&w, 1u, data, 10u));
    TEST_ASSERT_EQUAL_INT(ENOSPC, recording_writer_flush(&w));
    TEST_ASSERT_EQUAL_INT(ENOSPC, recording_writer_append(&w, 2u, data, 10u)); /* sticky */
    TEST_ASSERT_EQUAL_INT(ENOSPC, recording_writer_close(&w));
    TEST_ASSERT_NULL(w.fp);

    /* Large appends fail in the append itself, at the latest on close. */
    TEST_ASSERT_EQUAL_INT(0, recording_writer_open(&w, "/dev/full"));
    int first = 0;
    for (int i = 0; i < 8 && first == 0; i++) {
        first = recording_writer_append(&w, (uint64_t)i, data, sizeof data);
    }
    TEST_ASSERT_EQUAL_INT(ENOSPC, first);
    TEST_ASSERT_EQUAL_INT(ENOSPC, recording_writer_close(&w));
}

/* --- play_timing.h ------------------------------------------------------ */

#define ROT PLAY_ROTATION_US
#define N_PLAY 60u

/* Scan k leaves the scanner at k rotations and is read 500 us later. */
static void steady_reads(uint64_t *t, size_t n)
{
    for (size_t k = 0u; k < n; k++) {
        t[k] = 1000000u + (uint64_t)k * ROT + 500u;
    }
}

static void test_play_gaps_keep_steady_reads(void)
{
    static uint64_t t[N_PLAY];
    static uint32_t gap[N_PLAY];
    /* 50 Hz reads (a rotation and a half apart, jittered): as recorded. */
    for (size_t k = 0u; k < N_PLAY; k++) {
        t[k] = 2000000u + (uint64_t)k * 20000u + (k % 3u) * 900u;
    }
    play_wire_gaps(t, gap, N_PLAY);
    TEST_ASSERT_EQUAL_UINT32(0u, gap[0]);
    for (size_t k = 1u; k < N_PLAY; k++) {
        const uint64_t want = 20000u + (k % 3u) * 900u - ((k - 1u) % 3u) * 900u;
        TEST_ASSERT_EQUAL_UINT32((uint32_t)want, gap[k]);
    }
}

static void test_play_gaps_drop_a_busy_readers_delay(void)
{
    static uint64_t t[N_PLAY];
    static uint32_t gap[N_PLAY];
    steady_reads(t, N_PLAY);
    /* The recorder was busy from scan 10 to scan 21: it read those 12
     * scans at once, 3 ms after scan 21 arrived. */
    const uint64_t late = t[21] + 3000u;
    for (size_t k = 10u; k <= 21u; k++) {
        t[k] = late;
    }
    TEST_ASSERT_TRUE(t[10] - t[9] > 8u * ROT); /* as recorded: a silence */
    const uint64_t first = t[0];
    const uint64_t last = t[N_PLAY - 1u];
    play_wire_gaps(t, gap, N_PLAY);
    /* Scan 22 came on time, a rotation after 21 left: the schedule is
     * recovered exactly. */
    uint64_t sum = 0u;
    for (size_t k = 1u; k < N_PLAY; k++) {
        TEST_ASSERT_EQUAL_UINT32(ROT, gap[k]);
        sum += gap[k];
    }
    /* The last scan keeps its time; the first was not late. */
    TEST_ASSERT_EQUAL_UINT(last, t[N_PLAY - 1u]);
    TEST_ASSERT_EQUAL_UINT(first, t[0]);
    TEST_ASSERT_EQUAL_UINT(last - first, sum);
}

static void test_play_gaps_keep_an_outage(void)
{
    static uint64_t t[N_PLAY];
    static uint32_t gap[N_PLAY];
    steady_reads(t, N_PLAY);
    /* The scanner fell silent for 40 rotations after scan 10. */
    for (size_t k = 11u; k < N_PLAY; k++) {
        t[k] += 40u * ROT;
    }
    play_wire_gaps(t, gap, N_PLAY);
    for (size_t k = 1u; k < N_PLAY; k++) {
        TEST_ASSERT_EQUAL_UINT32(k == 11u ? 41u * ROT : ROT, gap[k]);
    }
}

static void test_play_gaps_edges(void)
{
    uint64_t t[3] = {0u, 60000000u, 60000000u + ROT};
    uint32_t gap[3] = {7u, 7u, 7u};
    play_wire_gaps(t, gap, 0u); /* nothing */
    TEST_ASSERT_EQUAL_UINT32(7u, gap[0]);
    play_wire_gaps(t, gap, 1u);
    TEST_ASSERT_EQUAL_UINT32(0u, gap[0]);
    /* A minute's pause is played as PLAY_GAP_MAX_US. */
    play_wire_gaps(t, gap, 3u);
    TEST_ASSERT_EQUAL_UINT32(PLAY_GAP_MAX_US, gap[1]);
    TEST_ASSERT_EQUAL_UINT32(ROT, gap[2]);
    /* Three scans read at once 5 ms into the recording: the wire times
     * stop at 0. */
    uint64_t u[3] = {5000u, 5000u, 5000u};
    play_wire_gaps(u, gap, 3u);
    TEST_ASSERT_EQUAL_UINT(0u, u[0]);
    TEST_ASSERT_EQUAL_UINT(0u, u[1]);
    TEST_ASSERT_EQUAL_UINT(5000u, u[2]);
    TEST_ASSERT_EQUAL_UINT32(0u, gap[1]);
    TEST_ASSERT_EQUAL_UINT32(5000u, gap[2]);
}

static void test_play_cursor_resumes_a_restarted_stream(void)
{
    play_cursor_t c = {0u, 0u, false};
    /* Scans 0..2 leave, 3 is fetched when 2 left. */
    for (uint32_t k = 0u; k <= 3u; k++) {
        TEST_ASSERT_EQUAL_UINT(k, play_cursor_index(&c, k));
    }
    /* The host restarts the stream: 3 never left, so it comes first. */
    TEST_ASSERT_EQUAL_UINT(3u, play_cursor_index(&c, 0u));
    TEST_ASSERT_EQUAL_UINT(4u, play_cursor_index(&c, 1u));
    /* Again, with 4 fetched and not sent; then once more before any scan
     * left: no scan is skipped or repeated. */
    TEST_ASSERT_EQUAL_UINT(4u, play_cursor_index(&c, 0u));
    TEST_ASSERT_EQUAL_UINT(4u, play_cursor_index(&c, 0u));
    TEST_ASSERT_EQUAL_UINT(5u, play_cursor_index(&c, 1u));
    TEST_ASSERT_EQUAL_UINT(6u, play_cursor_index(&c, 2u));
}

int main(void)
{
    /* The directory the CLI tests read from. */
    if (mkdir(LMSEGO_REC_OUT_DIR, 0777) != 0 && errno != EEXIST) {
        perror(LMSEGO_REC_OUT_DIR);
        return 1;
    }
    UNITY_BEGIN();
    RUN_TEST(test_recording_round_trip);
    RUN_TEST(test_recording_round_trip_sequence);
    RUN_TEST(test_recording_through_stdin_pipe);
    RUN_TEST(test_recording_raw_streams_unchanged);
    RUN_TEST(test_recording_malformed_refused);
    RUN_TEST(test_recording_edges_accepted);
    RUN_TEST(test_recording_writer_splits_and_refuses);
    RUN_TEST(test_recording_writer_reports_errors);
    RUN_TEST(test_play_gaps_keep_steady_reads);
    RUN_TEST(test_play_gaps_drop_a_busy_readers_delay);
    RUN_TEST(test_play_gaps_keep_an_outage);
    RUN_TEST(test_play_gaps_edges);
    RUN_TEST(test_play_cursor_resumes_a_restarted_stream);
    return UNITY_END();
}
