/* main_framer.c - what the telegram framer (driver/lms_framer.h) and the B0
 * decoder (driver/lms_decode.h) cost on the target, in instructions per
 * input byte, over a recorded stream compiled into flash (lmsego_stream,
 * cmake/bin2c.cmake).
 *
 * Two passes over the stream, fed straight from flash in chunks of
 * EGO_LOOP_READ_CHUNK bytes as ego_loop_step feeds it (its copy into a
 * receive buffer is the HAL's, not counted): the first only frames, the
 * second frames and decodes every B0 telegram, as ego_loop does. Each pass is counted whole
 * with SysTick under QEMU's -icount (target.h): one tick is 40
 * instructions, too coarse to time a single call. The decoder's cost is
 * the difference of the two passes. After the passes it writes
 *   # framer bytes=B telegrams=T scans=S crc_errors=C length_errors=L decode_errors=E
 *   # framer_insns=F decode_insns=D
 *   # framer_insns_per_byte=F/B           (two decimals, rounded)
 *   # decode_insns_per_scan=D/S
 *   # framer_decoder_insns_per_byte=(F+D)/B
 *   # stack_bytes used=U of=Z
 * and exits 0, or 1 when the two passes found different telegrams
 * (ctest target_framer_*, run_framer.cmake, checks the counts against the
 * host's `lmsego stats`).
 */
#include <stdbool.h>
#include <stdint.h>

#include "ego_loop.h"
#include "lms_decode.h"
#include "lms_framer.h"
#include "report.h"
#include "target.h"

extern const uint8_t lmsego_stream[];
extern const uint32_t lmsego_stream_size;

typedef struct {
    uint32_t telegrams;
    uint32_t scans;
    uint32_t decode_errors;
} pass_counts_t;

static lms_framer_t framer;
static lms_scan_t scan;

static void on_event(lms_framer_event_t ev, bool decode, pass_counts_t *counts)
{
    if (ev != LMS_FRAMER_TELEGRAM) {
        return;
    }
    size_t len = 0u;
    const uint8_t *t = lms_framer_telegram(&framer, &len);
    counts->telegrams++;
    if (!decode || t == NULL || len <= LMS_HEADER_SIZE || t[LMS_HEADER_SIZE] != LMS_REPLY_VALUES) {
        return;
    }
    if (lms_decode_scan(t, len, &scan) == LMS_OK) {
        counts->scans++;
    } else {
        counts->decode_errors++;
    }
}

/* One pass over the stream; returns its instructions. */
static uint64_t run_pass(bool decode, pass_counts_t *counts)
{
    lms_framer_init(&framer, LMS_FROM_SCANNER);
    const uint64_t start = target_instructions();
    uint32_t pos = 0u;
    while (pos < lmsego_stream_size) {
        const uint32_t left = lmsego_stream_size - pos;
        const size_t n = left < EGO_LOOP_READ_CHUNK ? (size_t)left : EGO_LOOP_READ_CHUNK;
        const uint8_t *chunk = &lmsego_stream[pos];
        pos += (uint32_t)n;
        size_t offset = 0u;
        for (;;) { /* ends: NEED_MORE once every byte of the chunk is used */
            size_t used = 0u;
            const lms_framer_event_t ev =
                lms_framer_feed(&framer, &chunk[offset], n - offset, &used);
            offset += used;
            if (ev == LMS_FRAMER_NEED_MORE) {
                break;
            }
            on_event(ev, decode, counts);
        }
    }
    /* End of input, as in ego_loop_step: what the framer holds comes out. */
    for (uint32_t guard = 0u; guard <= LMS_FRAMER_BUF_SIZE + 1u; guard++) {
        const lms_framer_event_t ev = lms_framer_flush(&framer);
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        on_event(ev, decode, counts);
    }
    return target_instructions() - start;
}

/* num / den with two decimals, rounded to nearest. */
static void put_ratio(const char *name, uint64_t num, uint64_t den)
{
    report_fixed(name, den == 0u ? 0u : (num * 100u + den / 2u) / den, 2u);
}

int main(void)
{
    target_uart_init();
    target_clock_init();
    static pass_counts_t framed;
    static pass_counts_t decoded;
    const uint64_t framing = run_pass(false, &framed);
    const uint64_t both = run_pass(true, &decoded);
    const lms_framer_stats_t *st = lms_framer_stats(&framer);
    const uint64_t decoding = both > framing ? both - framing : 0u;

    report_field("# framer bytes=", st->bytes_in);
    report_field(" telegrams=", st->telegrams);
    report_field(" scans=", decoded.scans);
    report_field(" crc_errors=", st->crc_errors);
    report_field(" length_errors=", st->length_errors);
    report_field(" decode_errors=", decoded.decode_errors);
    report_field("\n# framer_insns=", framing);
    report_field(" decode_insns=", decoding);
    put_ratio("\n# framer_insns_per_byte=", framing, st->bytes_in);
    put_ratio("\n# decode_insns_per_scan=", decoding, decoded.scans);
    put_ratio("\n# framer_decoder_insns_per_byte=", both, st->bytes_in);
    report_field("\n# stack_bytes used=", target_stack_used());
    report_field(" of=", target_stack_size());
    target_uart_puts("\n");
    const bool same = framed.telegrams == decoded.telegrams && framed.telegrams == st->telegrams;
    target_exit(same ? TARGET_EXIT_OK : TARGET_EXIT_FAILED);
}
