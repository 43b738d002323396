/* fuzz_frame.c - libFuzzer target over the binary ego-motion frame decoder
 * (firmware/ego_frame.h), what `lmsego frames` and a vehicle computer run
 * on bytes from a serial line.
 *
 * Input: the first byte seeds the chunking (chunks of 1..32 bytes from a
 * small generator), the rest is the byte stream given to ego_frame_feed.
 *
 * Checks (abort on violation):
 *  - after every feed and flush: bytes_in == bytes_framed + bytes_skipped
 *    + pending, pending < EGO_FRAME_SIZE, and *consumed <= the bytes given;
 *  - NEED_MORE uses every byte given;
 *  - every reported frame: bytes_framed grows by 66 (version 2) or 42
 *    (version 1), frames by one (it counted the whole buffer once: a
 *    version 1 frame inside a failed version 2 candidate, see
 *    docs/robustness.md); a version 2 frame re-encodes (ego_frame_encode)
 *    to 66 bytes that occur in the stream consumed so far, a version 1
 *    frame's covariance says "not measured";
 *  - ego_format_line of every frame writes one NUL-terminated line ending
 *    in a newline, within EGO_LOOP_LINE_MAX;
 *  - after the final flush nothing is pending;
 *  - no crash, no undefined behaviour (ASan, UBSan).
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "ego_frame.h"
#include "ego_loop.h"
#include "fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_accounting(const ego_frame_decoder_t *d)
{
    const ego_frame_stats_t *s = ego_frame_stats(d);
    const size_t pending = ego_frame_pending(d);
    FUZZ_CHECK(pending < EGO_FRAME_SIZE);
    FUZZ_CHECK(s->bytes_in == s->bytes_framed + s->bytes_skipped + (uint32_t)pending);
}

/* Whether the n bytes at needle occur in hay[0..len). */
static bool occurs(const uint8_t *hay, size_t len, const uint8_t *needle, size_t n)
{
    for (size_t k = 0u; k + n <= len; k++) {
        if (hay[k] == needle[0] && memcmp(&hay[k], needle, n) == 0) {
            return true;
        }
    }
    return false;
}

/* The frame just reported, which completed within stream[0..end). */
static void check_frame(const ego_frame_t *f, uint32_t framed_growth, const uint8_t *stream,
                        size_t end)
{
    static char line[EGO_LOOP_LINE_MAX + 1u];
    FUZZ_CHECK(framed_growth == EGO_FRAME_SIZE || framed_growth == EGO_FRAME_V1_SIZE);
    FUZZ_CHECK(end >= framed_growth);
    if (framed_growth == EGO_FRAME_SIZE) {
        uint8_t again[EGO_FRAME_SIZE];
        FUZZ_CHECK(ego_frame_encode(again, sizeof again, f->scan, f->time_us, &f->out) ==
                   EGO_FRAME_SIZE);
        FUZZ_CHECK(occurs(stream, end, again, sizeof again));
    } else {
        FUZZ_CHECK(f->out.cov.xx == EGO_COV_SATURATED && f->out.cov.yy == EGO_COV_SATURATED &&
                   f->out.cov.tt == EGO_COV_SATURATED);
    }
    const size_t n = ego_format_line(line, sizeof line, f->scan, f->time_us, &f->out);
    FUZZ_CHECK(n > 0u && n < sizeof line && line[n] == '\0' && line[n - 1u] == '\n');
    FUZZ_CHECK(strlen(line) == n && memchr(line, '\n', n) == &line[n - 1u]);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static ego_frame_decoder_t d;
    static ego_frame_t frame;
    if (size < 1u) {
        return 0;
    }
    const uint8_t *stream = data + 1;
    const size_t total = size - 1u;
    ego_frame_decoder_init(&d);
    uint32_t state = 0x2545F491u ^ data[0];
    size_t at = 0u;
    while (at < total) {
        state = state * 1664525u + 1013904223u;
        size_t chunk = 1u + ((state >> 24) & 0x1Fu);
        if (chunk > total - at) {
            chunk = total - at;
        }
        size_t pos = 0u;
        for (;;) {
            size_t used = 0u;
            const uint32_t framed = ego_frame_stats(&d)->bytes_framed;
            const uint32_t frames = ego_frame_stats(&d)->frames;
            const ego_frame_event_t ev =
                ego_frame_feed(&d, stream + at + pos, chunk - pos, &used, &frame);
            FUZZ_CHECK(used <= chunk - pos);
            pos += used;
            check_accounting(&d);
            if (ev == EGO_FRAME_NEED_MORE) {
                FUZZ_CHECK(pos == chunk);
                FUZZ_CHECK(ego_frame_stats(&d)->frames == frames);
                break;
            }
            FUZZ_CHECK(ev == EGO_FRAME_READY);
            FUZZ_CHECK(ego_frame_stats(&d)->frames == frames + 1u);
            check_frame(&frame, ego_frame_stats(&d)->bytes_framed - framed, stream, at + pos);
        }
        at += chunk;
    }
    ego_frame_flush(&d);
    check_accounting(&d);
    FUZZ_CHECK(ego_frame_pending(&d) == 0u);
    return 0;
}
