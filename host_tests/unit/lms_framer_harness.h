/* lms_framer_harness.h - drives an lms_framer_t the way its header says a
 * caller must (feed until NEED_MORE, flush at end of input), in a chosen
 * chunking, and checks the framer's contract after every single call:
 *
 * - consumed <= len, and NEED_MORE only when every byte was used;
 * - bytes_in grew by consumed; the stats invariant
 *   bytes_in == telegram_bytes + acks + naks + bytes_skipped + pending;
 * - each event moves exactly its own counter by one (NEED_MORE none), no
 *   counter ever decreases, resyncs moves only with a telegram;
 * - lms_framer_telegram is non-NULL exactly after TELEGRAM, and the bytes
 *   start with STX, carry an address of the framer's direction, agree with
 *   their length field and have a good CRC; telegram_bytes grew by the size;
 * - ACK/NAK only in the scanner direction.
 *
 * Events other than NEED_MORE are recorded in an optional log (with copies
 * of the telegram bytes) and passed to an optional sink.
 */
#ifndef LMS_FRAMER_HARNESS_H
#define LMS_FRAMER_HARNESS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lms_framer.h"

#define FH_MAX_EVENTS 8192u
#define FH_POOL_SIZE (256u * 1024u)

typedef struct {
    lms_framer_event_t event;
    uint32_t pool_offset; /* telegram bytes in the pool (TELEGRAM only) */
    uint16_t len;
} fh_event_t;

typedef struct {
    fh_event_t events[FH_MAX_EVENTS];
    size_t n_events;
    uint8_t pool[FH_POOL_SIZE];
    size_t pool_len;
    uint32_t count[7]; /* events seen, by lms_framer_event_t */
} fh_log_t;

typedef void (*fh_sink_t)(void *ctx, lms_framer_event_t event, const uint8_t *telegram,
                          size_t len);

typedef enum {
    FH_CHUNK_WHOLE = 0,  /* one feed call (plus the repeat calls) */
    FH_CHUNK_BYTES = 1,  /* one byte per call */
    FH_CHUNK_RANDOM = 2, /* seeded sizes 0..64, sometimes large */
    FH_CHUNK_SMALL = 3   /* seeded sizes 1..5 */
} fh_chunking_t;

typedef struct {
    lms_framer_t framer;
    lms_direction_t direction;
    fh_log_t *log;     /* may be NULL */
    fh_sink_t sink;    /* may be NULL */
    void *sink_ctx;
    const char *label; /* assertion message */
    uint32_t rng;
    lms_framer_stats_t last; /* stats after the previous call */
} fh_t;

void fh_log_clear(fh_log_t *log);

/* Initialises the framer and the harness; seed drives FH_CHUNK_RANDOM/SMALL. */
void fh_init(fh_t *h, lms_direction_t direction, fh_log_t *log, const char *label,
             uint32_t seed);

/* Feeds len bytes in the given chunking, each chunk until NEED_MORE. */
void fh_feed(fh_t *h, const uint8_t *bytes, size_t len, fh_chunking_t chunking);

/* Calls lms_framer_flush until NEED_MORE; then checks pending is 0. */
void fh_flush(fh_t *h);

/* fh_feed followed by fh_flush. */
void fh_run(fh_t *h, const uint8_t *bytes, size_t len, fh_chunking_t chunking);

/* Number of TELEGRAM events in the log equal, byte for byte, to t. */
size_t fh_log_find(const fh_log_t *log, const uint8_t *t, size_t len);

/* Asserts two logs hold the same events and the same telegram bytes. */
void fh_log_assert_equal(const fh_log_t *expected, const fh_log_t *actual, const char *label);

#endif /* LMS_FRAMER_HARNESS_H */
