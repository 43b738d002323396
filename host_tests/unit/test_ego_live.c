/* test_ego_live.c - the firmware core with a live scanner (ego_live.h)
 * against the simulated LMS 2xx (lms_sim.h), in-process, on a simulated
 * clock: bring-up from 9600 to 500 kbaud, every scan's line, the same CSV
 * as a replay of the same telegrams (the `lmsego replay` loop), recovery
 * after a power cycle (the outage counted in scan intervals from the bytes'
 * arrival stamps, also when the main loop runs late), a clean stop, a main
 * loop that runs late, old-rate bytes dropped at the baud switch, a
 * refused setting, and the init checks.
 *
 * Scan times (ego_loop.h, "Scan times from arrival stamps"): every line's
 * time is checked against the rig's own record of when the telegram's last
 * byte arrived, less its wire time and the lag of its beams, and its dt
 * against the counted interval, also at 38400 baud with 361 values, under
 * stamp jitter, and with the latency column of a slow estimator.
 *
 * The rig is a board: what the core writes reaches the simulator at the
 * host UART's current rate; what the simulator sends goes through the
 * receive ring as an interrupt would put it, stamped with the time it
 * arrived. Time advances to whichever end needs it next, at most
 * RIG_STEP_US at a time. The scene: the scanner drives through
 * synth_room; scene scan i is always the same telegram, and a stream
 * started again after a restart goes on with the scans not sent yet, so
 * the scans the core gets are scene scans 0, 1, 2, ... when nothing is
 * lost.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ego_live.h"
#include "lms_encode.h"
#include "lms_sim.h"
#include "synth_scan.h"
#include "unity.h"

#define RIG_STEP_US 2000u
#define SEC 1000000u
#define SCENE_MAX 128u
#define OUT_MAX 32768u
#define JUNK (UART_RING_STAMP_BYTES + 8u) /* more than one ring read takes */
#define PI_D 3.14159265358979323846
/* How much later than its last byte a late loop may see a telegram's
 * stamp: the pause before the next telegram (13.3 ms period, 374 bytes of
 * 20 us) and the 31 bytes after it in its ring block. */
#define LATE_STAMP_US (13333u - 374u * 20u + 31u * 20u)

typedef struct {
    uint8_t bytes[LMS_TELEGRAM_MAX];
    size_t len;
} telegram_t;

typedef struct {
    /* The scene: telegrams built on first use. */
    telegram_t scene[SCENE_MAX];
    uint32_t scene_built;
    uint32_t base;        /* scene index of k = 0 of the current stream */
    uint32_t last_k;
    bool asked;
    /* The board. */
    lms_sim_t sim;
    uart_ring_t ring;
    ego_live_t live;
    lms_baud_t host_baud;
    uint64_t now;
    uint32_t baud_sets;
    uint64_t first_streaming_us; /* 0: not yet */
    uint64_t sent_us[SCENE_MAX]; /* when the scanner queued its i-th scan */
    lms_framer_t watch;          /* the rig's view of every byte, for ... */
    uint32_t b0_seen;            /* ... the B0 telegrams that arrived, */
    uint64_t b0_end_us[SCENE_MAX]; /* when each one's last byte did, */
    uint16_t b0_len[SCENE_MAX];  /* and its length */
    uint16_t scene_values;       /* values per scene scan: 181 (default) or 361 */
    uint32_t dma_us;             /* > 0: the UART hands bytes over only this often */
    uint32_t jitter_us;          /* stamps late by up to this much more (DMA mode) */
    uint32_t rnd;
    uint64_t next_dma_us;
    uint32_t time_slack_us;      /* check_times: allowed beyond the band */
    /* Junk after the scanner's answer to the baud switch, in the same
     * chunk, as if the line had carried on at the old rate. */
    bool junk_on_switch;
    uint32_t junk_sent;
    lms_framer_t side;           /* the rig's own view of the scanner's bytes */
    uint8_t scene_mode;          /* measuring mode of the scene's values: 00 (cm) or
                                    06 (mm, 15 bits: the room's far walls need more than
                                    mode 00's 13) */
    char out[OUT_MAX];
    size_t out_len;
    bool out_overflow;
} rig_t;

static rig_t R;

/* Lengths that are a choice: under the emulator every scan runs the
 * estimator at an instruction a host cycle, and the CI has minutes. */
#if defined(LMSEGO_UNIT_ON_TARGET)
#define TIME_SCANS 40u     /* scan-time tests: scans compared */
#define JITTER_SCANS 40u
#else
#define TIME_SCANS 120u
#define JITTER_SCANS 100u
#endif

void setUp(void)
{
}

void tearDown(void)
{
}

/* --- The scene ---------------------------------------------------------- */

static const telegram_t *scene_scan(uint32_t i)
{
    static lms_scan_t scan;
    while (R.scene_built <= i && R.scene_built < SCENE_MAX) {
        const double k = (double)R.scene_built;
        /* 3 cm and 0.25 deg per scan: an easy drive for the estimator. */
        synth_scan(synth_room, synth_room_walls, 0.03 * k, 0.004 * k, 0.25 * k * PI_D / 180.0,
                   R.scene_values == 0u ? 181u : R.scene_values, LMS_UNIT_CM, &scan);
        if (R.scene_mode == LMS_MEAS_32M_FIELD_A) {
            /* The same ranges in mm, 15 bits; the top codes moved up. */
            for (unsigned b = 0u; b < scan.count; b++) {
                const unsigned v = scan.values[b] & 0x1FFFu;
                scan.values[b] = (uint16_t)(v >= 0x1FF7u ? 0x7FFFu - (0x1FFFu - v) : v * 10u);
            }
            scan.unit = LMS_UNIT_MM;
        }
        telegram_t *t = &R.scene[R.scene_built];
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(t->bytes, sizeof t->bytes, 0x80u, &scan,
                                                      &t->len));
        R.scene_built++;
    }
    return i < SCENE_MAX ? &R.scene[i] : NULL;
}

/* Scan k of the current stream. The simulator asks for k + 1 as soon as k
 * is queued, so when a new stream starts (k = 0 again) the last scan asked
 * for was never sent: the new stream starts with it. */
static bool source(void *ctx, uint32_t k, uint16_t angle_deg, uint16_t resolution_cdeg,
                   bool partial, lms_unit_t unit, uint8_t reply_address, uint8_t *out, size_t cap,
                   size_t *len, uint32_t *gap_us)
{
    (void)ctx;
    (void)angle_deg;
    (void)resolution_cdeg;
    (void)partial;
    (void)unit;
    (void)reply_address;
    if (k == 0u && R.asked) {
        R.base += R.last_k;
    }
    R.asked = true;
    R.last_k = k;
    const telegram_t *t = scene_scan(R.base + k);
    if (t == NULL || t->len > cap) {
        return false;
    }
    memcpy(out, t->bytes, t->len);
    *len = t->len;
    *gap_us = 0u;
    return true;
}

/* --- The board ---------------------------------------------------------- */

static void hal_scanner_write(void *ctx, const uint8_t *bytes, size_t len)
{
    rig_t *r = ctx;
    lms_sim_receive(&r->sim, bytes, len, r->host_baud, r->now);
}

static void hal_set_baud(void *ctx, lms_baud_t baud)
{
    rig_t *r = ctx;
    r->host_baud = baud;
    r->baud_sets++;
}

static uint32_t hal_now_us(void *ctx)
{
    const rig_t *r = ctx;
    return (uint32_t)r->now;
}

static void hal_out(void *ctx, const uint8_t *bytes, size_t len)
{
    rig_t *r = ctx;
    if (r->out_len + len >= sizeof r->out) {
        r->out_overflow = true;
        return;
    }
    memcpy(&r->out[r->out_len], bytes, len);
    r->out_len += len;
    r->out[r->out_len] = '\0';
}

static void config_defaults(lms_sim_config_t *sc, ego_live_config_t *lc)
{
    lms_sim_defaults(sc);
    sc->scan_source = source; /* powers up at 9600, 180 deg / 0.5 deg */
    ego_live_defaults(lc);
    lc->session.baud = LMS_BAUD_500000;
    lc->session.angle_deg = 180u;
    lc->session.resolution_cdeg = 100u; /* 181 values, 75 Hz */
}

static void rig_init(const lms_sim_config_t *sc, const ego_live_config_t *lc)
{
    memset(&R, 0, sizeof R);
    R.now = 1000u;
    R.host_baud = LMS_BAUD_9600;
    lms_sim_init(&R.sim, sc, R.now);
    lms_framer_init(&R.side, LMS_FROM_SCANNER);
    lms_framer_init(&R.watch, LMS_FROM_SCANNER);
    R.rnd = 12345u;
    uart_ring_init(&R.ring);
    const ego_live_hal_t hal = {hal_scanner_write, hal_set_baud, hal_now_us, hal_out, &R};
    TEST_ASSERT_EQUAL_INT(LMS_OK, ego_live_init(&R.live, lc, &hal, &R.ring));
}

/* True when bytes[0..n) end with a complete A0 telegram (the answer to a
 * mode command such as the baud switch). */
static bool ends_with_mode_reply(const uint8_t *bytes, size_t n)
{
    size_t off = 0u;
    bool at_end = false;
    for (size_t guard = 0u; guard <= n + LMS_FRAMER_BUF_SIZE; guard++) {
        size_t used = 0u;
        const lms_framer_event_t ev = lms_framer_feed(&R.side, bytes + off, n - off, &used);
        off += used;
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        size_t len = 0u;
        const uint8_t *t = lms_framer_telegram(&R.side, &len);
        at_end = ev == LMS_FRAMER_TELEGRAM && off == n && t != NULL && len > LMS_HEADER_SIZE &&
                 t[LMS_HEADER_SIZE] == LMS_REPLY_MODE;
    }
    return at_end;
}

/* Records the B0 telegrams among bytes that arrived by R.now. */
static void watch_bytes(const uint8_t *bytes, size_t n)
{
    size_t off = 0u;
    for (size_t guard = 0u; guard <= n + LMS_FRAMER_BUF_SIZE; guard++) {
        size_t used = 0u;
        const lms_framer_event_t ev = lms_framer_feed(&R.watch, bytes + off, n - off, &used);
        off += used;
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        size_t len = 0u;
        const uint8_t *t = lms_framer_telegram(&R.watch, &len);
        if (ev == LMS_FRAMER_TELEGRAM && t != NULL && len > LMS_HEADER_SIZE &&
            t[LMS_HEADER_SIZE] == LMS_REPLY_VALUES && R.b0_seen < SCENE_MAX) {
            R.b0_end_us[R.b0_seen] = R.now;
            R.b0_len[R.b0_seen] = (uint16_t)len;
            R.b0_seen++;
        }
    }
}

static uint32_t rig_rnd(void)
{
    R.rnd ^= R.rnd << 13;
    R.rnd ^= R.rnd >> 17;
    R.rnd ^= R.rnd << 5;
    return R.rnd;
}

/* The receive interrupt: what the simulator has put on the wire by now
 * (with dma_us, only every dma_us, stamped up to jitter_us late). */
static void rig_receive(void)
{
    static uint8_t buf[512];
    if (R.dma_us > 0u) {
        if (R.now < R.next_dma_us) {
            return;
        }
        R.next_dma_us = R.now + R.dma_us;
    }
    const uint32_t late = R.jitter_us > 0u ? rig_rnd() % (R.jitter_us + 1u) : 0u;
    const uint32_t stamp = (uint32_t)R.now + late;
    for (int guard = 0; guard < 64; guard++) {
        const size_t n = lms_sim_transmit(&R.sim, R.host_baud, R.now, buf, sizeof buf);
        watch_bytes(buf, n);
        (void)uart_ring_write(&R.ring, buf, n, stamp);
        if (R.junk_on_switch && ends_with_mode_reply(buf, n) &&
            lms_session_state(ego_live_session(&R.live)) == LMS_SESSION_SWITCH) {
            static uint8_t junk[JUNK];
            memset(junk, 0x55, sizeof junk); /* never STX, ACK or NAK */
            R.junk_sent += (uint32_t)uart_ring_write(&R.ring, junk, sizeof junk, (uint32_t)R.now);
        }
        /* The wire's own clock, for the tests to check the core's times. */
        const uint32_t sent = lms_sim_stats(&R.sim)->scans_sent;
        for (uint32_t i = 0u; i < sent && i < SCENE_MAX; i++) {
            R.sent_us[i] = R.sent_us[i] == 0u ? R.now : R.sent_us[i];
        }
        if (n < sizeof buf) {
            return;
        }
    }
}

/* Runs until the core is no longer RUNNING or `until` (absolute us). With
 * step_every_us > 0 the main loop only runs that often (a loop busy
 * elsewhere); the ring fills meanwhile. */
static void rig_run(uint64_t until, uint32_t step_every_us)
{
    uint64_t next_step = R.now;
    while (R.now < until && ego_live_status(&R.live) == EGO_LIVE_RUNNING) {
        uint64_t step = RIG_STEP_US;
        if (step_every_us == 0u) {
            const uint32_t wait = ego_live_wait_us(&R.live);
            step = wait < step ? wait : step;
        }
        const uint64_t sim_next = lms_sim_next_event_us(&R.sim, R.now);
        if (sim_next != UINT64_MAX && sim_next - R.now < step) {
            step = sim_next - R.now;
        }
        R.now += step == 0u ? 1u : step;
        rig_receive();
        if (R.now >= next_step) {
            (void)ego_live_step(&R.live);
            next_step = R.now + step_every_us;
            if (R.first_streaming_us == 0u &&
                lms_session_state(ego_live_session(&R.live)) == LMS_SESSION_STREAMING) {
                R.first_streaming_us = R.now;
            }
        }
    }
}

/* --- The reference: the replay loop over the same telegrams ------------- */

typedef struct {
    const uint8_t *bytes;
    size_t len;
    size_t pos;
    char out[OUT_MAX];
    size_t out_len;
} replay_t;

static replay_t P;
static uint8_t replay_stream[SCENE_MAX * LMS_TELEGRAM_MAX];

static int32_t replay_read(void *ctx, uint8_t *buf, size_t cap)
{
    replay_t *p = ctx;
    if (p->pos >= p->len) {
        return -1;
    }
    size_t n = p->len - p->pos;
    n = n < cap ? n : cap;
    memcpy(buf, p->bytes + p->pos, n);
    p->pos += n;
    return (int32_t)n;
}

static void replay_write(void *ctx, const uint8_t *buf, size_t len)
{
    replay_t *p = ctx;
    TEST_ASSERT_TRUE(p->out_len + len < sizeof p->out);
    memcpy(&p->out[p->out_len], buf, len);
    p->out_len += len;
    p->out[p->out_len] = '\0';
}

static uint32_t replay_now(void *ctx)
{
    (void)ctx;
    return 0u;
}

/* `lmsego replay` of scene scans [from, to): ego_loop_step over the bytes,
 * times from the scan index and the mode's period. */
static const char *replay(uint32_t from, uint32_t to)
{
    static ego_loop_t loop;
    static ego_loop_config_t config;
    size_t len = 0u;
    for (uint32_t i = from; i < to; i++) {
        const telegram_t *t = scene_scan(i);
        TEST_ASSERT_NOT_NULL(t);
        memcpy(&replay_stream[len], t->bytes, t->len);
        len += t->len;
    }
    memset(&P, 0, sizeof P);
    P.bytes = replay_stream;
    P.len = len;
    ego_live_config_t live;
    ego_live_defaults(&live);
    config = live.loop; /* the live core's: `replay --budget default` */
    config.lms.meas_mode = R.scene_mode; /* `lmsego replay --mode` */
    ego_loop_init(&loop, &config);
    const ego_hal_t hal = {replay_read, replay_write, replay_now, &P};
    for (uint32_t guard = 0u; guard < 100000u; guard++) {
        if (ego_loop_step(&loop, &hal) == EGO_LOOP_END) {
            break;
        }
    }
    TEST_ASSERT_EQUAL_UINT32(to - from, ego_loop_stats(&loop)->scans);
    return P.out;
}

/* Line n (0 = the header) of a CSV text, without its newline, into buf. */
static const char *csv_line(const char *text, unsigned n, char *buf, size_t cap)
{
    for (unsigned i = 0u; i < n && text != NULL; i++) {
        text = strchr(text, '\n');
        text = text != NULL ? text + 1 : NULL;
    }
    if (text == NULL || *text == '\0') {
        return NULL;
    }
    size_t len = 0u;
    while (text[len] != '\0' && text[len] != '\n' && len + 1u < cap) {
        buf[len] = text[len];
        len++;
    }
    buf[len] = '\0';
    return buf;
}

/* The fields after the second comma: the motion, not scan index and time. */
static const char *motion_fields(const char *line)
{
    const char *p = strchr(line, ',');
    p = p != NULL ? strchr(p + 1, ',') : NULL;
    return p != NULL ? p + 1 : "";
}

static unsigned long field(const char *line, unsigned n)
{
    for (unsigned i = 0u; i < n && line != NULL; i++) {
        line = strchr(line, ',');
        line = line != NULL ? line + 1 : NULL;
    }
    unsigned long v = 0u;
    while (line != NULL && *line >= '0' && *line <= '9') {
        v = v * 10u + (unsigned long)(*line - '0');
        line++;
    }
    return v;
}

/* The time column in microseconds (six decimals). */
static uint32_t time_us(const char *line)
{
    const char *p = strchr(line, ',');
    uint32_t v = 0u;
    for (p = p != NULL ? p + 1 : ""; *p != '\0' && *p != ','; p++) {
        if (*p >= '0' && *p <= '9') {
            v = v * 10u + (uint32_t)(*p - '0');
        }
    }
    return v;
}

/* --- Scan times ------------------------------------------------------------ */

/* The lag from the mean beam of a scene scan to its last (ego_range.h),
 * through the LMS adapter, us rounded as the loop rounds it. */
static uint32_t scene_lag_us(void)
{
    static lms_scan_t scan;
    const telegram_t *t = scene_scan(0u);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_scan(t->bytes, t->len, &scan));
    ego_lms_params_t params;
    ego_lms_defaults(&params);
    params.meas_mode = R.scene_mode;
    ego_range_scan_t range;
    TEST_ASSERT_EQUAL_INT(EGO_LMS_OK, ego_lms_to_range(&scan, &params, &range));
    return (ego_range_lag_ns(&range) + 500u) / 1000u;
}

/* What the time of B0 number i should be: the arrival of its last byte
 * (the rig's clock when the simulator handed it over) less its wire time
 * at baud and the lag of its beams. */
static uint32_t expected_time_us(uint32_t i, lms_baud_t baud)
{
    TEST_ASSERT_TRUE(i < R.b0_seen);
    return (uint32_t)R.b0_end_us[i] - lms_wire_us(R.b0_len[i], baud) - scene_lag_us();
}

/* Lines [first, last] of out (line n is scan n) against the rig's record:
 * each time within the tracker's band (plus R.time_slack_us) of
 * expected_time_us; the dt between
 * neighbouring lines exactly interval_us (exact_dt) or within the
 * tracker's slew of it; returns the largest time error seen. */
static uint32_t check_times(const char *out, unsigned first, unsigned last, lms_baud_t baud,
                            uint32_t interval_us, bool exact_dt)
{
    const uint32_t band = lms_wire_us(EGO_TIMING_BAND_BYTES, baud);
    const uint32_t slew = interval_us >> EGO_TIMING_SLEW_SHIFT;
    uint32_t worst = 0u;
    char line[EGO_LOOP_LINE_MAX + 32u];
    char prev[EGO_LOOP_LINE_MAX + 32u];
    for (unsigned n = first; n <= last; n++) {
        TEST_ASSERT_NOT_NULL(csv_line(out, n, line, sizeof line));
        TEST_ASSERT_EQUAL_UINT32(n, field(line, 0u));
        const int32_t error = (int32_t)(time_us(line) - expected_time_us(n, baud));
        const uint32_t size = (uint32_t)(error < 0 ? -error : error);
        worst = size > worst ? size : worst;
        TEST_ASSERT_TRUE_MESSAGE(size <= band + R.time_slack_us, line);
        if (n > first) {
            TEST_ASSERT_NOT_NULL(csv_line(out, n - 1u, prev, sizeof prev));
            const uint32_t dt = time_us(line) - time_us(prev);
            if (exact_dt) {
                TEST_ASSERT_EQUAL_UINT32_MESSAGE(interval_us, dt, line);
            } else {
                TEST_ASSERT_TRUE_MESSAGE(dt + slew >= interval_us && dt <= interval_us + slew,
                                         line);
            }
        }
    }
    return worst;
}

/* Lines [first, last] of out move as lines [first - offset, ...] of the
 * replay ref: the same fields but the time. */
static void check_motion(const char *out, const char *ref, unsigned first, unsigned last,
                         unsigned offset)
{
    char a[EGO_LOOP_LINE_MAX + 32u];
    char b[EGO_LOOP_LINE_MAX + 32u];
    TEST_ASSERT_NOT_NULL(csv_line(out, 0u, a, sizeof a));
    TEST_ASSERT_NOT_NULL(csv_line(ref, 0u, b, sizeof b));
    TEST_ASSERT_EQUAL_STRING(b, a); /* the header */
    for (unsigned n = first; n <= last; n++) {
        TEST_ASSERT_NOT_NULL(csv_line(out, n, a, sizeof a));
        TEST_ASSERT_NOT_NULL(csv_line(ref, n - offset, b, sizeof b));
        TEST_ASSERT_EQUAL_STRING(motion_fields(b), motion_fields(a));
    }
}

/* --- Tests ---------------------------------------------------------------- */

/* 9600 at power-on, 500 kbaud wanted: streaming within 3 s, N scans, N - 1
 * lines, then a clean stop that leaves the scanner at 9600; the CSV is the
 * replay's, byte for byte. */
static void test_ego_live_brings_up_streams_and_stops(void)
{
    enum { N = 30 };
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.max_scans = N;
    rig_init(&sc, &lc);
    rig_run(R.now + 10u * SEC, 0u);
    TEST_ASSERT_TRUE(R.first_streaming_us > 0u);
    TEST_ASSERT_TRUE(R.first_streaming_us - 1000u < 3u * SEC);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    const ego_live_stats_t *st = ego_live_stats(&R.live);
    const lms_session_stats_t *ss = lms_session_stats(ego_live_session(&R.live));
    TEST_ASSERT_EQUAL_UINT32(N, st->scans);
    TEST_ASSERT_EQUAL_UINT32(0u, st->gaps);
    TEST_ASSERT_EQUAL_UINT32(1u, ss->bring_ups);
    TEST_ASSERT_EQUAL_UINT32(0u, ss->restarts);
    TEST_ASSERT_EQUAL_UINT32(1u, ss->baud_switches);
    TEST_ASSERT_EQUAL_UINT32(N - 1u, ego_loop_stats(ego_live_loop(&R.live))->lines);
    TEST_ASSERT_EQUAL_UINT32(0u, uart_ring_dropped(&R.ring));
    TEST_ASSERT_FALSE(R.out_overflow);
    /* Stopped cleanly: both ends back at 9600. */
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&R.sim));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, R.host_baud);
    TEST_ASSERT_TRUE(R.baud_sets >= 3u); /* probe at 500k, 9600, switch up, back down */
    /* The motion of `lmsego replay` of the scans it got, at their true
     * times, the counted interval apart. */
    check_motion(R.out, replay(0u, N), 1u, N - 1u, 0u);
    (void)check_times(R.out, 1u, N - 1u, LMS_BAUD_500000, 13333u, true);
}

/* A scanner left in measuring mode 06 (15-bit mm ranges, a field flag in
 * bit 15) and mm units, both kept by the session's default policy: the
 * core decodes the values with the mode the session found, so the CSV is
 * that of `lmsego replay --mode 06`. Decoded with mode 00's 13-bit mask,
 * every range beyond 8.19 m would come out wrong. */
static void test_ego_live_decodes_in_the_scanners_measuring_mode(void)
{
    enum { N = 30 };
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    sc.meas_mode = LMS_MEAS_32M_FIELD_A;
    sc.unit = LMS_UNIT_MM;
    lc.max_scans = N;
    rig_init(&sc, &lc);
    R.scene_mode = LMS_MEAS_32M_FIELD_A;
    rig_run(R.now + 10u * SEC, 0u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_HEX8(LMS_MEAS_32M_FIELD_A,
                           lms_session_info(ego_live_session(&R.live))->meas_mode);
    TEST_ASSERT_EQUAL_UINT32(N - 1u, ego_loop_stats(ego_live_loop(&R.live))->lines);
    /* The scene does reach beyond mode 00's range. */
    const telegram_t *t = scene_scan(0u);
    static lms_scan_t first;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_scan(t->bytes, t->len, &first));
    unsigned far = 0u;
    for (unsigned b = 0u; b < first.count; b++) {
        far += ((first.values[b] & 0x7FFFu) > 8191u && (first.values[b] & 0x7FFFu) < 0x7FF7u) ? 1u : 0u;
    }
    TEST_ASSERT_TRUE(far > 20u);
    check_motion(R.out, replay(0u, N), 1u, N - 1u, 0u);
    (void)check_times(R.out, 1u, N - 1u, LMS_BAUD_500000, 13333u, true);
}

/* A power cycle after 15 scans (back at 9600, variant reset): the session
 * notices, the core restarts the estimator (one line flagged FIRST), the
 * scanner comes back at 500 kbaud, and the scans go on. Before the fault
 * the lines are the replay's; after it, the motion of every line but the
 * first is that of a replay starting at the first scan after the fault.
 * The first line after the fault is later by the outage in whole scan
 * intervals, counted from the times the bytes arrived, also when the main
 * loop only runs every step_every_us. */
static void power_cycle_run(uint32_t step_every_us)
{
    enum { N = 40, FAULT = 15 };
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    sc.faults.power_cycle_after_scans = FAULT;
    lc.max_scans = N;
    rig_init(&sc, &lc);
    rig_run(R.now + 20u * SEC, step_every_us);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    const ego_live_stats_t *st = ego_live_stats(&R.live);
    const lms_session_stats_t *ss = lms_session_stats(ego_live_session(&R.live));
    TEST_ASSERT_EQUAL_UINT32(N, st->scans);
    TEST_ASSERT_EQUAL_UINT32(1u, st->gaps);
    TEST_ASSERT_EQUAL_UINT32(1u, ss->restarts);
    TEST_ASSERT_EQUAL_UINT32(2u, ss->bring_ups);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&R.sim)->power_cycles);
    TEST_ASSERT_EQUAL_UINT32(0u, uart_ring_dropped(&R.ring));
    const ego_loop_stats_t *ls = ego_loop_stats(ego_live_loop(&R.live));
    TEST_ASSERT_EQUAL_UINT32(N - 1u, ls->lines);
    TEST_ASSERT_EQUAL_UINT32(1u, ls->restarts);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&R.sim));

    static char live_out[OUT_MAX];
    memcpy(live_out, R.out, R.out_len + 1u);
    char a[EGO_LOOP_LINE_MAX];
    char prev[EGO_LOOP_LINE_MAX];
    /* Lines 1 .. FAULT - 1: scans 1 .. FAULT - 1, as the replay's. */
    check_motion(live_out, replay(0u, FAULT), 1u, FAULT - 1u, 0u);
    /* Line FAULT: the first scan after the restart, flagged. */
    TEST_ASSERT_NOT_NULL(csv_line(live_out, FAULT, a, sizeof a));
    TEST_ASSERT_NOT_NULL(csv_line(live_out, FAULT - 1u, prev, sizeof prev));
    TEST_ASSERT_EQUAL_UINT32(FAULT, field(a, 0u));
    TEST_ASSERT_TRUE((field(a, 8u) & EGO_FLAG_FIRST) != 0u);
    /* Its time is its own, from the bytes' arrival stamps (not the loop's
     * clock): later than the last by the outage on the wire. */
    const uint32_t jump = time_us(a) - time_us(prev);
    const uint32_t outage = (uint32_t)(R.sent_us[FAULT] - R.sent_us[FAULT - 1u]);
    TEST_ASSERT_TRUE(outage > 10u * 13333u); /* the power cycle takes about a second */
    {
        char msg[96];
        (void)snprintf(msg, sizeof msg, "loop every %u us: outage %u us, times %u us apart (%+d)",
                       (unsigned)step_every_us, (unsigned)outage, (unsigned)jump,
                       (int)(int32_t)(jump - outage));
        TEST_MESSAGE(msg);
    }
    /* Every line at its true time: the stamps of a late loop's ring are
     * late only for the block a telegram shares with the next one, and each
     * scan takes the least bound of its pieces. */
    (void)check_times(live_out, 1u, FAULT - 1u, LMS_BAUD_500000, 13333u, true);
    (void)check_times(live_out, FAULT, N - 1u, LMS_BAUD_500000, 13333u, true);
    /* Lines FAULT + 1 .. N - 1 move as a replay of scans FAULT .. N - 1:
     * nothing lost after the restart. */
    const char *after = replay(FAULT, N);
    check_motion(live_out, after, FAULT + 1u, N - 1u, FAULT);
    TEST_ASSERT_NULL(csv_line(live_out, N, a, sizeof a)); /* nothing more */
}

static void test_ego_live_recovers_after_power_cycle(void)
{
    power_cycle_run(0u);
}

/* The same with a main loop that only runs every 30 ms: the arrival
 * stamps, not the time the loop got to the bytes, count the outage. */
static void test_ego_live_recovers_after_power_cycle_late_loop(void)
{
    power_cycle_run(30000u);
    power_cycle_run(50000u);
}

/* The main loop runs only every 40 ms (busy elsewhere): the ring holds
 * three scans meanwhile, nothing is lost or restarted, the motion is still
 * the replay's and the times are the scans' own (from the ring's stamps,
 * not from when the loop ran), the counted interval apart. */
static void test_ego_live_late_main_loop(void)
{
    enum { N = 25 };
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.max_scans = N;
    rig_init(&sc, &lc);
    rig_run(R.now + 15u * SEC, 40000u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_UINT32(N, ego_live_stats(&R.live)->scans);
    TEST_ASSERT_EQUAL_UINT32(0u, lms_session_stats(ego_live_session(&R.live))->restarts);
    TEST_ASSERT_EQUAL_UINT32(0u, uart_ring_dropped(&R.ring));
    /* 40 ms at 75 Hz: three telegrams of 374 bytes at least once. */
    TEST_ASSERT_TRUE(uart_ring_peak(&R.ring) >= 3u * 374u);
    TEST_ASSERT_TRUE(uart_ring_peak(&R.ring) < UART_RING_SIZE);
    check_motion(R.out, replay(0u, N), 1u, N - 1u, 0u);
    (void)check_times(R.out, 1u, N - 1u, LMS_BAUD_500000, 13333u, true);
}

/* The bytes after the scanner's answer to the baud switch came at the old
 * rate: what the ring still holds when the session changes the rate is
 * dropped, not fed to the session (the rest of the chunk with the answer,
 * at most UART_RING_STAMP_BYTES - 1 bytes, is fed: the session skips it). */
static void test_ego_live_rate_change_drops_old_rate_bytes(void)
{
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.max_scans = 3u;
    rig_init(&sc, &lc);
    R.junk_on_switch = true;
    rig_run(R.now + 10u * SEC, 0u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_UINT32(3u, ego_live_stats(&R.live)->scans);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_session_stats(ego_live_session(&R.live))->baud_switches);
    TEST_ASSERT_EQUAL_UINT32(JUNK, R.junk_sent);
    const uint32_t dropped = ego_live_stats(&R.live)->bytes_discarded;
    TEST_ASSERT_TRUE(dropped >= JUNK - (UART_RING_STAMP_BYTES - 1u));
    TEST_ASSERT_TRUE(dropped <= JUNK);
}

/* A variant the scanner does not have: FAILED, no scan, no line. */
static void test_ego_live_refused_setting_fails(void)
{
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    sc.fixed_angle_deg = 180u;
    sc.fixed_resolution_cdeg = 50u;
    rig_init(&sc, &lc);
    rig_run(R.now + 20u * SEC, 0u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_FAILED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_INT(LMS_SESSION_ERR_VARIANT,
                          lms_session_error(ego_live_session(&R.live)));
    TEST_ASSERT_EQUAL_UINT32(0u, ego_live_stats(&R.live)->scans);
    TEST_ASSERT_EQUAL_UINT(0u, R.out_len);
    /* Once failed, a step does nothing. */
    const uint32_t sent = lms_sim_stats(&R.sim)->host_telegrams;
    R.now += SEC;
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_FAILED, ego_live_step(&R.live));
    TEST_ASSERT_EQUAL_UINT32(sent, lms_sim_stats(&R.sim)->host_telegrams);
}

/* Init: missing pieces are refused; bytes waiting from before are
 * discarded; a stop before the scanner was found stops at once. */
static void test_ego_live_init_checks_and_early_stop(void)
{
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    memset(&R, 0, sizeof R);
    uart_ring_init(&R.ring);
    ego_live_hal_t hal = {hal_scanner_write, hal_set_baud, hal_now_us, hal_out, &R};
    ego_live_hal_t bad = hal;
    bad.out_write = NULL;
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, ego_live_init(&R.live, &lc, &bad, &R.ring));
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_FAILED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, ego_live_init(&R.live, &lc, &hal, NULL));
    ego_live_config_t wrong = lc;
    wrong.session.retries = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, ego_live_init(&R.live, &wrong, &hal, &R.ring));
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_FAILED, ego_live_step(&R.live));

    const uint8_t stale[7] = {1u, 2u, 3u, 4u, 5u, 6u, 7u};
    (void)uart_ring_write(&R.ring, stale, sizeof stale, 1u);
    lms_sim_init(&R.sim, &sc, 0u);
    R.host_baud = LMS_BAUD_9600;
    TEST_ASSERT_EQUAL_INT(LMS_OK, ego_live_init(&R.live, &lc, &hal, &R.ring));
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_count(&R.ring));
    TEST_ASSERT_EQUAL_UINT32(7u, ego_live_stats(&R.live)->bytes_discarded);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_RUNNING, ego_live_step(&R.live));
    ego_live_stop(&R.live);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_step(&R.live));
    TEST_ASSERT_EQUAL_UINT(0u, R.out_len);
}

/* --- Deferred mode --------------------------------------------------------- */

/* A microcontroller whose estimator takes cost_us per scan. The receive
 * interrupt fills the ring all the time (every SERVICE_US here). Deferred:
 * a timer interrupt runs ego_live_service every SERVICE_US, also while the
 * main loop is inside ego_live_estimate. Not deferred: the main loop's
 * ego_live_step runs the estimator inline, and nothing serves the line
 * until it returns. Runs for `span` from now. */
#define SERVICE_US 1000u

static void rig_run_busy(uint64_t span, uint32_t cost_us)
{
    const uint64_t until = R.now + span;
    uint64_t busy_until = R.now;
    const bool deferred = R.live.deferred;
    while (R.now < until && ego_live_status(&R.live) == EGO_LIVE_RUNNING) {
        R.now += SERVICE_US;
        rig_receive();
        if (deferred) {
            ego_live_service(&R.live); /* the timer interrupt */
            if (R.now >= busy_until && ego_live_estimate(&R.live)) {
                busy_until = R.now + cost_us;
            }
        } else if (R.now >= busy_until) {
            const uint32_t before = ego_live_stats(&R.live)->scans;
            (void)ego_live_step(&R.live);
            if (ego_live_stats(&R.live)->scans != before) {
                busy_until = R.now + cost_us;
            }
        }
    }
}

/* Field n of a CSV line as a number: [-]digits[.digits], as the loop
 * prints them (parsed by hand: newlib's strtod would pull the heap into
 * the target's test image). A field that does not parse fails the test. */
static double number(const char *line, unsigned n)
{
    for (unsigned i = 0u; i < n && line != NULL; i++) {
        line = strchr(line, ',');
        line = line != NULL ? line + 1 : NULL;
    }
    if (line == NULL) {
        TEST_FAIL_MESSAGE("a CSV line with too few fields");
        return 0.0;
    }
    const bool negative = *line == '-';
    line += negative ? 1 : 0;
    double v = 0.0;
    double scale = 0.0; /* 0 before the point, then 0.1, 0.01, ... */
    unsigned digits = 0u;
    for (; *line != '\0' && *line != ','; line++) {
        if (*line == '.' && scale == 0.0) {
            scale = 0.1;
        } else if (*line >= '0' && *line <= '9') {
            const double d = (double)(*line - '0');
            if (scale == 0.0) {
                v = v * 10.0 + d;
            } else {
                v += d * scale;
                scale /= 10.0;
            }
            digits++;
        } else {
            TEST_FAIL_MESSAGE("a CSV field that is not a number");
        }
    }
    TEST_ASSERT_TRUE(digits > 0u);
    return negative ? -v : v;
}

/* Brought up to streaming with an idle main loop. */
static void rig_until_streaming(void)
{
    for (int i = 0; i < 400 && R.first_streaming_us == 0u; i++) {
        rig_run(R.now + 10000u, 0u);
    }
    TEST_ASSERT_TRUE(R.first_streaming_us > 0u);
}

/* Deferred, with an estimator as fast as the line: every scan reaches it,
 * the motion is the replay's, the times the scans' own, and max_scans
 * stops cleanly. */
static void test_ego_live_deferred_without_load_is_the_replay(void)
{
    enum { N = 30 };
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.max_scans = N;
    lc.deferred = true;
    rig_init(&sc, &lc);
    rig_run(R.now + 10u * SEC, 0u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    const ego_live_stats_t *st = ego_live_stats(&R.live);
    TEST_ASSERT_EQUAL_UINT32(N, st->scans);
    TEST_ASSERT_EQUAL_UINT32(N, st->scans_estimated);
    TEST_ASSERT_EQUAL_UINT32(0u, st->scans_skipped);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&R.sim));
    check_motion(R.out, replay(0u, N), 1u, N - 1u, 0u);
    (void)check_times(R.out, 1u, N - 1u, LMS_BAUD_500000, 13333u, true);
}

/* The pose of scene scan b in the frame of scene scan a (the drive of
 * scene_scan). */
static void scene_motion(uint32_t a, uint32_t b, double *dx, double *dy, double *dtheta)
{
    const double ha = 0.25 * (double)a * PI_D / 180.0;
    const double hb = 0.25 * (double)b * PI_D / 180.0;
    const double ex = 0.03 * ((double)b - (double)a);
    const double ey = 0.004 * ((double)b - (double)a);
    *dx = cos(ha) * ex + sin(ha) * ey;
    *dy = -sin(ha) * ex + cos(ha) * ey;
    *dtheta = hb - ha;
}

/* Deferred, with an estimator that takes 100 ms a scan (7.5 scan
 * intervals): the line is served every millisecond meanwhile, so nothing
 * is dropped and the session never takes the busy estimator for a silent
 * scanner; the estimator gets the newest scan each time, the skipped ones
 * are counted, and every line's motion is the true motion over the scans
 * it spans. */
static void test_ego_live_deferred_keeps_the_line_behind_a_slow_estimator(void)
{
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.deferred = true;
    rig_init(&sc, &lc);
    rig_until_streaming();
    rig_run_busy(700000u, 100000u);
    const ego_live_stats_t *st = ego_live_stats(&R.live);
    const lms_session_stats_t *ss = lms_session_stats(ego_live_session(&R.live));
    char msg[160];
    (void)snprintf(msg, sizeof msg, "scans %lu estimated %lu skipped %lu restarts %lu dropped %lu",
                   (unsigned long)st->scans, (unsigned long)st->scans_estimated,
                   (unsigned long)st->scans_skipped, (unsigned long)ss->restarts,
                   (unsigned long)uart_ring_dropped(&R.ring));
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(EGO_LIVE_RUNNING, ego_live_status(&R.live), msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, ss->restarts, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(0u, uart_ring_dropped(&R.ring), msg);
    TEST_ASSERT_TRUE_MESSAGE(st->scans >= 45u, msg);
    TEST_ASSERT_TRUE_MESSAGE(st->scans_estimated >= 6u && st->scans_estimated <= 9u, msg);
    /* Every scan was estimated, skipped, or is the one still waiting. */
    const uint32_t accounted = st->scans_estimated + st->scans_skipped;
    TEST_ASSERT_TRUE_MESSAGE(accounted == st->scans || accounted + 1u == st->scans, msg);
    /* Each line spans several scans (its time says which scan it is: the
     * one whose telegram arrived a wire time and a lag after it); from the
     * second line on, the previous line's scan is the one it starts from,
     * and the motion must be the scene's. */
    const uint32_t band = lms_wire_us(EGO_TIMING_BAND_BYTES, LMS_BAUD_500000);
    unsigned checked = 0u;
    long prev_k = -1;
    char buf[256];
    for (unsigned n = 1u; csv_line(R.out, n, buf, sizeof buf) != NULL; n++) {
        const uint32_t t = time_us(buf);
        const double dx = number(buf, 2u);
        const double dy = number(buf, 3u);
        const double dth = number(buf, 4u);
        long k = -1;
        for (uint32_t i = 0u; i < R.b0_seen && k < 0; i++) {
            const int32_t e = (int32_t)(t - expected_time_us(i, LMS_BAUD_500000));
            k = (e <= (int32_t)band && e >= -(int32_t)band) ? (long)i : -1;
        }
        TEST_ASSERT_TRUE_MESSAGE(k >= 0, buf);
        if (prev_k >= 0) {
            TEST_ASSERT_TRUE_MESSAGE(k >= prev_k + 6, buf); /* the skipped scans */
            double ex = 0.0;
            double ey = 0.0;
            double eth = 0.0;
            scene_motion((uint32_t)prev_k, (uint32_t)k, &ex, &ey, &eth);
            TEST_ASSERT_TRUE_MESSAGE(fabs(dx - ex) < 0.01 && fabs(dy - ey) < 0.01, buf);
            TEST_ASSERT_TRUE_MESSAGE(fabs(dth - eth) < 0.2 * PI_D / 180.0, buf);
            checked++;
        }
        prev_k = k;
    }
    TEST_ASSERT_TRUE_MESSAGE(checked + 2u == st->scans_estimated, msg);
}

/* The same load on the inline estimator: nothing serves the line while it
 * works, so the ring overflows behind every scan (what deferred mode is
 * for). */
static void test_ego_live_inline_estimator_loses_bytes_behind_a_slow_one(void)
{
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    rig_init(&sc, &lc);
    rig_until_streaming();
    rig_run_busy(700000u, 100000u);
    char msg[96];
    (void)snprintf(msg, sizeof msg, "dropped %lu restarts %lu",
                   (unsigned long)uart_ring_dropped(&R.ring),
                   (unsigned long)lms_session_stats(ego_live_session(&R.live))->restarts);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(uart_ring_dropped(&R.ring) > 0u, msg);
}

/* ego_live_stop in deferred mode: a flag the next service acts on. */
static void test_ego_live_deferred_stop(void)
{
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.deferred = true;
    rig_init(&sc, &lc);
    rig_until_streaming();
    rig_run(R.now + 100000u, 0u);
    ego_live_stop(&R.live);
    TEST_ASSERT_EQUAL_UINT32(0u, ego_live_wait_us(&R.live)); /* the service is due */
    rig_run(R.now + 2u * SEC, 0u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&R.sim));
    TEST_ASSERT_FALSE(ego_live_estimate(&R.live) && ego_live_estimate(&R.live));
}

/* Deferred, an estimator taking 250 ms a scan, and the scanner silent for
 * 150 ms: the session restarts and is streaming again well within the
 * estimator's max_gap (1 s). The restart travels with the next scan into
 * the mailbox, and on to the newer scans that replace it while the
 * estimator is busy, so the estimator starts over (one line flagged FIRST)
 * instead of matching across the outage. */
static void test_ego_live_deferred_restart_reaches_the_estimator(void)
{
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    sc.faults.silence_after_scans = 12u;
    sc.faults.silence_us = 150000u;
    lc.deferred = true;
    rig_init(&sc, &lc);
    rig_until_streaming();
    rig_run_busy(1500000u, 250000u);
    const ego_live_stats_t *st = ego_live_stats(&R.live);
    char msg[128];
    (void)snprintf(msg, sizeof msg, "gaps %lu estimated %lu skipped %lu state %s sent %lu",
                   (unsigned long)st->gaps, (unsigned long)st->scans_estimated,
                   (unsigned long)st->scans_skipped,
                   lms_session_state_name(lms_session_state(ego_live_session(&R.live))),
                   (unsigned long)lms_sim_stats(&R.sim)->scans_sent);
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, st->gaps, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, ego_loop_stats(ego_live_loop(&R.live))->restarts, msg);
    unsigned first_lines = 0u;
    char buf[256];
    for (unsigned n = 1u; csv_line(R.out, n, buf, sizeof buf) != NULL; n++) {
        first_lines += ((field(buf, 8u) & EGO_FLAG_FIRST) != 0u) ? 1u : 0u;
    }
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(1u, first_lines, msg);
}

/* --- Scan times ------------------------------------------------------------ */

/* 181 values at 500 kbaud, TIME_SCANS scans: every line's time is the arrival of
 * its telegram's last byte less the wire time (372 bytes: 7 440 us) and
 * the lag (3 333 us), within the stamp granularity, and the lines are the
 * counted interval apart although the simulated mirror turns in 13 333.3
 * us (the count's 25 ppm stay inside the band). */
static void test_ego_live_scan_time_181_at_500k(void)
{
    enum { N = TIME_SCANS };
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.max_scans = N;
    rig_init(&sc, &lc);
    rig_run(R.now + 10u * SEC, 0u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_UINT32(N - 1u, ego_loop_stats(ego_live_loop(&R.live))->lines);
    TEST_ASSERT_EQUAL_UINT32(3333u, scene_lag_us());
    TEST_ASSERT_EQUAL_UINT32(7440u, lms_wire_us(R.b0_len[0], LMS_BAUD_500000));
    const uint32_t worst = check_times(R.out, 1u, N - 1u, LMS_BAUD_500000, 13333u, true);
    char msg[64];
    (void)snprintf(msg, sizeof msg, "largest time error %u us", (unsigned)worst);
    TEST_MESSAGE(msg);
}

/* 361 values (180 deg / 0.5 deg, two interlaced turns) at 38400 baud: a
 * telegram takes 190 ms on the wire (732 bytes), the scanner sends every
 * eighth scan (213 ms apart) and the lag is 9 990 us. */
static void test_ego_live_scan_time_361_at_38400(void)
{
    enum { N = 16 };
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.session.baud = LMS_BAUD_38400;
    lc.session.resolution_cdeg = 50u;
    lc.max_scans = N;
    rig_init(&sc, &lc);
    R.scene_values = 361u;
    rig_run(R.now + 20u * SEC, 0u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_38400, lms_session_info(ego_live_session(&R.live))->baud);
    TEST_ASSERT_EQUAL_UINT32(N - 1u, ego_loop_stats(ego_live_loop(&R.live))->lines);
    TEST_ASSERT_EQUAL_UINT32(9990u, scene_lag_us());
    TEST_ASSERT_EQUAL_UINT32(190625u, lms_wire_us(R.b0_len[0], LMS_BAUD_38400));
    const uint32_t interval = lms_scan_interval_us(361u, LMS_BAUD_38400);
    TEST_ASSERT_EQUAL_UINT32(213336u, interval);
    const uint32_t worst = check_times(R.out, 1u, N - 1u, LMS_BAUD_38400, interval, true);
    char msg[64];
    (void)snprintf(msg, sizeof msg, "largest time error %u us", (unsigned)worst);
    TEST_MESSAGE(msg);
}

/* The UART hands bytes over in 1 ms chunks (a DMA), each stamped up to
 * jitter_us late: within the band (600 us) the lines stay exactly the
 * counted interval apart; with 5 ms of jitter, far beyond it, dt moves by
 * at most the tracker's slew a scan and the times stay within the jitter
 * of the truth. */
static void stamp_jitter_run(uint32_t jitter_us, bool exact_dt)
{
    enum { N = JITTER_SCANS };
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.max_scans = N;
    rig_init(&sc, &lc);
    R.dma_us = 1000u;
    R.jitter_us = jitter_us;
    R.time_slack_us = exact_dt ? 0u : jitter_us;
    rig_run(R.now + 10u * SEC, 0u);
    TEST_ASSERT_EQUAL_INT(EGO_LIVE_STOPPED, ego_live_status(&R.live));
    TEST_ASSERT_EQUAL_UINT32(N - 1u, ego_loop_stats(ego_live_loop(&R.live))->lines);
    const uint32_t worst = check_times(R.out, 1u, N - 1u, LMS_BAUD_500000, 13333u, exact_dt);
    if (exact_dt) {
        check_motion(R.out, replay(0u, N), 1u, N - 1u, 0u);
    }
    char msg[80];
    (void)snprintf(msg, sizeof msg, "jitter %u us: largest time error %u us", (unsigned)jitter_us,
                   (unsigned)worst);
    TEST_MESSAGE(msg);
}

static void test_ego_live_dt_stays_the_interval_under_stamp_jitter(void)
{
    stamp_jitter_run(600u, true);
    stamp_jitter_run(5000u, false);
}


/* The tracker alone over an hour of 75 Hz scans (270 000), the mirror
 * 100 ppm slow or fast against the receiver's clock (and the integer
 * interval's own 25 ppm), three stamps in four late by up to 5 ms and the
 * fourth by up to 0.1 ms: the track never leaves the band around the
 * truth by more than the slew, and dt never moves by more than the slew. */
static void tracker_hour(double ppm)
{
    ego_timing_t t;
    ego_timing_reset(&t);
    const uint32_t interval = 13333u;
    const uint32_t band = lms_wire_us(EGO_TIMING_BAND_BYTES, LMS_BAUD_500000);
    const uint32_t slew = interval >> EGO_TIMING_SLEW_SHIFT;
    const double period = 1e6 / 75.0 * (1.0 + ppm * 1e-6);
    uint32_t rnd = 99u;
    uint32_t last = 0u;
    uint32_t moves = 0u;
    double worst = 0.0;
    for (uint32_t k = 0u; k < 270000u; k++) {
        const double truth = 5000.0 + (double)k * period;
        rnd ^= rnd << 13;
        rnd ^= rnd >> 17;
        rnd ^= rnd << 5;
        const uint32_t late = (rnd % 4u == 0u) ? rnd % 101u : rnd % 5001u;
        const uint32_t estimate = (uint32_t)llround(truth) + late;
        const uint32_t s = ego_timing_track(&t, estimate, 1u, interval, band);
        const double error = (double)s - truth;
        worst = (k >= 200u && fabs(error) > worst) ? fabs(error) : worst;
        if (k > 0u) {
            const uint32_t dt = s - last;
            TEST_ASSERT_TRUE(dt + slew >= interval && dt <= interval + slew);
            moves += dt != interval ? 1u : 0u;
        }
        /* After the first second, which may start 5 ms late and slews back. */
        TEST_ASSERT_TRUE(k < 200u || fabs(error) <= (double)(band + slew + 101u));
        last = s;
    }
    char msg[96];
    (void)snprintf(msg, sizeof msg,
                   "%+.0f ppm: largest error %.0f us after 200 scans, dt moved on %u of 270000",
                   ppm, worst, (unsigned)moves);
    TEST_MESSAGE(msg);
}

static void test_ego_live_tracker_follows_clock_drift_for_an_hour(void)
{
    tracker_hour(100.0);
    tracker_hour(-100.0);
    tracker_hour(0.0);
}

/* An estimator that takes 20 ms a scan (1.5 intervals) behind a consumer
 * that keeps every scan (`lmsego run`): the latency column grows by about
 * 6.7 ms a line, and each value is the clock when the line was written
 * less the line's time. */
#define LATENCY_QUEUE 64u

static void test_ego_live_latency_shows_a_slow_estimator(void)
{
    enum { LINES = 30 };
    static ego_live_slot_t queue[LATENCY_QUEUE];
    static uint64_t written_us[LINES + 2];
    lms_sim_config_t sc;
    ego_live_config_t lc;
    config_defaults(&sc, &lc);
    lc.deferred = true;
    lc.one_scan_per_service = true;
    lc.loop.latency = true;
    rig_init(&sc, &lc);
    rig_until_streaming();
    const uint32_t cost_us = 20000u;
    uint32_t head = 0u;
    uint32_t count = 0u;
    uint64_t busy_until = R.now;
    const ego_loop_stats_t *ls = ego_loop_stats(ego_live_loop(&R.live));
    for (uint32_t guard = 0u; guard < 3000u && ls->lines < LINES; guard++) {
        R.now += SERVICE_US;
        rig_receive();
        ego_live_service(&R.live);
        const ego_live_slot_t *slot = ego_live_take(&R.live);
        if (slot != NULL) {
            TEST_ASSERT_TRUE(count < LATENCY_QUEUE);
            queue[(head + count++) % LATENCY_QUEUE] = *slot;
        }
        if (count > 0u && R.now >= busy_until) {
            const uint32_t before = ls->lines;
            ego_live_estimate_slot(&R.live, &queue[head]);
            head = (head + 1u) % LATENCY_QUEUE;
            count--;
            busy_until = R.now + cost_us;
            const uint32_t after = ego_loop_stats(ego_live_loop(&R.live))->lines;
            if (after != before && after <= LINES) {
                written_us[after] = R.now; /* the clock the line was written at */
            }
        }
    }
    TEST_ASSERT_EQUAL_UINT32(LINES, ls->lines);
    char line[EGO_LOOP_LINE_MAX + 32u];
    TEST_ASSERT_NOT_NULL(csv_line(R.out, 0u, line, sizeof line));
    TEST_ASSERT_EQUAL_STRING(EGO_LOOP_CSV_COLUMNS ",latency_ms", line);
    double prev = 0.0;
    for (unsigned n = 1u; n <= LINES; n++) {
        TEST_ASSERT_NOT_NULL(csv_line(R.out, n, line, sizeof line));
        const double latency_ms = number(line, 17u);
        const uint32_t expected_us = (uint32_t)written_us[n] - time_us(line);
        TEST_ASSERT_TRUE_MESSAGE(fabs(latency_ms * 1000.0 - (double)expected_us) < 0.5, line);
        if (n == 1u) {
            /* Scan 0 was estimated at once (its lag, wire time and a tick:
             * 10-13 ms); scan 1 waited for it. */
            TEST_ASSERT_TRUE_MESSAGE(latency_ms - (20.0 - 13.333) > 10.0 &&
                                         latency_ms - (20.0 - 13.333) < 13.0,
                                     line);
        } else {
            TEST_ASSERT_TRUE_MESSAGE(fabs(latency_ms - prev - (20.0 - 13.333)) < 1.01, line);
        }
        prev = latency_ms;
    }
    char msg[64];
    (void)snprintf(msg, sizeof msg, "latency of line %u: %.3f ms", (unsigned)LINES, prev);
    TEST_MESSAGE(msg);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ego_live_brings_up_streams_and_stops);
    RUN_TEST(test_ego_live_decodes_in_the_scanners_measuring_mode);
    RUN_TEST(test_ego_live_recovers_after_power_cycle);
    RUN_TEST(test_ego_live_recovers_after_power_cycle_late_loop);
    RUN_TEST(test_ego_live_late_main_loop);
    RUN_TEST(test_ego_live_rate_change_drops_old_rate_bytes);
    RUN_TEST(test_ego_live_refused_setting_fails);
    RUN_TEST(test_ego_live_init_checks_and_early_stop);
    RUN_TEST(test_ego_live_deferred_without_load_is_the_replay);
    RUN_TEST(test_ego_live_deferred_keeps_the_line_behind_a_slow_estimator);
    RUN_TEST(test_ego_live_inline_estimator_loses_bytes_behind_a_slow_one);
    RUN_TEST(test_ego_live_deferred_stop);
    RUN_TEST(test_ego_live_deferred_restart_reaches_the_estimator);
    RUN_TEST(test_ego_live_scan_time_181_at_500k);
    RUN_TEST(test_ego_live_scan_time_361_at_38400);
    RUN_TEST(test_ego_live_dt_stays_the_interval_under_stamp_jitter);
    RUN_TEST(test_ego_live_tracker_follows_clock_drift_for_an_hour);
    RUN_TEST(test_ego_live_latency_shows_a_slow_estimator);
    return UNITY_END();
}
