/* ego_loop.c - see ego_loop.h. */
#include "ego_loop.h"

#include <string.h>

#include "ego_frame.h"

#define MICRO 1000000

void ego_loop_defaults(ego_loop_config_t *config)
{
    memset(config, 0, sizeof *config);
    ego_defaults(&config->ego);
    ego_lms_defaults(&config->lms);
}

void ego_loop_init(ego_loop_t *loop, const ego_loop_config_t *config)
{
    memset(loop, 0, sizeof *loop);
    loop->config = *config;
    lms_framer_init(&loop->framer, LMS_FROM_SCANNER);
    ego_reset(&loop->ego);
    ego_timing_reset(&loop->timing);
    loop->period_us = config->period_us;
#if EGO_LOOP_OBJECTS
    ego_moving_reset(&loop->moving);
#endif
}

/* --- Scan times from arrival stamps ------------------------------------- */

void ego_timing_reset(ego_timing_t *t)
{
    memset(t, 0, sizeof *t);
}

void ego_timing_boundary(ego_timing_t *t)
{
    t->since = 0u;
    t->has_bound = false;
}

/* An upper bound on the start of the telegram in progress, kept if least
 * (compared as a difference: the clock wraps). */
static void take_bound(ego_timing_t *t, uint32_t start_us)
{
    if (!t->has_bound || (int32_t)(start_us - t->bound_us) < 0) {
        t->bound_us = start_us;
        t->has_bound = true;
    }
}

void ego_timing_bytes(ego_timing_t *t, size_t n, uint32_t stamp_us, lms_baud_t baud)
{
    if (n == 0u) {
        return;
    }
    const uint32_t since = (uint32_t)t->since + (uint32_t)(n > UINT16_MAX ? UINT16_MAX : n);
    t->since = (uint16_t)(since > UINT16_MAX ? UINT16_MAX : since);
    take_bound(t, stamp_us - lms_wire_us(t->since, baud));
}

/* Values of a B0 telegram from its count word (low 10 bits), 0 when it is
 * too short to hold one. */
static uint16_t telegram_values(const uint8_t *telegram, size_t len)
{
    if (telegram == NULL || len < LMS_HEADER_SIZE + 3u) {
        return 0u;
    }
    return (uint16_t)((telegram[LMS_HEADER_SIZE + 1u] |
                       ((uint32_t)telegram[LMS_HEADER_SIZE + 2u] << 8)) & 0x3FFu);
}

uint32_t ego_timing_track(ego_timing_t *t, uint32_t estimate_us, uint32_t steps,
                          uint32_t interval_us, uint32_t band_us)
{
    if (!t->started) {
        t->started = true;
        t->time_us = estimate_us;
        t->window = 0u;
        t->floor_us = INT32_MAX;
        return t->time_us;
    }
    const uint32_t predicted = t->time_us + steps * interval_us;
    /* Estimates lie within a half interval of the count unless a restart
     * was missed: clamped, so the arithmetic below cannot overflow. */
    int32_t r = (int32_t)(estimate_us - predicted);
    const int32_t half = (int32_t)(interval_us / 2u);
    r = r < -half ? -half : (r > half ? half : r);
    const int32_t band = (int32_t)(band_us > (uint32_t)half ? (uint32_t)half : band_us);
    int32_t slew = (int32_t)(interval_us >> EGO_TIMING_SLEW_SHIFT);
    slew = slew < 1 ? 1 : slew;
    int32_t move = 0;
    if (r < -band) {
        /* Started sending before the track says: the track is late. */
        const int32_t want = r + band / 2;
        move = want < -slew ? -slew : want;
    } else {
        t->floor_us = r < t->floor_us ? r : t->floor_us;
        if (++t->window >= EGO_TIMING_WINDOW) {
            if (t->floor_us > band) {
                /* No estimate in the window came near: the track is early. */
                const int32_t want = t->floor_us - band / 2;
                move = want > slew ? slew : want;
            }
            t->window = 0u;
            t->floor_us = INT32_MAX;
        }
    }
    if (move != 0) {
        t->window = 0u; /* the window's estimates were against the old track */
        t->floor_us = INT32_MAX;
    }
    t->time_us = predicted + (uint32_t)move;
    return t->time_us;
}

uint32_t ego_timing_scan(ego_timing_t *t, const uint8_t *telegram, size_t len,
                         uint32_t stamp_us, lms_baud_t baud, uint32_t damaged)
{
    /* The pieces' bounds hold for this telegram only when nothing else came
     * since the last one; else the last piece's. */
    const uint32_t start_us = (t->has_bound && t->since <= len)
                                  ? t->bound_us
                                  : stamp_us - lms_wire_us((uint32_t)len, baud);
    const uint16_t lost16 = (uint16_t)((uint16_t)damaged - t->damaged);
    const uint32_t lost = lost16 > EGO_TIMING_MAX_LOST ? EGO_TIMING_MAX_LOST : lost16;
    t->damaged = (uint16_t)damaged;
    ego_timing_boundary(t);
    const uint32_t interval = lms_scan_interval_us(telegram_values(telegram, len), baud);
    return ego_timing_track(t, start_us - EGO_TIMING_SEND_DELAY_US, 1u + lost, interval,
                            lms_wire_us(EGO_TIMING_BAND_BYTES, baud));
}

const ego_loop_stats_t *ego_loop_stats(const ego_loop_t *loop)
{
    return &loop->stats;
}

size_t ego_format_fixed(char *out, int64_t value, unsigned decimals)
{
    char digits[24];
    size_t n = 0u;
    const bool negative = value < 0;
    uint64_t v = negative ? (uint64_t)0 - (uint64_t)value : (uint64_t)value;
    /* Digits, least significant first; at least decimals + 1 of them. */
    do {
        digits[n++] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while ((v != 0u || n <= decimals) && n < sizeof digits);
    size_t len = 0u;
    if (negative) {
        out[len++] = '-';
    }
    while (n > 0u) {
        if (n == decimals) {
            out[len++] = '.';
        }
        out[len++] = digits[--n];
    }
    out[len] = '\0';
    return len;
}

size_t ego_format_sci(char *out, int32_t q30)
{
    size_t len = 0u;
    if (q30 < 0) {
        out[len++] = '-';
    }
    if (q30 == INT32_MAX || q30 == INT32_MIN) {
        out[len++] = 'i';
        out[len++] = 'n';
        out[len++] = 'f';
        out[len] = '\0';
        return len;
    }
    if (q30 == 0) {
        out[len++] = '0';
        out[len] = '\0';
        return len;
    }
    const uint64_t one = (uint64_t)1 << 30;
    uint64_t m = (q30 < 0) ? (uint64_t)0 - (uint64_t)(int64_t)q30 : (uint64_t)q30;
    int32_t exponent = 0;
    while (m < one) { /* at most ten times: m >= 1 */
        m *= 10u;
        exponent--;
    }
    /* m / 2^30 in [1, 2]: four digits, the quotient rounded half to even. */
    const uint64_t num = m * 1000u;
    uint64_t digits = num >> 30;
    const uint64_t rest = num & (one - 1u);
    if (rest > one / 2u || (rest == one / 2u && (digits & 1u) != 0u)) {
        digits++;
    }
    if (digits >= 10000u) {
        digits /= 10u;
        exponent++;
    }
    out[len++] = (char)('0' + (int)(digits / 1000u));
    out[len++] = '.';
    out[len++] = (char)('0' + (int)(digits / 100u % 10u));
    out[len++] = (char)('0' + (int)(digits / 10u % 10u));
    out[len++] = (char)('0' + (int)(digits % 10u));
    out[len++] = 'e';
    out[len++] = (exponent < 0) ? '-' : '+';
    const uint32_t e = (uint32_t)((exponent < 0) ? -exponent : exponent);
    out[len++] = (char)('0' + (int)(e / 10u));
    out[len++] = (char)('0' + (int)(e % 10u));
    out[len] = '\0';
    return len;
}

/* Q16.16 -> micro-units, rounded. */
static int64_t micro_from_q16(int64_t v)
{
    return fx_shr_round_s64(v * MICRO, 16u);
}

/* Signed binary angle -> microradians: 2 pi 10^6 / 2^32 per unit. */
static int64_t microrad_from_bam(fx_bam32_t a)
{
    return fx_shr_round_s64((int64_t)fx_bam32_diff(a, 0u) * 6283185, 32u);
}

typedef struct {
    char *buf;
    size_t cap; /* > 0 */
    size_t len;
} line_t;

static void put_text(line_t *l, const char *s)
{
    while (*s != '\0' && l->len + 1u < l->cap) {
        l->buf[l->len++] = *s++;
    }
    l->buf[l->len] = '\0';
}

static void put_number(line_t *l, int64_t value, unsigned decimals, bool comma)
{
    char tmp[32];
    (void)ego_format_fixed(tmp, value, decimals);
    put_text(l, tmp);
    put_text(l, comma ? "," : "\n");
}

size_t ego_format_line(char *out, size_t cap, uint32_t scan, uint32_t time_us,
                       const ego_output_t *o)
{
    if (out == NULL || cap == 0u || o == NULL) {
        return 0u;
    }
    out[0] = '\0';
    line_t l = {out, cap, 0u};
    put_number(&l, scan, 0u, true);
    put_number(&l, time_us, 6u, true);
    put_number(&l, micro_from_q16(o->pose.x), 6u, true);
    put_number(&l, micro_from_q16(o->pose.y), 6u, true);
    put_number(&l, microrad_from_bam(o->pose.theta), 6u, true);
    put_number(&l, micro_from_q16(o->vx), 6u, true);
    put_number(&l, micro_from_q16(o->vy), 6u, true);
    put_number(&l, micro_from_q16(o->omega), 6u, true);
    put_number(&l, o->flags, 0u, true);
    put_number(&l, o->iterations, 0u, true);
    put_number(&l, o->matches, 0u, true);
    const int32_t cov[6] = {o->cov.xx, o->cov.xy, o->cov.xt, o->cov.yy, o->cov.yt, o->cov.tt};
    for (unsigned k = 0u; k < 6u; k++) {
        char tmp[16];
        (void)ego_format_sci(tmp, cov[k]);
        put_text(&l, tmp);
        put_text(&l, (k < 5u) ? "," : "\n");
    }
    return l.len;
}

static void write_text(const ego_hal_t *hal, const char *text, size_t len)
{
    hal->write(hal->ctx, (const uint8_t *)text, len);
}

/* The CSV line (with config.latency its latency column, measured now). */
static void write_line(ego_loop_t *loop, const ego_hal_t *hal, uint32_t k, uint32_t t_us,
                       const ego_output_t *out)
{
    if (!loop->header_written) {
        if (loop->config.latency) {
            write_text(hal, EGO_LOOP_CSV_HEADER_LATENCY, sizeof EGO_LOOP_CSV_HEADER_LATENCY - 1u);
        } else {
            write_text(hal, EGO_LOOP_CSV_HEADER, sizeof EGO_LOOP_CSV_HEADER - 1u);
        }
        loop->header_written = true;
    }
    size_t n = ego_format_line(loop->line, sizeof loop->line, k, t_us, out);
    if (!loop->config.latency || n == 0u) {
        write_text(hal, loop->line, n);
        return;
    }
    /* In two writes, so the line buffer need not grow: milliseconds with
     * three decimals, signed (a clock set back shows). */
    char tail[24];
    const int32_t latency_us = (int32_t)(hal->now_us(hal->ctx) - t_us);
    loop->line[n - 1u] = ',';
    write_text(hal, loop->line, n);
    n = ego_format_fixed(tail, latency_us, 3u);
    tail[n++] = '\n';
    write_text(hal, tail, n);
}

/* The scan's time: k * period, or (use_clock) its track time less the
 * lag from its mean beam to its last (ego_range.h), rounded to us. */
static uint32_t scan_time_us(const ego_loop_t *loop, uint32_t k, uint32_t track_us,
                             const ego_range_scan_t *range)
{
    if (!loop->config.use_clock) {
        return k * loop->period_us;
    }
    return track_us - (ego_range_lag_ns(range) + 500u) / 1000u;
}

#if EGO_LOOP_OBJECTS
/* The moving objects of scan k, after its line (ego_loop.h). Out of line:
 * its objects are not on the stack while the estimator runs. */
static EGO_NOINLINE void write_objects(ego_loop_t *loop, const ego_hal_t *hal, uint32_t k,
                                       const ego_range_scan_t *range, uint32_t t_us,
                                       const ego_output_t *out)
{
    ego_moving_object_t found[EGO_MOVING_MAX_OBJECTS];
    const uint8_t n = ego_moving_scan(&loop->moving, range, t_us, out, found, EGO_MOVING_MAX_OBJECTS);
    if (k == 0u) {
        return;
    }
    if (loop->config.objects_observer != NULL) {
        loop->config.objects_observer(loop->config.objects_ctx, k, found, n);
    }
    if (!loop->config.objects || loop->config.frames) {
        return;
    }
    for (uint8_t i = 0u; i < n; i++) {
        const ego_moving_object_t *o = &found[i];
        line_t l = {loop->line, sizeof loop->line, 0u};
        put_text(&l, "o,");
        put_number(&l, k, 0u, true);
        put_number(&l, o->id, 0u, true);
        put_number(&l, o->cx_cm, 2u, true);
        put_number(&l, o->cy_cm, 2u, true);
        put_number(&l, o->length_cm, 2u, true);
        put_number(&l, o->width_cm, 2u, true);
        if (o->vx_cms == EGO_MOVING_UNKNOWN) {
            put_text(&l, "nan,nan,");
        } else {
            put_number(&l, o->vx_cms, 2u, true);
            put_number(&l, o->vy_cms, 2u, true);
        }
        put_number(&l, o->points, 0u, false);
        write_text(hal, loop->line, l.len);
    }
}
#endif

static void on_scan(ego_loop_t *loop, const ego_hal_t *hal, uint32_t track_us)
{
    const uint32_t k = loop->stats.scans++;
    if (loop->period_us == 0u) {
        loop->period_us = lms_scan_period_us(loop->scan.count);
    }
    ego_output_t out;
    ego_pose_t prior;
    const bool has_prior = k > 0u && loop->config.prior != NULL &&
                           loop->config.prior(loop->config.prior_ctx, k, &prior);
    ego_range_scan_t range; /* points into loop->scan */
    if (ego_lms_to_range(&loop->scan, &loop->config.lms, &range) != EGO_LMS_OK) {
        loop->stats.decode_errors++;
        return;
    }
    const uint32_t t_us = scan_time_us(loop, k, track_us, &range);
    if (ego_process_with_prior(&loop->ego, &loop->config.ego, &range, t_us,
                               has_prior ? &prior : NULL, &out) != EGO_OK) {
        loop->stats.decode_errors++;
        return;
    }
    if (k == 0u) {
#if EGO_LOOP_OBJECTS
        if (loop->config.objects || loop->config.objects_observer != NULL) {
            write_objects(loop, hal, k, &range, t_us, &out); /* its first reference */
        }
#endif
        return; /* the first scan has no motion */
    }
    if (loop->config.observer != NULL) {
        loop->config.observer(loop->config.observer_ctx, k, t_us, &out);
    }
    if (loop->config.frames) {
        uint8_t frame[EGO_FRAME_SIZE];
        const size_t n = ego_frame_encode(frame, sizeof frame, k, t_us, &out);
        hal->write(hal->ctx, frame, n);
    } else {
        write_line(loop, hal, k, t_us, &out);
    }
#if EGO_LOOP_OBJECTS
    if (loop->config.objects || loop->config.objects_observer != NULL) {
        write_objects(loop, hal, k, &range, t_us, &out);
    }
#endif
    loop->stats.lines++;
    loop->stats.predicted += (out.flags & EGO_FLAG_PREDICTED) ? 1u : 0u;
    loop->stats.restarts += (out.flags & EGO_FLAG_FIRST) ? 1u : 0u;
}

void ego_loop_telegram(ego_loop_t *loop, const ego_hal_t *hal, const uint8_t *telegram, size_t len,
                       uint32_t track_us)
{
    if (telegram == NULL || len <= LMS_HEADER_SIZE || telegram[LMS_HEADER_SIZE] != LMS_REPLY_VALUES) {
        return;
    }
    if (lms_decode_scan(telegram, len, &loop->scan) != LMS_OK) {
        loop->stats.decode_errors++;
        return;
    }
    on_scan(loop, hal, track_us);
}

void ego_loop_gap(ego_loop_t *loop)
{
    ego_reset(&loop->ego);
#if EGO_LOOP_OBJECTS
    ego_moving_reset(&loop->moving);
#endif
}

void ego_loop_set_meas_mode(ego_loop_t *loop, uint8_t meas_mode)
{
    loop->config.lms.meas_mode = meas_mode;
}

static uint32_t framer_damage(const lms_framer_t *f)
{
    const lms_framer_stats_t *st = lms_framer_stats(f);
    return st->crc_errors + st->length_errors + st->truncated;
}

/* A framer event after the bytes that led to it, stamped now_us. */
static void on_event(ego_loop_t *loop, const ego_hal_t *hal, lms_framer_event_t ev,
                     uint32_t now_us)
{
    if (ev != LMS_FRAMER_TELEGRAM) {
        return;
    }
    size_t len = 0u;
    const uint8_t *t = lms_framer_telegram(&loop->framer, &len);
    uint32_t track_us = 0u;
    if (loop->config.use_clock && t != NULL && len > LMS_HEADER_SIZE) {
        /* What the live core does with the session's B0 and the A0 that
         * started the stream (ego_live.c). */
        if (t[LMS_HEADER_SIZE] == LMS_REPLY_VALUES) {
            track_us = ego_timing_scan(&loop->timing, t, len, now_us,
                                       (lms_baud_t)loop->config.line_baud,
                                       framer_damage(&loop->framer));
        } else if (t[LMS_HEADER_SIZE] == LMS_REPLY_MODE) {
            ego_timing_boundary(&loop->timing);
        }
    }
    ego_loop_telegram(loop, hal, t, len, track_us);
}

ego_loop_status_t ego_loop_step(ego_loop_t *loop, const ego_hal_t *hal)
{
    if (loop->ended) {
        return EGO_LOOP_END;
    }
    const int32_t got = hal->read(hal->ctx, loop->rx, sizeof loop->rx);
    const uint32_t now = hal->now_us(hal->ctx);
    if (got < 0) {
        /* End of input: whatever the framer still holds comes out now. */
        for (uint32_t guard = 0u; guard <= LMS_FRAMER_BUF_SIZE + 1u; guard++) {
            const lms_framer_event_t ev = lms_framer_flush(&loop->framer);
            if (ev == LMS_FRAMER_NEED_MORE) {
                break;
            }
            on_event(loop, hal, ev, now);
        }
        loop->ended = true;
        return EGO_LOOP_END;
    }
    if (got == 0) {
        return EGO_LOOP_IDLE;
    }
    loop->stats.bytes += (uint32_t)got;
    size_t offset = 0u;
    for (;;) { /* ends: the framer reports NEED_MORE once every byte is used */
        size_t used = 0u;
        const lms_framer_event_t ev =
            lms_framer_feed(&loop->framer, &loop->rx[offset], (size_t)got - offset, &used);
        offset += used;
        if (loop->config.use_clock) {
            ego_timing_bytes(&loop->timing, used, now, (lms_baud_t)loop->config.line_baud);
        }
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        on_event(loop, hal, ev, now);
    }
    return EGO_LOOP_BUSY;
}
