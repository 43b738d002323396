/* fuzz_recording.c - libFuzzer target over the recording reader
 * (firmware/host/stream_file.h, format of recording.h): what `lmsego
 * stats`, `scans`, `replay` and `play` read their FILE through.
 *
 * Input: byte 0 picks the read size (1 + b % 64, or STREAM_FILE_CHUNK
 * when b >= 192); the rest is the file, read through fmemopen (a
 * recording when it starts with "LMSREC1\n", else a raw stream). Seeds
 * start with the magic so that the blocks are what gets mutated.
 *
 * Checks (abort on violation), against a model of the format written here
 * from recording.h (not from the reader):
 *  - a raw stream reads back byte for byte, time_us 0, and ends cleanly;
 *  - a recording reads back as the concatenation of its blocks' bytes up
 *    to the first malformed block (header cut short, length 0 or above
 *    4096, time below the previous block's, bytes cut short: those that
 *    are there are given out first), each read within one block (got <=
 *    the block's bytes left, time_us the block's time); then END for a
 *    well-formed file, or ERROR with EBADMSG, a reason in words and
 *    bad_offset the offset of the malformed block's header;
 *  - every DATA read gives 1..cap bytes, END and ERROR give 0; after
 *    END or ERROR, the next read says the same;
 *  - stream_file_problem fits its buffer and names the offset;
 *  - recording_get_header(recording_put_header(t, n)) == (t, n);
 *  - no crash, no undefined behaviour (ASan, UBSan).
 */
#include <errno.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "fuzz_check.h"
#include "recording.h"
#include "stream_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The model's reading of a file: the bytes a reader gives out, block by
 * block, and how it ends. */
typedef struct {
    bool recording;
    bool bad;           /* malformed: ERROR/EBADMSG at the end */
    uint64_t bad_offset;
    size_t n_blocks;    /* blocks whose bytes are given out (the last may be cut short) */
} model_t;

static uint64_t get_le(const uint8_t *p, unsigned n)
{
    uint64_t v = 0u;
    for (unsigned k = 0u; k < n; k++) {
        v |= (uint64_t)p[k] << (8u * k);
    }
    return v;
}

/* Walks the blocks; for block i, *start / *len / *time (when asked for). */
static model_t model(const uint8_t *f, size_t n, size_t want, size_t *start, size_t *len,
                     uint64_t *time)
{
    model_t m = {false, false, 0u, 0u};
    if (n < RECORDING_MAGIC_SIZE || memcmp(f, RECORDING_MAGIC, RECORDING_MAGIC_SIZE) != 0) {
        return m;
    }
    m.recording = true;
    size_t at = RECORDING_MAGIC_SIZE;
    uint64_t last = 0u;
    while (at < n) {
        if (n - at < RECORDING_HEADER_SIZE) {
            m.bad = true;
            m.bad_offset = at;
            return m;
        }
        const uint64_t t = get_le(&f[at], 8u);
        const size_t l = (size_t)get_le(&f[at + 8u], 2u);
        if (l == 0u || l > RECORDING_BLOCK_MAX || (m.n_blocks > 0u && t < last)) {
            m.bad = true;
            m.bad_offset = at;
            return m;
        }
        const size_t body = at + RECORDING_HEADER_SIZE;
        const size_t have = (n - body < l) ? n - body : l;
        if (have == 0u) { /* cut short before its first byte: nothing given out */
            m.bad = true;
            m.bad_offset = at;
            return m;
        }
        if (m.n_blocks == want) {
            *start = body;
            *len = have;
            *time = t;
        }
        m.n_blocks++;
        last = t;
        if (have < l) {
            m.bad = true;
            m.bad_offset = at;
            return m;
        }
        at = body + l;
    }
    return m;
}

static void check_header_round_trip(const uint8_t *p)
{
    uint8_t h[RECORDING_HEADER_SIZE];
    uint64_t t = 0u;
    uint16_t l = 0u;
    const uint64_t t0 = get_le(p, 8u);
    const uint16_t l0 = (uint16_t)get_le(p + 8, 2u);
    recording_put_header(h, t0, l0);
    recording_get_header(h, &t, &l);
    FUZZ_CHECK(t == t0 && l == l0 && memcmp(h, p, sizeof h) == 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static uint8_t buf[STREAM_FILE_CHUNK];
    static uint8_t file[1u << 16];
    if (size < 2u || size - 1u > sizeof file) {
        return 0;
    }
    const size_t cap = (data[0] >= 192u) ? STREAM_FILE_CHUNK : 1u + data[0] % 64u;
    const size_t n = size - 1u;
    memcpy(file, data + 1, n);
    if (n >= RECORDING_HEADER_SIZE) {
        check_header_round_trip(file);
    }

    stream_file_t sf;
    memset(&sf, 0, sizeof sf);
    sf.name = "fuzz";
    sf.fp = fmemopen(file, n, "rb");
    FUZZ_CHECK(sf.fp != NULL);

    size_t d0 = 0u;
    size_t d1 = 0u;
    uint64_t dt = 0u;
    const model_t m = model(file, n, (size_t)-1, &d0, &d1, &dt);
    size_t block = 0u;       /* recording: the block being read */
    size_t block_start = 0u; /* ... its bytes in file, how many, its time */
    size_t block_len = 0u;
    uint64_t block_time = 0u;
    size_t block_done = 0u;
    size_t raw_pos = 0u;
    if (m.recording && m.n_blocks > 0u) {
        (void)model(file, n, 0u, &block_start, &block_len, &block_time);
    }
    stream_read_t r;
    for (;;) {
        size_t got = 12345u;
        r = stream_file_read(&sf, buf, cap, &got);
        if (r != STREAM_READ_DATA) {
            FUZZ_CHECK(got == 0u);
            break;
        }
        FUZZ_CHECK(got >= 1u && got <= cap);
        if (!m.recording) {
            FUZZ_CHECK(!sf.is_recording && sf.time_us == 0u);
            FUZZ_CHECK(raw_pos + got <= n && memcmp(buf, &file[raw_pos], got) == 0);
            raw_pos += got;
            continue;
        }
        FUZZ_CHECK(sf.is_recording);
        if (block_done == block_len) { /* the next block */
            block++;
            FUZZ_CHECK(block < m.n_blocks);
            (void)model(file, n, block, &block_start, &block_len, &block_time);
            block_done = 0u;
        }
        FUZZ_CHECK(block < m.n_blocks && got <= block_len - block_done);
        FUZZ_CHECK(memcmp(buf, &file[block_start + block_done], got) == 0);
        FUZZ_CHECK(sf.time_us == block_time);
        block_done += got;
    }
    if (!m.recording) {
        FUZZ_CHECK(r == STREAM_READ_END && raw_pos == n);
    } else {
        /* Every block's bytes out: the last block entirely, or as many as
         * the file has of it. */
        FUZZ_CHECK(m.n_blocks == 0u || (block + 1u == m.n_blocks && block_done == block_len));
        if (m.bad) {
            char text[160];
            FUZZ_CHECK(r == STREAM_READ_ERROR && sf.error == EBADMSG && sf.bad != NULL);
            FUZZ_CHECK(sf.bad_offset == m.bad_offset);
            const char *p = stream_file_problem(&sf, text, sizeof text);
            FUZZ_CHECK(p != NULL && strlen(p) < sizeof text && strstr(p, " at byte ") != NULL);
        } else {
            FUZZ_CHECK(r == STREAM_READ_END && sf.error == 0 && sf.bad == NULL);
        }
    }
    size_t again = 1u;
    FUZZ_CHECK(stream_file_read(&sf, buf, cap, &again) == r && again == 0u);
    stream_file_close(&sf);
    FUZZ_CHECK(sf.fp == NULL);
    return 0;
}
