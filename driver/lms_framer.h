/* lms_framer.h - byte stream -> CRC-checked LMS 2xx telegrams.
 *
 * Feed it the raw bytes of one direction of a serial line, in any chunk
 * sizes. It hunts for STX followed by a plausible address byte, rejects an
 * impossible length field as soon as it arrives (before waiting for the
 * bytes), checks the CRC when the telegram is complete and reports it.
 * When a candidate is rejected (impossible length, CRC mismatch, or
 * abandoned by lms_framer_flush) only its STX is dropped: every byte after
 * it is searched again for a start, so a good telegram hidden inside a bad
 * candidate is never lost. Telegrams are reported only after their CRC
 * matched.
 *
 * Direction LMS_FROM_SCANNER: addresses 0x80..0xFF; a 06 or 15 met while
 * hunting for a start is reported as ACK or NAK, also when it comes from
 * the searched-again bytes of a rejected candidate. LMS_FROM_HOST:
 * addresses 0x00..0x7F; 06 and 15 are ordinary (skipped) bytes.
 *
 * Length rules applied before the data arrive (L = the length field):
 * 1 <= L <= LMS_LENGTH_MAX for host telegrams (exact sizes for the commands
 * that have one: 10, 31, 32, 3A, 74 -> 1; 3B -> 5; 77 -> 33 or 35; 20 and 30
 * at least 2, as their parameters vary with the mode), and for scanner replies L >= 2 and the exact size of
 * each known code (90, 91, 92, A0, B1, BA, BB, F4, F7), and for B0
 * L = 2N + 4 or 2N + 6 with N (count word) <= LMS_SCAN_MAX_VALUES.
 *
 * Cost: each byte is copied once and summed once into a CRC on a clean
 * stream. On hostile input a rejected candidate costs at most one CRC pass
 * and one buffer move over LMS_TELEGRAM_MAX bytes, so the worst case per
 * input byte is bounded by O(LMS_TELEGRAM_MAX). Not reentrant; one
 * instance per direction of a line; call from the main loop, not an ISR.
 */
#ifndef LMS_FRAMER_H
#define LMS_FRAMER_H

#include <stddef.h>
#include <stdint.h>

#include "lms_proto.h"

typedef enum {
    LMS_FROM_SCANNER = 0, /* replies and the B0 stream */
    LMS_FROM_HOST = 1     /* commands (what a simulated scanner reads) */
} lms_direction_t;

typedef enum {
    LMS_FRAMER_NEED_MORE = 0,     /* all bytes given are used; nothing left to report */
    LMS_FRAMER_TELEGRAM = 1,      /* a CRC-valid telegram: see lms_framer_telegram() */
    LMS_FRAMER_ACK = 2,           /* a lone 06 (scanner direction only) */
    LMS_FRAMER_NAK = 3,           /* a lone 15 (scanner direction only) */
    LMS_FRAMER_CRC_ERROR = 4,     /* a complete candidate failed its CRC */
    LMS_FRAMER_LENGTH_ERROR = 5,  /* a candidate's length field was impossible */
    LMS_FRAMER_TRUNCATED = 6      /* lms_framer_flush abandoned an incomplete candidate */
} lms_framer_event_t;

/* Counters; they wrap modulo 2^32. At every return of feed/flush:
 * bytes_in == telegram_bytes + acks + naks + bytes_skipped + pending. */
typedef struct {
    uint32_t bytes_in;       /* bytes given to lms_framer_feed */
    uint32_t telegrams;      /* CRC-valid telegrams reported */
    uint32_t telegram_bytes; /* bytes of those telegrams, STX .. CRC */
    uint32_t acks;           /* lone 06 reported */
    uint32_t naks;           /* lone 15 reported */
    uint32_t crc_errors;     /* complete candidates with a wrong CRC */
    uint32_t length_errors;  /* candidates rejected for their length field */
    uint32_t truncated;      /* incomplete candidates abandoned by flush */
    uint32_t bytes_skipped;  /* bytes that ended up in no telegram and no ACK/NAK */
    uint32_t resyncs;        /* telegrams accepted after skipped bytes: sync regained */
} lms_framer_stats_t;

#define LMS_FRAMER_BUF_SIZE LMS_TELEGRAM_MAX

typedef struct {
    /* Private: use the functions below. */
    uint8_t buf[LMS_FRAMER_BUF_SIZE];
    uint16_t head;     /* first byte of the candidate (or of unexamined bytes) */
    uint16_t tail;     /* one past the last buffered byte */
    uint16_t examined; /* bytes from head already examined as the candidate */
    uint16_t expect;   /* total size of the candidate once L is known, else 0 */
    uint16_t release;  /* size of the telegram last reported, dropped on the next call */
    uint8_t direction; /* lms_direction_t */
    uint8_t skipped_since_sync; /* nonzero: bytes were skipped since the last telegram */
    lms_framer_stats_t stats;
} lms_framer_t;

/* Resets the instance: empty buffer, zero counters. */
void lms_framer_init(lms_framer_t *f, lms_direction_t direction);

/* Consumes up to len bytes and stops at the first event. *consumed gets
 * the number of bytes used (may be less than len, or 0 when the event came
 * from bytes buffered earlier). Call again with the rest until it returns
 * LMS_FRAMER_NEED_MORE, which means every byte was used. bytes NULL is
 * taken as len 0. */
lms_framer_event_t lms_framer_feed(lms_framer_t *f, const uint8_t *bytes, size_t len,
                                   size_t *consumed);

/* The line went idle or the input ended: no more bytes of the current
 * candidate will come. Abandons it (LMS_FRAMER_TRUNCATED; a lone trailing
 * 02 counts as a truncated candidate too) and searches its bytes again;
 * call until it returns LMS_FRAMER_NEED_MORE, after which nothing is
 * buffered. The session calls it after an inter-byte silence
 * longer than the scanner's 14 ms limit. */
lms_framer_event_t lms_framer_flush(lms_framer_t *f);

/* The telegram of the last LMS_FRAMER_TELEGRAM event, STX .. CRC, and its
 * size in *len. Valid until the next feed, flush or init; NULL (and *len
 * 0) when the last event was not a telegram. */
const uint8_t *lms_framer_telegram(const lms_framer_t *f, size_t *len);

/* Bytes held for an incomplete candidate. */
size_t lms_framer_pending(const lms_framer_t *f);

const lms_framer_stats_t *lms_framer_stats(const lms_framer_t *f);

#endif /* LMS_FRAMER_H */
