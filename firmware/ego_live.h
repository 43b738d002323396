/* ego_live.h - the firmware core with a live scanner: the receive ring
 * drained into the session (driver/lms_session.h), which brings the
 * scanner up and keeps it streaming, and every scan handed to the loop
 * (ego_loop.h), which writes its CSV line or binary frame. Portable C11:
 * no OS headers, no heap, no stdio.
 *
 *   UART RX interrupt / DMA --uart_ring_put/write--> uart_ring_t
 *   main loop: ego_live_step --> lms_session_feed / _poll
 *                                  EV_SCAN    -> ego_loop_telegram -> hal.out_write
 *                                  EV_RESTART -> ego_loop_gap
 *                               <-- hal.scanner_write, hal.scanner_set_baud
 *
 * Scan times (ego_loop.h, "Scan times from arrival stamps"): the scan's
 * time as the estimator defines it (the mean of its beams' times), on
 * hal.now_us's clock, from the arrival stamps of its telegram's bytes less
 * the telegram's wire time and the lag of its beams, tracked by counting
 * scan intervals so that dt is the mirror's, not the stamps' jitter. The
 * stamps are the receive ring's (uart_ring.h: taken by the interrupt when
 * the bytes came, late by at most the rest of their ring block), not the
 * time the loop read them: a loop held up by a hard scan still times the
 * scans by when they came. Every time given to the session with bytes
 * (byte gaps, the silence timer, replies) is that stamp too, and the
 * timers run after the waiting bytes are fed, so a reply or a scan that
 * did come is never taken for a timeout or for silence because the loop
 * was late. After a restart the next scan seeds the times afresh. The
 * receive side (ego_live_service) runs the tracker on live->loop.timing;
 * the estimator's side never touches it. `lmsego run` (cmd_run.c) runs
 * this core, and `lmsego replay` of its recording (run --record) runs the
 * same tracker over the recorded arrival times (ego_loop_step with
 * use_clock): a run without a restart prints that replay's CSV, byte for
 * byte, but for its latency column.
 *
 * Static memory: ego_live_t holds the session, the loop (ego_loop_t, about
 * 25 KB with the estimator) and a chunk buffer (EGO_LIVE_CHUNK bytes); the
 * caller owns it (a static) and the ring. Main loop only; nothing here
 * runs in an interrupt except the ring's producer side.
 */
#ifndef EGO_LIVE_H
#define EGO_LIVE_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ego_loop.h"
#include "lms_session.h"
#include "uart_ring.h"

/* Bytes taken from the ring per session feed: a ring read returns at most
 * one stamp block, the unit of arrival time. */
#define EGO_LIVE_CHUNK UART_RING_STAMP_BYTES

/* The platform. */
typedef struct {
    /* Bytes to the scanner's UART (may block; at 500 kbaud the platform
     * paces host telegrams, >= 55 us between bytes). */
    void (*scanner_write)(void *ctx, const uint8_t *bytes, size_t len);
    /* Reprograms the scanner's UART to a rate (the core has discarded the
     * ring's bytes, received at the old rate, just before). */
    void (*scanner_set_baud)(void *ctx, lms_baud_t baud);
    /* The free-running microsecond clock the receive interrupt stamps
     * bytes with (wraps after 71.6 minutes: fine). */
    uint32_t (*now_us)(void *ctx);
    /* The output: CSV lines or binary frames (may block). */
    void (*out_write)(void *ctx, const uint8_t *bytes, size_t len);
    void *ctx;
} ego_live_hal_t;

typedef struct {
    lms_session_config_t session;
    ego_loop_config_t loop;   /* use_clock is forced on: scan times from the arrival
                                 stamps (latency: the CSV's latency_ms column);
                                 lms.meas_mode is the session's: the mode the scanner
                                 was found in or set to */
    uint32_t max_scans;       /* stop cleanly after this many scans; 0: never */
    bool deferred;            /* false: ego_live_step estimates every scan as it comes;
                                 true: the newest scan waits for ego_live_estimate
                                 (see "Deferred mode" below) */
    /* Deferred mode: ego_live_service returns as soon as it put a scan in
     * the mailbox (the rest waits in the ring; the timers run when a
     * service drains it), so a consumer that keeps its own queue takes
     * every scan (ego_live_take) before a newer one could replace it:
     * `lmsego run`. A service puts at most one: a chunk that completes
     * two (the framer finds a whole telegram again in the bytes it held
     * for a damaged one) keeps the rest for the next. Default off. */
    bool one_scan_per_service;
} ego_live_config_t;

/* Session defaults (500 kbaud, scanner's variant and units kept), loop
 * defaults (CSV), no scan limit, the estimator within its sensor-rate
 * budget (ego_budget_defaults): a line is due before the next scan. */
void ego_live_defaults(ego_live_config_t *config);

typedef enum {
    EGO_LIVE_RUNNING = 0,
    EGO_LIVE_STOPPED = 1, /* stopped cleanly (ego_live_stop or max_scans) */
    EGO_LIVE_FAILED = 2   /* the scanner refused a setting: lms_session_error() */
} ego_live_status_t;

typedef struct {
    uint32_t steps;
    uint32_t bytes;           /* fed to the session */
    uint32_t bytes_discarded; /* dropped from the ring: at init, at a rate change */
    uint32_t scans;           /* handed to the loop (deferred: to the mailbox) */
    uint32_t scans_ignored;   /* reported after max_scans */
    uint32_t gaps;            /* restarts passed to the loop */
    uint32_t scans_skipped;   /* deferred: replaced in the mailbox by a newer scan */
    uint32_t scans_estimated; /* deferred: taken by ego_live_estimate */
} ego_live_stats_t;

/* Deferred mode: one scan waiting for the estimator, with its time and
 * whether a restart came before it. Three of them make a lock-free
 * "newest value" mailbox between ego_live_service (producer: an interrupt)
 * and ego_live_estimate (consumer: the main loop). */
typedef struct {
    uint8_t bytes[LMS_TELEGRAM_MAX];
    uint16_t len;
    bool gap;
    uint8_t meas_mode;        /* the scanner's measuring mode (lms_session_info) */
    uint32_t time_us;         /* its track time (ego_timing_scan) */
} ego_live_slot_t;

#define EGO_LIVE_SLOTS 3u

typedef struct {
    /* Private. */
    ego_live_hal_t hal;
    ego_hal_t loop_hal;       /* the loop's view: out_write and now_us */
    uart_ring_t *rx;
    uint32_t max_scans;
    ego_live_status_t status;
    ego_live_stats_t stats;
    lms_session_t session;
    ego_loop_t loop;
    uint8_t chunk[EGO_LIVE_CHUNK];
    /* Deferred mode: the producer owns slot[write_slot], the consumer
     * slot[read_slot], and `middle` (the third slot's index, plus
     * EGO_LIVE_FRESH when it holds a scan not yet taken) changes hands by
     * atomic exchange only, so the two never touch the same slot. */
    bool deferred;
    bool one_scan_per_service;
    /* chunk[chunk_used .. chunk_len) arrived by chunk_arrival_us and waits
     * for the next service: one_scan_per_service stopped at a scan there. */
    uint8_t chunk_used;
    uint8_t chunk_len;
    ego_live_slot_t slot[EGO_LIVE_SLOTS];
    atomic_uint_fast8_t middle;
    uint8_t write_slot;
    uint8_t read_slot;
    bool gap_pending;         /* producer: a restart since the last scan published */
    volatile bool stop_requested;
    uint32_t chunk_arrival_us;
} ego_live_t;

/* Starts the session now (hal.now_us) and the loop. rx is the ring the
 * receive interrupt fills (uart_ring_init'ed by the caller); what it holds
 * now is discarded. Returns LMS_ERR_ARG for a NULL argument, a missing HAL
 * function or a session configuration lms_session_check_config refuses
 * (the core is then FAILED). live and rx must stay where they are (the
 * session keeps a pointer to live). */
lms_status_t ego_live_init(ego_live_t *live, const ego_live_config_t *config,
                           const ego_live_hal_t *hal, uart_ring_t *rx);

/* One round of the main loop: feeds the session the bytes the ring holds
 * now (in chunks of at most EGO_LIVE_CHUNK, each with its arrival stamp; bytes that
 * arrive meanwhile wait for the next step), runs each scan through the
 * loop as it comes (the estimator runs here), then runs the session's
 * timers at hal.now_us. Returns the status; once STOPPED or FAILED it
 * does nothing more. */
ego_live_status_t ego_live_step(ego_live_t *live);

/* Deferred mode (config.deferred): the estimator, which can take far
 * longer than a scan interval on a microcontroller, runs apart from the
 * line. ego_live_service does everything but the estimator: it feeds the
 * session the ring's bytes and runs its timers, and puts each scan (with
 * its time) in the mailbox, replacing a scan still waiting there (counted
 * in scans_skipped: the estimator always gets the newest scan, and the
 * motion it reports spans the scans it skipped, their time included). Call
 * it from a periodic timer interrupt (every few milliseconds: the ring
 * must not fill between two calls, 40 ms at 500 kbaud) or from the UART
 * interrupt; it never waits. ego_live_estimate, from the main loop, takes
 * the newest scan, if any, through the estimator and writes its line
 * (hal.out_write); it returns false when there was none. ego_live_stop
 * only raises a flag that the next ego_live_service acts on. On a single
 * core the mailbox needs nothing more than the atomic exchange (LDREX /
 * STREX on Cortex-M3 and up); ego_live_step does both in turn. A build
 * with EGO_LIVE_DEFERRED_ONLY defined has this mode only (config.deferred
 * is then always on), so the estimator is not on the interrupt's call
 * path at all: what a firmware serving the line from an interrupt uses. */
void ego_live_service(ego_live_t *live);
bool ego_live_estimate(ego_live_t *live);

/* ego_live_estimate in its two halves, for a consumer that keeps its own
 * queue (`lmsego run`: every scan estimated in order however long the
 * estimator takes, the line served between any two): ego_live_take hands
 * over the newest waiting scan (NULL: none), valid until the next take;
 * ego_live_estimate_slot runs one through the loop. Main loop only. */
const ego_live_slot_t *ego_live_take(ego_live_t *live);
void ego_live_estimate_slot(ego_live_t *live, const ego_live_slot_t *slot);

/* How long the caller may sleep (WFI) before the next step if no byte
 * comes: 0 when bytes wait or something is due. */
uint32_t ego_live_wait_us(const ego_live_t *live);

/* The platform lost the line (a hang-up, a UART that had to be reset): the
 * session restarts now, and the waiting bytes, from the old line, are
 * dropped. Main loop only, like ego_live_step (in deferred mode: where
 * ego_live_service runs, with that interrupt masked). */
void ego_live_link_lost(ego_live_t *live);

/* Asks for a clean stop (stream off, scanner back at 9600 baud with the
 * session's restore_9600); the status becomes STOPPED when it is done. */
void ego_live_stop(ego_live_t *live);

ego_live_status_t ego_live_status(const ego_live_t *live);
const ego_live_stats_t *ego_live_stats(const ego_live_t *live);
const lms_session_t *ego_live_session(const ego_live_t *live);
const ego_loop_t *ego_live_loop(const ego_live_t *live);

#endif /* EGO_LIVE_H */
