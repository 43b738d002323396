/* ego_live.c - see ego_live.h. */
#include "ego_live.h"

#include <string.h>

/* Built with EGO_LIVE_DEFERRED_ONLY, the core has only the deferred mode:
 * the estimator is not even linked into the line's path, so the call
 * graph (and its worst-case stack, which the interrupt adds on top of the
 * main loop's) shows that the interrupt never runs it. */
#if defined(EGO_LIVE_DEFERRED_ONLY)
#define INLINE_ESTIMATOR false
#else
#define INLINE_ESTIMATOR true
#endif

void ego_live_defaults(ego_live_config_t *config)
{
    memset(config, 0, sizeof *config);
    lms_session_defaults(&config->session);
    ego_loop_defaults(&config->loop);
    /* Live, a line is due before the next scan: the sensor-rate budget. */
    ego_budget_defaults(&config->loop.ego);
}

/* --- Scan times: ego_timing_* (ego_loop.h) on the loop's tracker ------- */

static uint32_t framer_damage(const lms_session_t *s)
{
    const lms_framer_stats_t *f = lms_session_framer_stats(s);
    return f->crc_errors + f->length_errors + f->truncated;
}

static lms_baud_t line_baud(const ego_live_t *live)
{
    return lms_session_info(&live->session)->baud;
}

/* --- The session's and the loop's HAL --------------------------------- */

static void session_write(void *ctx, const uint8_t *bytes, size_t len)
{
    ego_live_t *live = ctx;
    live->hal.scanner_write(live->hal.ctx, bytes, len);
}

/* chunk_used and chunk_len index the chunk. */
_Static_assert(EGO_LIVE_CHUNK <= 255u, "ego_live_t's chunk_used and chunk_len are 8-bit");

/* The session's "set the rate and drop what was buffered": the ring is
 * emptied before the UART changes, so that a byte caught between the two
 * is old-rate noise the framer skips rather than a good new-rate byte
 * lost. (The rest of the chunk being fed when the rate changes goes on to
 * the session, which has seen the answer it waited for and skips what
 * follows as noise, as `lmsego run` does with the rest of its read.) */
static void session_set_baud(void *ctx, lms_baud_t baud)
{
    ego_live_t *live = ctx;
    live->stats.bytes_discarded += (uint32_t)uart_ring_discard(live->rx);
    live->hal.scanner_set_baud(live->hal.ctx, baud);
}

lms_status_t ego_live_init(ego_live_t *live, const ego_live_config_t *config,
                           const ego_live_hal_t *hal, uart_ring_t *rx)
{
    if (live == NULL) {
        return LMS_ERR_ARG;
    }
    memset(live, 0, sizeof *live);
    live->status = EGO_LIVE_FAILED;
    if (config == NULL || hal == NULL || rx == NULL || hal->scanner_write == NULL ||
        hal->scanner_set_baud == NULL || hal->now_us == NULL || hal->out_write == NULL) {
        return LMS_ERR_ARG;
    }
    live->hal = *hal;
    live->rx = rx;
    live->max_scans = config->max_scans;
    live->one_scan_per_service = config->one_scan_per_service;
    live->deferred = config->deferred || !INLINE_ESTIMATOR;
    live->write_slot = 0u;
    atomic_init(&live->middle, 1u);
    live->read_slot = 2u;
    live->loop_hal.read = NULL; /* ego_loop_telegram only writes */
    live->loop_hal.write = hal->out_write;
    live->loop_hal.now_us = hal->now_us;
    live->loop_hal.ctx = hal->ctx;
    ego_loop_config_t loop_config = config->loop;
    loop_config.use_clock = true; /* with the track times of ego_timing_scan */
    ego_loop_init(&live->loop, &loop_config);
    live->stats.bytes_discarded = (uint32_t)uart_ring_discard(rx); /* from before the session */
    const lms_session_io_t io = {session_write, session_set_baud, live};
    if (lms_session_init(&live->session, &config->session, &io, hal->now_us(hal->ctx)) != LMS_OK) {
        return LMS_ERR_ARG;
    }
    live->status = EGO_LIVE_RUNNING;
    return LMS_OK;
}

/* The mailbox's index byte: the middle slot, and whether it is fresh. */
#define EGO_LIVE_FRESH 0x4u
#define EGO_LIVE_SLOT_MASK 0x3u

/* Deferred mode, producer: the scan into the slot it owns, then that slot
 * made the middle one by one atomic exchange; the slot it gets back is
 * its own from now on (a fresh one there was never taken: skipped). Runs
 * where the consumer cannot (an interrupt), so reading the middle slot's
 * gap flag first is safe. */
static void publish(ego_live_t *live, const uint8_t *t, size_t len, uint32_t t_us)
{
    ego_live_slot_t *slot = &live->slot[live->write_slot];
    const size_t n = len < sizeof slot->bytes ? len : sizeof slot->bytes;
    memcpy(slot->bytes, t, n);
    slot->len = (uint16_t)n;
    slot->time_us = t_us;
    slot->meas_mode = lms_session_info(&live->session)->meas_mode;
    slot->gap = live->gap_pending;
    live->gap_pending = false;
    const unsigned waiting = (unsigned)atomic_load(&live->middle);
    if ((waiting & EGO_LIVE_FRESH) != 0u) {
        /* The scan it replaces had a restart before it: so has this one. */
        slot->gap = slot->gap || live->slot[waiting & EGO_LIVE_SLOT_MASK].gap;
    }
    const unsigned before =
        (unsigned)atomic_exchange(&live->middle, (uint_fast8_t)(live->write_slot | EGO_LIVE_FRESH));
    live->write_slot = (uint8_t)(before & EGO_LIVE_SLOT_MASK);
    if ((before & EGO_LIVE_FRESH) != 0u) {
        live->stats.scans_skipped++;
    }
}

/* One event of the session, at time now_us. */
static void on_event(ego_live_t *live, lms_session_event_t ev, uint32_t now_us)
{
    switch (ev) {
    case LMS_SESSION_EV_SCAN: {
        size_t len = 0u;
        const uint8_t *t = lms_session_telegram(&live->session, &len);
        const uint32_t t_us = ego_timing_scan(&live->loop.timing, t, len, now_us, line_baud(live),
                                              framer_damage(&live->session));
        if (live->max_scans != 0u && live->stats.scans >= live->max_scans) {
            live->stats.scans_ignored++;
            break;
        }
        live->stats.scans++;
        if (live->deferred || !INLINE_ESTIMATOR) {
            publish(live, t, len, t_us);
        } else {
            /* The values are decoded with the mode the scanner measures in. */
            ego_loop_set_meas_mode(&live->loop, lms_session_info(&live->session)->meas_mode);
            ego_loop_telegram(&live->loop, &live->loop_hal, t, len, t_us);
        }
        if (live->max_scans != 0u && live->stats.scans == live->max_scans) {
            lms_session_stop(&live->session, now_us); /* no B0 is reported after this */
        }
        break;
    }
    case LMS_SESSION_EV_RESTART:
        if (live->deferred || !INLINE_ESTIMATOR) {
            live->gap_pending = true; /* travels with the next scan */
        } else {
            ego_loop_gap(&live->loop);
        }
        ego_timing_reset(&live->loop.timing); /* the next scan seeds the times */
        live->stats.gaps++;
        break;
    case LMS_SESSION_EV_STREAMING:
        /* The A0 that started the stream ended here: the first scan's bytes
         * come next (ego_loop_step does the same at every A0). */
        ego_timing_boundary(&live->loop.timing);
        break;
    case LMS_SESSION_EV_STOPPED:
        live->status = EGO_LIVE_STOPPED;
        break;
    case LMS_SESSION_EV_FAILED:
        live->status = EGO_LIVE_FAILED;
        break;
    default: /* NONE: nothing to do */
        break;
    }
}

/* Feeds chunk[chunk_used .. chunk_len), which arrived by chunk_arrival_us,
 * handling every event; with one_scan_per_service it stops after a scan,
 * the rest kept for the next service. Returns whether a scan came. */
static bool feed_chunk(ego_live_t *live)
{
    const uint32_t arrival_us = live->chunk_arrival_us;
    const uint32_t scans_before = live->stats.scans;
    /* Bounded: each feed uses bytes or reports an event, and the session
     * reports at most LMS_FRAMER_BUF_SIZE events from its framer's buffer
     * plus its four pending reports without new bytes. */
    for (size_t guard = 0u; guard <= EGO_LIVE_CHUNK + LMS_FRAMER_BUF_SIZE + 4u; guard++) {
        size_t used = 0u;
        const lms_session_event_t ev =
            lms_session_feed(&live->session, &live->chunk[live->chunk_used],
                             (size_t)live->chunk_len - live->chunk_used, &used, arrival_us);
        live->chunk_used = (uint8_t)(live->chunk_used + used);
        /* Before the event: a scan's bytes count towards its own time. */
        ego_timing_bytes(&live->loop.timing, used, arrival_us, line_baud(live));
        if (ev == LMS_SESSION_EV_NONE) {
            break;
        }
        on_event(live, ev, arrival_us);
        if (live->status != EGO_LIVE_RUNNING ||
            (live->one_scan_per_service && live->stats.scans != scans_before)) {
            break;
        }
    }
    return live->stats.scans != scans_before;
}

/* The session's timers at now_us, every event handled. */
static void run_timers(ego_live_t *live, uint32_t now_us)
{
    for (uint32_t guard = 0u; guard < 16u && live->status == EGO_LIVE_RUNNING; guard++) {
        const lms_session_event_t ev = lms_session_poll(&live->session, now_us);
        if (ev == LMS_SESSION_EV_NONE) {
            break;
        }
        on_event(live, ev, now_us);
    }
}

/* Everything but the estimator (deferred mode) or everything (not). */
static void service(ego_live_t *live)
{
    if (live->status != EGO_LIVE_RUNNING) {
        return;
    }
    live->stats.steps++;
    if (live->stop_requested) {
        live->stop_requested = false;
        lms_session_stop(&live->session, live->hal.now_us(live->hal.ctx));
    }
    /* What an earlier service left of its chunk first, then only what is
     * waiting now: a babbling line cannot starve the timers. */
    bool fed = live->chunk_used < live->chunk_len;
    if (fed && feed_chunk(live) && live->one_scan_per_service) {
        return;
    }
    size_t budget = uart_ring_count(live->rx);
    while (budget > 0u && live->status == EGO_LIVE_RUNNING) {
        const size_t want = budget < sizeof live->chunk ? budget : sizeof live->chunk;
        const size_t n = uart_ring_read(live->rx, live->chunk, want, &live->chunk_arrival_us);
        if (n == 0u) {
            break; /* discarded at a rate change */
        }
        budget -= n;
        fed = true;
        live->stats.bytes += (uint32_t)n;
        live->chunk_used = 0u;
        live->chunk_len = (uint8_t)n;
        if (feed_chunk(live) && live->one_scan_per_service) {
            return; /* the timers when a service drains the ring */
        }
    }
    /* The timers, after the bytes: a reply that came before its deadline
     * is never taken for a timeout because the loop was late. And when
     * bytes were fed, at the arrival of the last of them: the line is
     * known up to there, and no further (an inline estimator may have
     * spent a while on the scans, and what came meanwhile waits in the
     * ring or the UART for the next step). Silence is judged by a step
     * that found nothing waiting, at most one step later. */
    run_timers(live, fed ? live->chunk_arrival_us : live->hal.now_us(live->hal.ctx));
}

void ego_live_service(ego_live_t *live)
{
    service(live);
}

const ego_live_slot_t *ego_live_take(ego_live_t *live)
{
    if (!live->deferred ||
        ((unsigned)atomic_load(&live->middle) & EGO_LIVE_FRESH) == 0u) {
        return NULL;
    }
    /* The fresh middle slot becomes ours; ours becomes the middle (not
     * fresh), for the producer to fill next. */
    const unsigned got = (unsigned)atomic_exchange(&live->middle, (uint_fast8_t)live->read_slot);
    live->read_slot = (uint8_t)(got & EGO_LIVE_SLOT_MASK);
    return &live->slot[live->read_slot];
}

void ego_live_estimate_slot(ego_live_t *live, const ego_live_slot_t *slot)
{
    if (slot->gap) {
        ego_loop_gap(&live->loop);
    }
    ego_loop_set_meas_mode(&live->loop, slot->meas_mode);
    ego_loop_telegram(&live->loop, &live->loop_hal, slot->bytes, slot->len, slot->time_us);
    live->stats.scans_estimated++;
}

bool ego_live_estimate(ego_live_t *live)
{
    const ego_live_slot_t *slot = ego_live_take(live);
    if (slot == NULL) {
        return false;
    }
    ego_live_estimate_slot(live, slot);
    return true;
}

ego_live_status_t ego_live_step(ego_live_t *live)
{
    service(live);
    if (live->deferred) {
        (void)ego_live_estimate(live);
    }
    return live->status;
}

uint32_t ego_live_wait_us(const ego_live_t *live)
{
    if (live->status != EGO_LIVE_RUNNING || uart_ring_count(live->rx) > 0u ||
        live->chunk_used < live->chunk_len || live->stop_requested ||
        ((unsigned)atomic_load(&live->middle) & EGO_LIVE_FRESH) != 0u) {
        return 0u;
    }
    return lms_session_wait_us(&live->session, live->hal.now_us(live->hal.ctx));
}

void ego_live_link_lost(ego_live_t *live)
{
    if (live->status != EGO_LIVE_RUNNING) {
        return;
    }
    live->stats.bytes_discarded += (uint32_t)uart_ring_discard(live->rx);
    live->chunk_len = live->chunk_used; /* what a service left: from before too */
    lms_session_link_lost(&live->session, live->hal.now_us(live->hal.ctx));
}

void ego_live_stop(ego_live_t *live)
{
    if (live->status != EGO_LIVE_RUNNING) {
        return;
    }
    if (live->deferred) {
        live->stop_requested = true; /* the session belongs to ego_live_service */
    } else {
        lms_session_stop(&live->session, live->hal.now_us(live->hal.ctx));
    }
}

ego_live_status_t ego_live_status(const ego_live_t *live)
{
    return live->status;
}

const ego_live_stats_t *ego_live_stats(const ego_live_t *live)
{
    return &live->stats;
}

const lms_session_t *ego_live_session(const ego_live_t *live)
{
    return &live->session;
}

const ego_loop_t *ego_live_loop(const ego_live_t *live)
{
    return &live->loop;
}
