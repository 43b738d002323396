/* fuzz_codec.c - libFuzzer target over the whole telegram codec.
 *
 * The input is split in two: the first byte picks the direction and a
 * chunking seed, the rest is the byte stream. Every reported telegram must
 * pass lms_telegram_parse, every decoder must return without touching
 * memory it does not own (ASan/UBSan watch), a decoded B0 must re-encode to
 * the same bytes (the reserved count-word bit 10 aside), and the framer's
 * byte accounting must balance after every call. A broken property traps,
 * which libFuzzer reports as a crash.
 */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "lms_decode.h"
#include "lms_encode.h"
#include "lms_framer.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond)               \
    do {                          \
        if (!(cond)) {            \
            __builtin_trap();     \
        }                         \
    } while (0)

static void check_accounting(const lms_framer_t *f)
{
    const lms_framer_stats_t *s = lms_framer_stats(f);
    CHECK(s->bytes_in == s->telegram_bytes + s->acks + s->naks + s->bytes_skipped +
                             (uint32_t)lms_framer_pending(f));
}

static void decode_all(const uint8_t *t, size_t len)
{
    static lms_scan_t scan;
    static uint8_t again[LMS_TELEGRAM_MAX];
    lms_telegram_t tel;
    CHECK(lms_telegram_parse(t, len, &tel) == LMS_OK);

    if (lms_decode_scan(t, len, &scan) == LMS_OK) {
        size_t written = 0u;
        CHECK(lms_encode_scan(again, sizeof again, scan.address, &scan, &written) == LMS_OK);
        /* Bit for bit, but for the reserved count-word bit 10 (byte 6,
         * bit 2), which the scan does not keep; the CRC then differs. */
        CHECK(written == len);
        if ((t[6] & 0x04u) == 0u) {
            CHECK(memcmp(again, t, len) == 0);
        } else {
            CHECK(memcmp(again, t, 6u) == 0 && again[6] == (uint8_t)(t[6] & ~0x04u) &&
                  memcmp(&again[7], &t[7], len - 9u) == 0);
        }
        lms_layout_t layout;
        (void)lms_scan_layout(&scan, &layout);
        for (uint16_t i = 0u; i < scan.count; i++) {
            lms_value_t v;
            CHECK(lms_value_decode(scan.values[i], LMS_MEAS_16M_REFLECTOR, scan.unit, &v) ==
                  LMS_OK);
        }
    }
    lms_mode_reply_t mode;
    lms_ident_t ident;
    lms_bare_reply_t bare;
    lms_device_status_t status;
    lms_variant_reply_t variant;
    lms_config_reply_t config;
    lms_config_write_reply_t written_config;
    (void)lms_decode_mode_reply(t, len, &mode);
    (void)lms_decode_power_on(t, len, &ident);
    (void)lms_decode_type(t, len, &ident);
    (void)lms_decode_reset_ack(t, len, &bare);
    (void)lms_decode_not_ack(t, len, &bare);
    (void)lms_decode_status(t, len, &status);
    (void)lms_decode_variant_reply(t, len, &variant);
    (void)lms_decode_config(t, len, &config);
    (void)lms_decode_config_write_reply(t, len, &written_config);
}

static void handle(const lms_framer_t *f, lms_framer_event_t ev)
{
    if (ev == LMS_FRAMER_TELEGRAM) {
        size_t len = 0u;
        const uint8_t *t = lms_framer_telegram(f, &len);
        CHECK(t != NULL && len >= LMS_OVERHEAD + 1u && len <= LMS_TELEGRAM_MAX);
        decode_all(t, len);
    } else {
        size_t len = 1u;
        CHECK(lms_framer_telegram(f, &len) == NULL && len == 0u);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static lms_framer_t framer;
    if (size < 1u) {
        return 0;
    }
    const uint8_t control = data[0];
    const uint8_t *stream = data + 1;
    size_t left = size - 1u;
    lms_framer_init(&framer, (control & 1u) ? LMS_FROM_HOST : LMS_FROM_SCANNER);

    /* Chunk sizes 1..16 from a tiny generator seeded by the control byte. */
    uint32_t state = 0x9E3779B9u ^ control;
    while (left > 0u) {
        state = state * 1664525u + 1013904223u;
        size_t chunk = 1u + ((state >> 24) & 0x0Fu);
        if (chunk > left) {
            chunk = left;
        }
        size_t pos = 0u;
        for (;;) {
            size_t used = 0u;
            const lms_framer_event_t ev = lms_framer_feed(&framer, stream + pos, chunk - pos, &used);
            pos += used;
            check_accounting(&framer);
            if (ev == LMS_FRAMER_NEED_MORE) {
                CHECK(pos == chunk);
                break;
            }
            handle(&framer, ev);
        }
        stream += chunk;
        left -= chunk;
    }
    for (;;) {
        const lms_framer_event_t ev = lms_framer_flush(&framer);
        check_accounting(&framer);
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        handle(&framer, ev);
    }
    CHECK(lms_framer_pending(&framer) == 0u);
    return 0;
}
