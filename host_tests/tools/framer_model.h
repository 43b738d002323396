/* framer_model.h - a slow, deliberately simple model of the lms_framer
 * contract for the scanner -> host direction, used by lmsgen to work out
 * the counters a correct framer must report for a stream it generated.
 *
 * Written from the comments of driver/lms_framer.h only (not from the
 * framer's source), and with its own CRC, so the expected statistics are
 * an independent prediction. It sees the whole stream at once; the
 * contract makes the final counters independent of how the bytes are
 * chunked, and the end of the array plays the part of lms_framer_flush.
 *
 * The rules it applies, in order, at each position while hunting:
 *   06 -> ACK, 15 -> NAK, any other byte except 02 -> skipped;
 *   02 followed by a byte < 0x80 -> the 02 is skipped;
 *   02 followed by an address 0x80..0xFF starts a candidate, judged by
 *   framer_model_judge(). A telegram moves past its bytes; every rejected
 *   candidate (length error, CRC error, truncated at the end) drops only
 *   its STX (skipped) and hunting resumes at the next byte.
 * resyncs counts telegrams accepted while skipped bytes were pending since
 * the previous telegram (an ACK or NAK does not end the skip run).
 */
#ifndef LMSGEN_FRAMER_MODEL_H
#define LMSGEN_FRAMER_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint32_t bytes_in;
    uint32_t telegrams;
    uint32_t telegram_bytes;
    uint32_t acks;
    uint32_t naks;
    uint32_t crc_errors;
    uint32_t length_errors;
    uint32_t truncated;
    uint32_t bytes_skipped;
    uint32_t resyncs;
    /* The stream ends in a lone 02: the contract does not say whether
     * flush counts that as a truncated candidate, so the generator avoids
     * it. */
    bool ends_with_lone_stx;
} framer_model_counts_t;

typedef enum {
    FRAMER_MODEL_TELEGRAM = 0,
    FRAMER_MODEL_LENGTH_ERROR = 1,
    FRAMER_MODEL_CRC_ERROR = 2,
    FRAMER_MODEL_TRUNCATED = 3
} framer_model_verdict_t;

/* Fate of the candidate at c[0] (STX) with c[1] a reply address, given
 * the avail bytes that follow it in the stream (avail >= 2). *size gets
 * the telegram size for FRAMER_MODEL_TELEGRAM. Length rules, as
 * lms_framer.h states them for scanner replies:
 *   2 <= L <= LMS_LENGTH_MAX (as soon as L is complete);
 *   the exact L of each fixed-size reply code (as soon as the code is in):
 *     90 23, 91 2, 92 2, A0 3, B1 154, BA 23, BB 7, F4 34|36, F7 35|37;
 *   B0: L = 2N + 4 or 2N + 6 with N = count word bits 0-9 <= 401 (as soon
 *     as the count word is in);
 *   then the CRC over L + 4 bytes once all L + 6 are there. */
framer_model_verdict_t framer_model_judge(const uint8_t *c, size_t avail, size_t *size);

/* Called for each candidate in stream order: accepted telegrams (size =
 * their size) and rejected candidates (size 0), with the offset of their
 * STX in the stream. */
typedef void (*framer_model_event_fn)(void *ctx, framer_model_verdict_t verdict, size_t offset,
                                      size_t size);

/* Runs the model over the whole stream. on_event may be NULL. */
void framer_model_run(const uint8_t *bytes, size_t len, framer_model_counts_t *counts,
                      framer_model_event_fn on_event, void *ctx);

/* CRC SICK (docs: lms2xx-protocol.md section 1.3), written again here. */
uint16_t framer_model_crc(const uint8_t *bytes, size_t len);

#endif /* LMSGEN_FRAMER_MODEL_H */
