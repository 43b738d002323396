/* fuzz_session.c - libFuzzer target over the session state machine
 * (driver/lms_session.h): arbitrary reply bytes, well-formed replies with
 * arbitrary contents, clock jumps, hang-ups and stops, with or without the
 * simulated scanner (driver/sim) answering on the line.
 *
 * Input: byte 0 picks the session's settings (bits 0-1 the rate, 2-3 the
 * variant: keep, 180/1, 180/0.5, 100/0.25; 4 partial scans; 5 millimetres;
 * 6 a power-on wait; 7 no restore of 9600), byte 1 the simulated
 * scanner's (bit 0 present, 1-2 its power-on rate, 3 millimetres, 4 a
 * fixed 100-degree variant, 5-7 byte faults). Then operations, one byte
 * each (the low 3 bits), with their arguments from the bytes that follow:
 *   0 FEED   n = 1 + next % 64 raw bytes, as if the scanner sent them
 *   1 REPLY  a telegram from the scanner with a good checksum: address
 *            0x80, n = 1 + next % 40 payload bytes from the input
 *   2 RUN    the line with the simulator for up to 1 + next % 64 steps
 *            (each step: the simulator's bytes in, the timers polled, the
 *            clock moved to the next thing due)
 *   3 JUMP   the session's clock jumps by the next 4 bytes (little
 *            endian, any value: backwards too), the line's clock does not
 *   4 WAIT   both clocks advance by the next 2 bytes * 16 us, then a poll
 *   5 HANGUP lms_session_link_lost
 *   6 STOP   lms_session_stop
 *   7 BYTE   one of ACK, NAK, STX, 0x80 (next % 4)
 * At most 400 line steps per input, so that an input stays fast.
 *
 * Checks (abort on violation), after every call:
 *  - the state is a state, every name function returns a string;
 *  - feed: *consumed <= the bytes given, EV_NONE only when all are used;
 *    poll settles (EV_NONE) within 64 calls;
 *  - the framer's accounting balances (bytes_in == telegram_bytes + acks +
 *    naks + bytes_skipped + pending);
 *  - the counters agree: restarts == restarts_silence + restarts_power_on +
 *    restarts_link, retries <= commands, scans == EV_SCAN events seen,
 *    restarts == EV_RESTART events seen or one more (one decided, not yet
 *    reported);
 *  - EV_SCAN: in STREAMING, lms_session_telegram gives a telegram that
 *    parses (good CRC) and is a B0; EV_FAILED: state FAILED with an error
 *    named; EV_STOPPED: state STOPPED; the telegram is NULL otherwise;
 *  - lms_session_wait_us never exceeds 2^31 us (no timeout may);
 *  - every write is one whole host telegram (it parses, at most
 *    LMS_CMD_MAX bytes), set_baud only ever gets one of the four rates;
 *  - no crash, no undefined behaviour (ASan, UBSan).
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "fuzz_check.h"
#include "lms_crc.h"
#include "lms_decode.h"
#include "lms_encode.h"
#include "lms_session.h"
#include "lms_sim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_STEPS 400u
#define MAX_STEP_US 20000u

static uint8_t next_byte(fuzz_input_t *in)
{
    return (uint8_t)fuzz_take(in, 1u);
}

typedef struct {
    lms_session_t s;
    lms_sim_t sim;
    bool with_sim;
    uint64_t line_us;   /* the line's (and simulator's) clock, monotonic */
    uint32_t skew_us;   /* the session's clock: line_us + skew_us, mod 2^32 */
    lms_baud_t host_baud;
    uint32_t steps;
    uint32_t scan_events;
    uint32_t restart_events;
} rig_t;

static rig_t R;

static uint32_t session_now(void)
{
    return (uint32_t)R.line_us + R.skew_us;
}

static void io_write(void *ctx, const uint8_t *bytes, size_t len)
{
    (void)ctx;
    lms_telegram_t t;
    FUZZ_CHECK(bytes != NULL && len > 0u && len <= LMS_CMD_MAX);
    FUZZ_CHECK(lms_telegram_parse(bytes, len, &t) == LMS_OK);
    if (R.with_sim) {
        lms_sim_receive(&R.sim, bytes, len, R.host_baud, R.line_us);
    }
}

static void io_set_baud(void *ctx, lms_baud_t baud)
{
    (void)ctx;
    FUZZ_CHECK(baud == LMS_BAUD_9600 || baud == LMS_BAUD_19200 || baud == LMS_BAUD_38400 ||
               baud == LMS_BAUD_500000);
    R.host_baud = baud;
}

/* Scan k of the simulated scanner's stream: a flat wall, in the variant
 * and unit asked for. */
static bool sim_scan(void *ctx, uint32_t k, uint16_t angle_deg, uint16_t resolution_cdeg,
                     bool partial, lms_unit_t unit, uint8_t reply_address, uint8_t *out,
                     size_t cap, size_t *len, uint32_t *gap_us)
{
    static lms_scan_t scan;
    (void)ctx;
    memset(&scan, 0, sizeof scan);
    const uint16_t steps = (uint16_t)(angle_deg * 100u / (partial ? 100u : resolution_cdeg));
    scan.count = (uint16_t)(steps + 1u);
    scan.unit = unit;
    scan.address = reply_address;
    scan.status = 0x10u;
    scan.is_partial = partial;
    scan.partial_index = (uint8_t)(k % 4u);
    for (uint16_t i = 0u; i < scan.count && i < LMS_SCAN_MAX_VALUES; i++) {
        scan.values[i] = (uint16_t)(300u + (i + k) % 50u);
    }
    *gap_us = 0u;
    return lms_encode_scan(out, cap, reply_address, &scan, len) == LMS_OK;
}

static void check_counters(void)
{
    const lms_session_t *s = &R.s;
    FUZZ_CHECK((unsigned)lms_session_state(s) < (unsigned)LMS_SESSION_STATE_COUNT);
    FUZZ_CHECK(lms_session_state_name(lms_session_state(s)) != NULL);
    FUZZ_CHECK(lms_session_error_name(lms_session_error(s)) != NULL);
    const lms_session_stats_t *st = lms_session_stats(s);
    FUZZ_CHECK(st->restarts == st->restarts_silence + st->restarts_power_on + st->restarts_link);
    FUZZ_CHECK(st->retries <= st->commands);
    FUZZ_CHECK(st->scans == R.scan_events);
    /* A restart is counted when decided and reported at the next call. */
    FUZZ_CHECK(R.restart_events <= st->restarts && st->restarts <= R.restart_events + 1u);
    const lms_framer_stats_t *f = lms_session_framer_stats(s);
    FUZZ_CHECK(f->bytes_in == f->telegram_bytes + f->acks + f->naks + f->bytes_skipped +
                                  (uint32_t)lms_framer_pending(&s->framer));
    FUZZ_CHECK(lms_session_wait_us(s, session_now()) <= 0x80000000u);
    (void)lms_session_scan_interval_us(s);
    FUZZ_CHECK(lms_session_info(s) != NULL);
}

static void on_event(lms_session_event_t ev)
{
    size_t len = 1u;
    const uint8_t *t = lms_session_telegram(&R.s, &len);
    switch (ev) {
    case LMS_SESSION_EV_SCAN: {
        lms_telegram_t tel;
        R.scan_events++;
        FUZZ_CHECK(lms_session_state(&R.s) == LMS_SESSION_STREAMING);
        FUZZ_CHECK(t != NULL && len >= LMS_OVERHEAD + 1u && len <= LMS_TELEGRAM_MAX);
        FUZZ_CHECK(lms_telegram_parse(t, len, &tel) == LMS_OK);
        FUZZ_CHECK(t[4] == 0xB0u);
        return;
    }
    case LMS_SESSION_EV_RESTART:
        R.restart_events++;
        break;
    case LMS_SESSION_EV_FAILED:
        FUZZ_CHECK(lms_session_state(&R.s) == LMS_SESSION_FAILED);
        FUZZ_CHECK(lms_session_error(&R.s) != LMS_SESSION_ERR_NONE);
        break;
    case LMS_SESSION_EV_STOPPED:
        FUZZ_CHECK(lms_session_state(&R.s) == LMS_SESSION_STOPPED);
        break;
    case LMS_SESSION_EV_STREAMING:
        FUZZ_CHECK(lms_session_stats(&R.s)->bring_ups > 0u);
        break;
    default:
        FUZZ_CHECK(false);
    }
    FUZZ_CHECK(t == NULL);
}

static void poll_all(void)
{
    for (unsigned guard = 0u; guard < 64u; guard++) {
        const lms_session_event_t ev = lms_session_poll(&R.s, session_now());
        if (ev != LMS_SESSION_EV_NONE) {
            on_event(ev);
        }
        check_counters();
        if (ev == LMS_SESSION_EV_NONE) {
            return;
        }
    }
    FUZZ_CHECK(false); /* poll never settles */
}

static void feed_all(const uint8_t *bytes, size_t n)
{
    size_t off = 0u;
    /* Each event consumes at least one byte or reports one pending event. */
    for (size_t guard = 0u; guard <= 2u * n + 8u; guard++) {
        size_t used = 0u;
        const lms_session_event_t ev =
            lms_session_feed(&R.s, bytes + off, n - off, &used, session_now());
        FUZZ_CHECK(used <= n - off);
        off += used;
        if (ev != LMS_SESSION_EV_NONE) {
            on_event(ev);
        }
        check_counters();
        if (ev == LMS_SESSION_EV_NONE) {
            FUZZ_CHECK(off == n);
            poll_all();
            return;
        }
    }
    FUZZ_CHECK(false); /* feed never finishes */
}

/* One step of the line: the clock to the next thing due (at most
 * MAX_STEP_US), the simulator's bytes in, the timers run. */
static void line_step(void)
{
    static uint8_t buf[LMS_SIM_OUT_SIZE];
    uint64_t step = lms_session_wait_us(&R.s, session_now());
    if (R.with_sim) {
        const uint64_t next = lms_sim_next_event_us(&R.sim, R.line_us);
        if (next != UINT64_MAX && next - R.line_us < step) {
            step = (next > R.line_us) ? next - R.line_us : 1u;
        }
    }
    step = (step == 0u) ? 1u : (step > MAX_STEP_US ? MAX_STEP_US : step);
    R.line_us += step;
    size_t n = 0u;
    if (R.with_sim) {
        n = lms_sim_transmit(&R.sim, R.host_baud, R.line_us, buf, sizeof buf);
        FUZZ_CHECK(n <= sizeof buf);
        if (lms_sim_take_hangup(&R.sim)) {
            lms_session_link_lost(&R.s, session_now());
            check_counters();
        }
    }
    feed_all(buf, n);
    R.steps++;
}

static void setup(uint8_t a, uint8_t b)
{
    static const lms_baud_t rates[4] = {LMS_BAUD_9600, LMS_BAUD_19200, LMS_BAUD_38400,
                                        LMS_BAUD_500000};
    static const uint16_t angle[4] = {0u, 180u, 180u, 100u};
    static const uint16_t res[4] = {100u, 100u, 50u, 25u};
    memset(&R, 0, sizeof R);
    R.line_us = 1000u;
    R.host_baud = LMS_BAUD_9600;
    lms_session_config_t c;
    lms_session_defaults(&c);
    c.baud = rates[a & 3u];
    c.angle_deg = angle[(a >> 2) & 3u];
    c.resolution_cdeg = res[(a >> 2) & 3u];
    c.partial = ((a >> 4) & 1u) != 0u && c.resolution_cdeg != 25u;
    c.unit = ((a >> 5) & 1u) ? (uint8_t)LMS_UNIT_MM : LMS_SESSION_KEEP;
    c.power_wait_us = ((a >> 6) & 1u) ? 300000u : 0u;
    c.restore_9600 = ((a >> 7) & 1u) == 0u;
    FUZZ_CHECK(lms_session_check_config(&c) == LMS_OK);

    R.with_sim = (b & 1u) != 0u;
    if (R.with_sim) {
        lms_sim_config_t sc;
        lms_sim_defaults(&sc);
        sc.power_on_baud = rates[(b >> 1) & 3u];
        sc.unit = ((b >> 3) & 1u) ? LMS_UNIT_MM : LMS_UNIT_CM;
        if ((b >> 4) & 1u) {
            sc.fixed_angle_deg = 100u;
            sc.fixed_resolution_cdeg = 100u;
        }
        const unsigned faults = (b >> 5) & 7u;
        sc.faults.drop_ppm = (faults & 1u) ? 2000u : 0u;
        sc.faults.flip_ppm = (faults & 2u) ? 2000u : 0u;
        sc.faults.nak_percent = (faults & 4u) ? 20u : 0u;
        sc.faults.seed = b;
        sc.power_on_delay_us = 50000u;
        sc.speed_permille = 4000u; /* four times real time: more per step */
        sc.scan_source = sim_scan;
        lms_sim_init(&R.sim, &sc, R.line_us);
    }
    const lms_session_io_t io = {io_write, io_set_baud, NULL};
    FUZZ_CHECK(lms_session_init(&R.s, &c, &io, session_now()) == LMS_OK);
    check_counters();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static uint8_t buf[LMS_TELEGRAM_MAX];
    static const uint8_t singles[4] = {0x06u, 0x15u, 0x02u, 0x80u};
    if (size < 2u) {
        return 0;
    }
    fuzz_input_t in = {data, size, 2u};
    setup(data[0], data[1]);
    while (in.pos < in.size && R.steps < MAX_STEPS) {
        const uint8_t op = next_byte(&in);
        switch (op & 7u) {
        case 0u: {
            const size_t n = 1u + next_byte(&in) % 64u;
            const size_t avail = (in.size - in.pos < n) ? in.size - in.pos : n;
            feed_all(&in.data[in.pos], avail);
            in.pos += avail;
            break;
        }
        case 1u: {
            uint8_t payload[40];
            const size_t n = 1u + next_byte(&in) % 40u;
            for (size_t k = 0u; k < n; k++) {
                payload[k] = next_byte(&in);
            }
            size_t len = 0u;
            FUZZ_CHECK(lms_telegram_write(buf, sizeof buf, 0x80u, payload, n, -1, &len) ==
                       LMS_OK);
            feed_all(buf, len);
            break;
        }
        case 2u: {
            const unsigned n = 1u + next_byte(&in) % 64u;
            for (unsigned k = 0u; k < n && R.steps < MAX_STEPS; k++) {
                line_step();
            }
            break;
        }
        case 3u: {
            uint32_t jump = 0u;
            for (unsigned k = 0u; k < 4u; k++) {
                jump |= (uint32_t)next_byte(&in) << (8u * k);
            }
            R.skew_us += jump;
            poll_all();
            break;
        }
        case 4u: {
            const uint32_t lo = next_byte(&in);
            const uint32_t hi = next_byte(&in);
            R.line_us += 16u * (lo | (hi << 8));
            poll_all();
            break;
        }
        case 5u:
            lms_session_link_lost(&R.s, session_now());
            check_counters();
            poll_all();
            break;
        case 6u:
            lms_session_stop(&R.s, session_now());
            check_counters();
            poll_all();
            break;
        default:
            feed_all(&singles[next_byte(&in) % 4u], 1u);
            break;
        }
    }
    return 0;
}
