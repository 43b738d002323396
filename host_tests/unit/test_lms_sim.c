/* test_lms_sim.c - the simulated LMS 2xx (driver/sim/lms_sim.h) seen from
 * the host's side of the line: every byte it hands out goes through a
 * LMS_FROM_SCANNER framer and the existing decoders, on a simulated clock
 * that jumps from one lms_sim_next_event_us to the next. Covers power-up
 * timing, every command, baud switching and garbling, streaming rates and
 * skipping, the faults, the fault-specification parser and hostile input.
 */
#include <string.h>

#include "lms_decode.h"
#include "lms_encode.h"
#include "lms_framer.h"
#include "lms_sim.h"
#include "lms_test_util.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* --- the host's end of the line ------------------------------------------ */

#define T0_US 1000000ull
#define MS 1000ull
#define LOG_MAX 8192u
#define TEL_SLOTS 64u
#define B0_TIMES 256u
#define BYTE_TIMES 8192u

typedef struct {
    lms_framer_event_t ev;
    uint8_t code;
    uint16_t len;
    uint64_t t_us;
    uint32_t tel_no; /* bytes kept while among the last TEL_SLOTS telegrams */
} log_ev_t;

/* A scan source that encodes its arguments into the values, so what the
 * host decodes says what the simulator asked for. */
typedef struct {
    uint32_t limit; /* 0: endless; else scans 0..limit-1 */
    uint32_t calls;
    uint32_t gap_us;
} src_t;

typedef struct {
    lms_sim_t sim;
    lms_sim_config_t cfg;
    src_t src;
    lms_framer_t fr;
    uint64_t now;
    lms_baud_t baud; /* the host's side of the line */
    log_ev_t log[LOG_MAX];
    uint32_t n_log;
    uint32_t n_tel;
    /* Every B0 decoded on arrival. */
    uint32_t b0;
    uint32_t b0_bad;
    uint32_t b0_last_k;
    uint32_t k_backwards;
    uint32_t k_jumps;
    uint64_t b0_t[B0_TIMES];
    uint32_t b0_k[B0_TIMES];
    /* Every byte. */
    uint32_t bytes;
    uint32_t hash;
    uint64_t last_byte_t;
    uint64_t max_gap_us;
    uint64_t byte_t[BYTE_TIMES];
} host_t;

static host_t g;
static uint8_t g_tel[TEL_SLOTS][LMS_TELEGRAM_MAX];
static lms_scan_t g_scan;

static bool test_source(void *ctx, uint32_t k, uint16_t angle_deg, uint16_t resolution_cdeg,
                        bool partial, lms_unit_t unit, uint8_t reply_address, uint8_t *out,
                        size_t cap, size_t *len, uint32_t *gap_us)
{
    src_t *src = (src_t *)ctx;
    static lms_scan_t scan;
    src->calls++;
    if (src->limit != 0u && k >= src->limit) {
        return false;
    }
    memset(&scan, 0, sizeof scan);
    const uint16_t steps =
        (uint16_t)(partial ? angle_deg : (unsigned)angle_deg * 100u / resolution_cdeg);
    scan.count = (uint16_t)(steps + 1u);
    scan.unit = unit;
    scan.is_partial = partial;
    scan.partial_index = partial ? (uint8_t)(k % 4u) : 0u;
    scan.status = 0x10u;
    for (uint16_t i = 0u; i < scan.count; i++) {
        scan.values[i] = (uint16_t)(1000u + i);
    }
    scan.values[0] = (uint16_t)(k & 0xFFFFu);
    scan.values[1] = (uint16_t)(k >> 16);
    scan.values[2] = angle_deg;
    scan.values[3] = resolution_cdeg;
    if (lms_encode_scan(out, cap, reply_address, &scan, len) != LMS_OK) {
        return false;
    }
    *gap_us = src->gap_us;
    return true;
}

static void on_event(lms_framer_event_t ev)
{
    log_ev_t e;
    memset(&e, 0, sizeof e);
    e.ev = ev;
    e.t_us = g.now;
    if (ev == LMS_FRAMER_TELEGRAM) {
        size_t len = 0u;
        const uint8_t *t = lms_framer_telegram(&g.fr, &len);
        TEST_ASSERT_NOT_NULL(t);
        e.code = t[4];
        e.len = (uint16_t)len;
        e.tel_no = g.n_tel;
        memcpy(g_tel[g.n_tel % TEL_SLOTS], t, len);
        g.n_tel++;
        if (e.code == LMS_REPLY_VALUES) {
            if (lms_decode_scan(t, len, &g_scan) != LMS_OK || g_scan.count < 4u) {
                g.b0_bad++;
            } else {
                const uint32_t k = g_scan.values[0] | ((uint32_t)g_scan.values[1] << 16);
                if (g.b0 > 0u && k <= g.b0_last_k) {
                    g.k_backwards++;
                }
                if (g.b0 > 0u && k > g.b0_last_k + 1u) {
                    g.k_jumps++;
                }
                if (g.b0 < B0_TIMES) {
                    g.b0_t[g.b0] = g.now;
                    g.b0_k[g.b0] = k;
                }
                g.b0_last_k = k;
                g.b0++;
            }
        }
    }
    if (g.n_log < LOG_MAX) {
        g.log[g.n_log++] = e;
    }
}

/* One lms_sim_transmit at g.now; frames what it handed out. */
static size_t take_once(void)
{
    static uint8_t buf[4096];
    const size_t n = lms_sim_transmit(&g.sim, g.baud, g.now, buf, sizeof buf);
    for (size_t i = 0u; i < n; i++) {
        g.hash = (g.hash ^ buf[i]) * 16777619u; /* FNV-1a */
        if (g.bytes > 0u && g.now - g.last_byte_t > g.max_gap_us) {
            g.max_gap_us = g.now - g.last_byte_t;
        }
        if (g.bytes < BYTE_TIMES) {
            g.byte_t[g.bytes] = g.now;
        }
        g.last_byte_t = g.now;
        g.bytes++;
    }
    size_t off = 0u;
    for (int guard = 0; guard < 100000; guard++) {
        size_t used = 0u;
        const lms_framer_event_t ev = lms_framer_feed(&g.fr, &buf[off], n - off, &used);
        off += used;
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        on_event(ev);
    }
    TEST_ASSERT_EQUAL_UINT(n, off);
    return n;
}

/* Takes everything the scanner has handed out by g.now. */
static void drain(void)
{
    for (int round = 0; round < 64; round++) {
        if (take_once() == 0u) {
            return;
        }
    }
}

/* Runs the line until t_end, waking exactly when the simulator asks to. */
static void pump_until(uint64_t t_end)
{
    for (uint32_t guard = 0u; guard < 20000000u; guard++) {
        drain();
        const uint64_t next = lms_sim_next_event_us(&g.sim, g.now);
        if (next > t_end) {
            g.now = t_end;
            drain();
            return;
        }
        if (next > g.now) {
            g.now = next;
        }
    }
    TEST_FAIL_MESSAGE("pump did not reach its end time");
}

static void pump_for(uint64_t dt_us)
{
    pump_until(g.now + dt_us);
}

static void host_init(const lms_sim_config_t *cfg)
{
    memset(&g, 0, sizeof g);
    g.hash = 2166136261u;
    g.cfg = *cfg;
    lms_framer_init(&g.fr, LMS_FROM_SCANNER);
    g.now = T0_US;
    g.baud = cfg->power_on_baud;
    lms_sim_init(&g.sim, &g.cfg, g.now);
}

static void config_with_source(lms_sim_config_t *cfg)
{
    lms_sim_defaults(cfg);
    cfg->scan_source = test_source;
    cfg->scan_ctx = &g.src;
}

/* Powers up and waits for the 90; the log starts empty afterwards. */
static void boot(const lms_sim_config_t *cfg)
{
    host_init(cfg);
    pump_for((uint64_t)cfg->power_on_delay_us * 1000u / cfg->speed_permille + 50u * MS);
    TEST_ASSERT_EQUAL_UINT32(1u, g.n_log);
    TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_POWER_ON, g.log[0].code);
    g.n_log = 0u;
}

static void send_raw(const uint8_t *bytes, size_t len)
{
    lms_sim_receive(&g.sim, bytes, len, g.baud, g.now);
}

static void send(const lms_cmd_t *c)
{
    send_raw(c->bytes, c->len);
}

static const uint8_t *tel(const log_ev_t *e, size_t *len)
{
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, e->ev);
    TEST_ASSERT_TRUE_MESSAGE(g.n_tel - e->tel_no <= TEL_SLOTS, "telegram no longer kept");
    *len = e->len;
    return g_tel[e->tel_no % TEL_SLOTS];
}

/* Sends a command and expects exactly an ACK, then one reply telegram with
 * the given code, within wait_us; returns the reply. */
static const uint8_t *request(const lms_cmd_t *c, uint64_t wait_us, uint8_t code, size_t *len)
{
    const uint32_t from = g.n_log;
    send(c);
    pump_for(wait_us);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(from + 2u, g.n_log, "ACK and one reply");
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, g.log[from].ev);
    TEST_ASSERT_EQUAL_HEX8(code, g.log[from + 1u].code);
    return tel(&g.log[from + 1u], len);
}

/* The first telegram with this code at or after log index from, or NULL. */
static const log_ev_t *find_code(uint32_t from, uint8_t code)
{
    for (uint32_t i = from; i < g.n_log; i++) {
        if (g.log[i].ev == LMS_FRAMER_TELEGRAM && g.log[i].code == code) {
            return &g.log[i];
        }
    }
    return NULL;
}

static uint32_t count_ev(uint32_t from, lms_framer_event_t ev)
{
    uint32_t n = 0u;
    for (uint32_t i = from; i < g.n_log; i++) {
        n += g.log[i].ev == ev ? 1u : 0u;
    }
    return n;
}

static lms_device_status_t status_now(void)
{
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    size_t len = 0u;
    const uint8_t *t = request(&c, 300u * MS, LMS_REPLY_STATUS, &len);
    lms_device_status_t st;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_status(t, len, &st));
    return st;
}

static uint8_t mode_result(const uint8_t *t, size_t len)
{
    lms_mode_reply_t r;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_mode_reply(t, len, &r));
    TEST_ASSERT_EQUAL_HEX8(0x10u, r.status);
    return (uint8_t)r.result;
}

static void set_mode(lms_mode_t mode)
{
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_mode(&c, 0u, mode));
    size_t len = 0u;
    const uint8_t *t = request(&c, 50u * MS, LMS_REPLY_MODE, &len);
    TEST_ASSERT_EQUAL_UINT8(LMS_MODE_RESULT_OK, mode_result(t, len));
}

static void enter_installation(void)
{
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_installation(&c, 0u, NULL));
    size_t len = 0u;
    const uint8_t *t = request(&c, 50u * MS, LMS_REPLY_MODE, &len);
    TEST_ASSERT_EQUAL_UINT8(LMS_MODE_RESULT_OK, mode_result(t, len));
}

/* Switches both ends to a new rate the way a driver does: A0 first. */
static void switch_baud(lms_baud_t baud)
{
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_baud(&c, 0u, baud));
    size_t len = 0u;
    const uint8_t *t = request(&c, 50u * MS, LMS_REPLY_MODE, &len);
    TEST_ASSERT_EQUAL_UINT8(LMS_MODE_RESULT_OK, mode_result(t, len));
    TEST_ASSERT_EQUAL_INT(baud, lms_sim_baud(&g.sim));
    g.baud = baud;
}

static void set_variant(uint16_t angle, uint16_t res, bool expect_accepted)
{
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_variant(&c, 0u, angle, res));
    size_t len = 0u;
    const uint8_t *t = request(&c, 50u * MS, LMS_REPLY_VARIANT, &len);
    lms_variant_reply_t v;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_variant_reply(t, len, &v));
    TEST_ASSERT_EQUAL(expect_accepted, v.accepted);
    if (expect_accepted) {
        TEST_ASSERT_EQUAL_UINT16(angle, v.angle_deg);
        TEST_ASSERT_EQUAL_UINT16(res, v.resolution_cdeg);
    }
}

/* Boots with the test source at 500 kbaud. */
static void boot_fast(lms_sim_config_t *cfg)
{
    boot(cfg);
    switch_baud(LMS_BAUD_500000);
}

/* Starts a stream: ACK, A0 00; B0s follow. */
static void start_stream(lms_mode_t mode)
{
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_mode(&c, 0u, mode));
    const uint32_t from = g.n_log;
    send(&c);
    pump_for(20u * MS); /* the A0 is there (9600 too), no scan yet */
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, g.log[from].ev);
    TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_MODE, g.log[from + 1u].code);
}

/* 20 25 while streaming: the A0 comes after the scan on the wire. */
static void stop_stream(uint64_t wait_us)
{
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_mode(&c, 0u, LMS_MODE_ON_REQUEST));
    const uint32_t from = g.n_log;
    send(&c);
    pump_for(wait_us);
    const log_ev_t *e = find_code(from, LMS_REPLY_MODE);
    TEST_ASSERT_NOT_NULL(e);
    size_t len = 0u;
    const uint8_t *t = tel(e, &len);
    TEST_ASSERT_EQUAL_UINT8(LMS_MODE_RESULT_OK, mode_result(t, len));
    const uint32_t n = g.b0;
    pump_for(wait_us);
    TEST_ASSERT_EQUAL_UINT32(n, g.b0);
    TEST_ASSERT_TRUE(lms_sim_next_event_us(&g.sim, g.now) == UINT64_MAX);
}

/* Checks that the B0 arrival times after the first few are period_us apart
 * (exact fractions, so each difference is the period rounded either way). */
static void check_period(uint32_t first, uint32_t last, uint64_t period_num, uint64_t period_den)
{
    TEST_ASSERT_TRUE(last < B0_TIMES && last <= g.b0);
    for (uint32_t i = first + 1u; i < last; i++) {
        const uint64_t d = g.b0_t[i] - g.b0_t[i - 1u];
        const uint64_t lo = period_num / period_den;
        TEST_ASSERT_TRUE_MESSAGE(d == lo || d == lo + 1u, "scan period");
        TEST_ASSERT_EQUAL_UINT32(g.b0_k[i - 1u] + 1u, g.b0_k[i]);
    }
}

/* --- 1. power-up ---------------------------------------------------------- */

static void test_lms_sim_power_up_sends_90_after_the_delay_at_the_line_rate(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    host_init(&cfg);
    const uint64_t on = T0_US + cfg.power_on_delay_us;
    TEST_ASSERT_TRUE(lms_sim_next_event_us(&g.sim, g.now) == on);
    g.now = on - 1u;
    drain();
    TEST_ASSERT_EQUAL_UINT32(0u, g.bytes);
    /* Byte i is complete at on + i * 10 / 9600 s, rounded up to whole us. */
    for (uint32_t i = 1u; i <= 29u; i++) {
        const uint64_t due = on + ((uint64_t)i * 10000000u + 9599u) / 9600u;
        g.now = due - 1u;
        drain();
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(i - 1u, g.bytes, "too early");
        g.now = due;
        drain();
        TEST_ASSERT_EQUAL_UINT32_MESSAGE(i, g.bytes, "too late");
    }
    TEST_ASSERT_EQUAL_UINT32(1u, g.n_log);
    size_t len = 0u;
    const uint8_t *t = tel(&g.log[0], &len);
    TEST_ASSERT_EQUAL_UINT(29u, len);
    lms_ident_t id;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_power_on(t, len, &id));
    TEST_ASSERT_EQUAL_STRING("LMS200;30106x;V02.10 ", id.text);
    TEST_ASSERT_EQUAL_HEX8(0x80u, id.address);
    TEST_ASSERT_EQUAL_HEX8(0x10u, id.status);
    TEST_ASSERT_TRUE(lms_sim_next_event_us(&g.sim, g.now) == UINT64_MAX);
    pump_for(10000u * MS);
    TEST_ASSERT_EQUAL_UINT32(29u, g.bytes);
}

/* Host bytes during the power-on delay are ignored, and a permanent rate
 * brings the 90 up at that rate. */
static void test_lms_sim_power_up_ignores_host_and_honours_power_on_baud(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    cfg.power_on_baud = LMS_BAUD_38400;
    cfg.power_on_delay_us = 2000000u;
    host_init(&cfg);
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    g.now += 500u * MS;
    send(&c);
    TEST_ASSERT_EQUAL_UINT32(c.len, lms_sim_stats(&g.sim)->host_ignored);
    pump_until(T0_US + 2000u * MS - 1u);
    TEST_ASSERT_EQUAL_UINT32(0u, g.bytes);
    pump_for(20u * MS);
    TEST_ASSERT_EQUAL_UINT32(1u, g.n_log);
    TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_POWER_ON, g.log[0].code);
    /* 29 bytes at 38400: 7.55 ms. */
    TEST_ASSERT_EQUAL_UINT32(T0_US + 2000u * MS + (29u * 10000000u + 38399u) / 38400u,
                             (uint32_t)g.log[0].t_us);
    g.n_log = 0u;
    const lms_device_status_t st = status_now();
    TEST_ASSERT_TRUE(st.baud_known);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_38400, st.baud);
    TEST_ASSERT_TRUE(st.permanent_baud);
}

/* --- 2. commands ---------------------------------------------------------- */

static void test_lms_sim_status_reply_fields(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    const uint64_t sent = g.now;
    size_t len = 0u;
    const uint8_t *t = request(&c, 300u * MS, LMS_REPLY_STATUS, &len);
    TEST_ASSERT_EQUAL_UINT(160u, len);
    /* ACK: one byte time; reply: after the 10 ms delay plus 160 bytes. */
    TEST_ASSERT_EQUAL_UINT32((uint32_t)(sent + 1042u), (uint32_t)g.log[0].t_us);
    TEST_ASSERT_EQUAL_UINT32((uint32_t)(sent + 10u * MS + (160u * 10000000u + 9599u) / 9600u),
                             (uint32_t)g.log[1].t_us);
    lms_device_status_t st;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_status(t, len, &st));
    TEST_ASSERT_EQUAL_HEX8(0x80u, st.address);
    TEST_ASSERT_EQUAL_HEX8(0x10u, st.status);
    TEST_ASSERT_EQUAL_STRING("V02.10 ", st.firmware);
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_ON_REQUEST, st.operating_mode);
    TEST_ASSERT_EQUAL_UINT8(0u, st.device_status);
    TEST_ASSERT_EQUAL_HEX8(0x00u, st.meas_mode);
    TEST_ASSERT_EQUAL_UINT16(180u, st.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(50u, st.resolution_cdeg);
    TEST_ASSERT_EQUAL_HEX16(0x8067u, st.baud_word);
    TEST_ASSERT_TRUE(st.baud_known);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, st.baud);
    TEST_ASSERT_FALSE(st.permanent_baud);
    TEST_ASSERT_EQUAL_UINT8(0u, st.scanner_address);
    TEST_ASSERT_EQUAL_UINT8(0u, st.units);
    TEST_ASSERT_TRUE(st.laser_on);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->host_telegrams);
}

static void test_lms_sim_installation_mode_password(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    lms_cmd_t c;
    size_t len = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_installation(&c, 0u, "SICK_XYZ"));
    const uint8_t *t = request(&c, 50u * MS, LMS_REPLY_MODE, &len);
    TEST_ASSERT_EQUAL_UINT8(LMS_MODE_RESULT_BAD_PASSWORD, mode_result(t, len));
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_ON_REQUEST, status_now().operating_mode);
    enter_installation();
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_INSTALLATION, status_now().operating_mode);
    set_mode(LMS_MODE_ON_REQUEST);
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_ON_REQUEST, status_now().operating_mode);

    /* A configured password replaces the default. */
    lms_sim_defaults(&cfg);
    memcpy(cfg.password, "LMS_PASS", 9u);
    boot(&cfg);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_installation(&c, 0u, NULL));
    t = request(&c, 50u * MS, LMS_REPLY_MODE, &len);
    TEST_ASSERT_EQUAL_UINT8(LMS_MODE_RESULT_BAD_PASSWORD, mode_result(t, len));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_installation(&c, 0u, "LMS_PASS"));
    t = request(&c, 50u * MS, LMS_REPLY_MODE, &len);
    TEST_ASSERT_EQUAL_UINT8(LMS_MODE_RESULT_OK, mode_result(t, len));
}

static void test_lms_sim_type_and_errors(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    memcpy(cfg.type_text, "LMS291;S05", 11u); /* short: padded with spaces */
    boot(&cfg);
    lms_cmd_t c;
    size_t len = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_type(&c, 0u));
    const uint8_t *t = request(&c, 50u * MS, LMS_REPLY_TYPE, &len);
    lms_ident_t id;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_type(t, len, &id));
    TEST_ASSERT_EQUAL_STRING("LMS291;S05           ", id.text);
    TEST_ASSERT_EQUAL_HEX8(0x10u, id.status);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_errors(&c, 0u));
    t = request(&c, 50u * MS, LMS_REPLY_ERRORS, &len);
    lms_telegram_t tg;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_parse(t, len, &tg));
    TEST_ASSERT_EQUAL_UINT16(0u, tg.data_len);
    TEST_ASSERT_EQUAL_HEX8(0x10u, tg.status);
}

static void test_lms_sim_variant_accepted_and_refused(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    boot(&cfg);
    set_variant(100u, 25u, true);
    lms_device_status_t st = status_now();
    TEST_ASSERT_EQUAL_UINT16(100u, st.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(25u, st.resolution_cdeg);
    /* 180 / 0.25 is not a variant: refused, 100 / 0.25 stays. */
    lms_cmd_t c;
    size_t len = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_variant(&c, 0u, 100u, 25u));
    c.bytes[5] = 180u; /* hand-built: the encoder refuses the pair */
    tu_fix_crc(c.bytes, c.len);
    const uint8_t *t = request(&c, 50u * MS, LMS_REPLY_VARIANT, &len);
    lms_variant_reply_t v;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_variant_reply(t, len, &v));
    TEST_ASSERT_FALSE(v.accepted);
    TEST_ASSERT_EQUAL_UINT16(100u, v.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(25u, v.resolution_cdeg);
    /* While streaming: 92, variant unchanged. */
    start_stream(LMS_MODE_STREAM_ALL);
    const uint32_t from = g.n_log;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_variant(&c, 0u, 180u, 100u));
    send(&c);
    pump_for(3000u * MS);
    TEST_ASSERT_NOT_NULL(find_code(from, LMS_REPLY_NOT_ACK));
    TEST_ASSERT_NULL(find_code(from, LMS_REPLY_VARIANT));
    TEST_ASSERT_EQUAL_UINT32(0u, g.b0_bad);
    TEST_ASSERT_TRUE(g.b0 > 0u);
    stop_stream(2000u * MS);
    st = status_now();
    TEST_ASSERT_EQUAL_UINT16(100u, st.angle_deg);

    /* A scanner with a fixed variant refuses every other one. */
    lms_sim_defaults(&cfg);
    cfg.fixed_angle_deg = 180u;
    cfg.fixed_resolution_cdeg = 100u;
    boot(&cfg);
    set_variant(100u, 50u, false);
    set_variant(180u, 100u, true);
}

static void test_lms_sim_config_read_and_write(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    lms_cmd_t c;
    size_t len = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_config_read(&c, 0u));
    const uint8_t *t = request(&c, 100u * MS, LMS_REPLY_CONFIG, &len);
    lms_config_reply_t r;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_config(t, len, &r));
    TEST_ASSERT_EQUAL_UINT8(34u, r.config.size);
    TEST_ASSERT_EQUAL_UINT8(0u, lms_config_units(&r.config));
    TEST_ASSERT_EQUAL_UINT8(0u, lms_config_meas_mode(&r.config));
    lms_config_t want = r.config;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_unit(&want, LMS_UNIT_MM));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_meas_mode(&want, LMS_MEAS_16M_REFLECTOR));

    /* Outside installation mode: 92 and nothing written. */
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_config_write(&c, 0u, &want));
    (void)request(&c, 50u * MS, LMS_REPLY_NOT_ACK, &len);
    TEST_ASSERT_EQUAL_UINT8(0u, status_now().units);

    enter_installation();
    const uint32_t from = g.n_log;
    send(&c);
    pump_for(990u * MS); /* the EEPROM write takes 1 s */
    TEST_ASSERT_EQUAL_UINT32(from + 1u, g.n_log);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, g.log[from].ev);
    pump_for(100u * MS);
    TEST_ASSERT_EQUAL_UINT32(from + 2u, g.n_log);
    t = tel(&g.log[from + 1u], &len);
    lms_config_write_reply_t w;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_config_write_reply(t, len, &w));
    TEST_ASSERT_TRUE(w.accepted);
    TEST_ASSERT_EQUAL_MEMORY(want.block, w.config.block, 34u);

    const lms_device_status_t st = status_now();
    TEST_ASSERT_EQUAL_UINT8(1u, st.units);
    TEST_ASSERT_EQUAL_HEX8(LMS_MEAS_16M_REFLECTOR, st.meas_mode);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_config_read(&c, 0u));
    t = request(&c, 100u * MS, LMS_REPLY_CONFIG, &len);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_config(t, len, &r));
    TEST_ASSERT_EQUAL_MEMORY(want.block, r.config.block, 34u);

    /* Reserved units: F7 00, nothing changes. */
    lms_config_t bad = want;
    bad.block[LMS_CONFIG_OFF_UNITS] = 2u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_config_write(&c, 0u, &bad));
    t = request(&c, 1100u * MS, LMS_REPLY_CONFIG_WRITE, &len);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_config_write_reply(t, len, &w));
    TEST_ASSERT_FALSE(w.accepted);
    TEST_ASSERT_EQUAL_UINT8(1u, status_now().units);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->config_writes);
}

static void test_lms_sim_reset_reboots_at_power_on_rate(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    cfg.unit = LMS_UNIT_MM;
    boot(&cfg);
    set_variant(100u, 25u, true);
    switch_baud(LMS_BAUD_38400);
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_reset(&c, 0u));
    size_t len = 0u;
    const uint8_t *t = request(&c, 20u * MS, LMS_REPLY_RESET_ACK, &len);
    lms_bare_reply_t b;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_reset_ack(t, len, &b));
    TEST_ASSERT_EQUAL_HEX8(0x10u, b.status);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&g.sim));
    const uint64_t reset_at = g.log[g.n_log - 1u].t_us;
    g.baud = LMS_BAUD_9600;
    const uint32_t from = g.n_log;
    pump_until(reset_at + 99u * MS);
    TEST_ASSERT_EQUAL_UINT32(from, g.n_log);
    pump_for(50u * MS);
    TEST_ASSERT_EQUAL_UINT32(from + 1u, g.n_log);
    TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_POWER_ON, g.log[from].code);
    const lms_device_status_t st = status_now();
    TEST_ASSERT_EQUAL_UINT16(180u, st.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(50u, st.resolution_cdeg);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, st.baud);
    TEST_ASSERT_EQUAL_UINT8(1u, st.units); /* the EEPROM survives */
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->power_cycles);
}

static void test_lms_sim_refuses_permanent_baud_and_unknown_commands(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    /* 66 01: 92, the rate stays. */
    const uint8_t p66[2] = {LMS_CMD_PERMANENT_BAUD, 0x01u};
    lms_cmd_t c;
    size_t written = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(c.bytes, sizeof c.bytes, 0u, p66, 2u, -1,
                                                     &written));
    c.len = (uint8_t)written;
    size_t len = 0u;
    const uint8_t *t = request(&c, 50u * MS, LMS_REPLY_NOT_ACK, &len);
    lms_bare_reply_t b;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_not_ack(t, len, &b));
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&g.sim));
    TEST_ASSERT_FALSE(status_now().permanent_baud);
    /* Unknown code, unknown mode, 30 with another sub-mode, 30 01 with no
     * source, 24 with a parameter. */
    static const uint8_t payloads[][3] = {
        {0x55u, 0x00u, 0x00u}, {LMS_CMD_MODE, 0x26u, 0u}, {LMS_CMD_REQUEST_VALUES, 0x02u, 0u},
        {LMS_CMD_REQUEST_VALUES, 0x01u, 0u}, {LMS_CMD_MODE, 0x24u, 0x01u}};
    static const size_t sizes[] = {1u, 2u, 2u, 2u, 3u};
    for (size_t i = 0u; i < sizeof sizes / sizeof sizes[0]; i++) {
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(c.bytes, sizeof c.bytes, 0u, payloads[i],
                                                         sizes[i], -1, &written));
        c.len = (uint8_t)written;
        (void)request(&c, 50u * MS, LMS_REPLY_NOT_ACK, &len);
    }
    TEST_ASSERT_EQUAL_UINT32(6u, lms_sim_stats(&g.sim)->not_acks);
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_ON_REQUEST, status_now().operating_mode);
}

static void test_lms_sim_bad_crc_gets_nak_and_nothing_else(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    c.bytes[c.len - 1u] ^= 0x01u;
    send(&c);
    pump_for(500u * MS);
    TEST_ASSERT_EQUAL_UINT32(1u, g.n_log);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_NAK, g.log[0].ev);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->host_bad);
    TEST_ASSERT_EQUAL_UINT32(0u, lms_sim_stats(&g.sim)->host_telegrams);
    (void)status_now(); /* and the next one is fine */
}

static void test_lms_sim_answers_its_own_address_and_broadcast_only(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    cfg.address = 5u;
    boot(&cfg);
    TEST_ASSERT_EQUAL_HEX8(0x85u, g_tel[0][1]); /* the 90 */
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 7u));
    send(&c);
    pump_for(200u * MS);
    TEST_ASSERT_EQUAL_UINT32(0u, g.n_log);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->other_address);
    size_t len = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 5u));
    const uint8_t *t = request(&c, 200u * MS, LMS_REPLY_STATUS, &len);
    lms_device_status_t st;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_status(t, len, &st));
    TEST_ASSERT_EQUAL_HEX8(0x85u, st.address);
    TEST_ASSERT_EQUAL_UINT8(5u, st.scanner_address);
    st = status_now(); /* broadcast */
    TEST_ASSERT_EQUAL_HEX8(0x85u, st.address);
}

static void test_lms_sim_request_values_in_mode_25_only(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    cfg.unit = LMS_UNIT_MM;
    boot(&cfg);
    lms_cmd_t c;
    size_t len = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_request_values(&c, 0u));
    for (uint32_t k = 0u; k < 2u; k++) {
        const uint8_t *t = request(&c, 1000u * MS, LMS_REPLY_VALUES, &len);
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_scan(t, len, &g_scan));
        TEST_ASSERT_EQUAL_UINT16(361u, g_scan.count);
        TEST_ASSERT_EQUAL_INT(LMS_UNIT_MM, g_scan.unit);
        TEST_ASSERT_FALSE(g_scan.is_partial);
        TEST_ASSERT_EQUAL_UINT16(k, g_scan.values[0]);
    }
    enter_installation();
    (void)request(&c, 50u * MS, LMS_REPLY_NOT_ACK, &len);
}

/* Two commands back to back: both ACKed at once, answered in order, the
 * second one's delay starting when the first reply went out. */
static void test_lms_sim_queues_commands_in_order(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    lms_cmd_t a;
    lms_cmd_t b;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_type(&a, 0u));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_errors(&b, 0u));
    const uint64_t sent = g.now;
    send(&a);
    send(&b);
    pump_for(100u * MS);
    TEST_ASSERT_EQUAL_UINT32(4u, g.n_log);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, g.log[0].ev);
    TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, g.log[1].ev);
    TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_TYPE, g.log[2].code);
    TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_ERRORS, g.log[3].code);
    TEST_ASSERT_TRUE(g.log[2].t_us > sent + 10u * MS);
    TEST_ASSERT_TRUE(g.log[3].t_us > sent + 20u * MS);
}

/* --- 3. baud switching and garbling ---------------------------------------- */

static void test_lms_sim_baud_switch_after_the_a0(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_baud(&c, 0u, LMS_BAUD_500000));
    const uint64_t sent = g.now;
    send(&c);
    /* The A0 (9 bytes at 9600) ends 10 ms + 9.375 ms after the command. */
    const uint64_t a0_end = sent + 10u * MS + (9u * 10000000u + 9599u) / 9600u;
    pump_until(a0_end - 1u);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&g.sim));
    TEST_ASSERT_EQUAL_UINT32(1u, g.n_log);
    pump_until(a0_end);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_500000, lms_sim_baud(&g.sim));
    TEST_ASSERT_EQUAL_UINT32(2u, g.n_log);
    size_t len = 0u;
    const uint8_t *t = tel(&g.log[1], &len);
    TEST_ASSERT_EQUAL_UINT8(LMS_MODE_RESULT_OK, mode_result(t, len));
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->baud_changes);
    g.baud = LMS_BAUD_500000;
    g.n_log = 0u;
    const lms_device_status_t st = status_now();
    TEST_ASSERT_EQUAL_HEX16(0x8001u, st.baud_word);

    /* The host still at 9600: its bytes are garbled and counted. */
    g.baud = LMS_BAUD_9600;
    g.n_log = 0u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    send(&c);
    pump_for(500u * MS);
    TEST_ASSERT_EQUAL_UINT32(c.len, lms_sim_stats(&g.sim)->garbled_bytes);
    TEST_ASSERT_EQUAL_UINT32(0u, g.n_log);
}

/* What a host reads at the wrong rate: noise, scaled by the rate ratio,
 * and never anything valid. */
static void test_lms_sim_output_at_the_wrong_rate_is_noise(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    boot_fast(&cfg);
    start_stream(LMS_MODE_STREAM_ALL);
    g.baud = LMS_BAUD_38400; /* reads at 38400, the scanner streams at 500 k */
    const uint32_t from = g.n_log;
    const uint32_t bytes0 = g.bytes;
    const uint32_t sent0 = lms_sim_stats(&g.sim)->scans_sent;
    pump_for(2000u * MS);
    const uint32_t scans = lms_sim_stats(&g.sim)->scans_sent - sent0;
    TEST_ASSERT_TRUE(scans >= 70u);
    TEST_ASSERT_EQUAL_UINT32(from, g.n_log); /* no telegram, no ACK, no NAK */
    TEST_ASSERT_EQUAL_UINT32(0u, g.fr.stats.crc_errors + g.fr.stats.length_errors);
    /* 732-byte scans at a ratio of 38400 / 500000: about 56 bytes each. */
    const uint32_t got = g.bytes - bytes0;
    const uint32_t expect = (uint32_t)((uint64_t)scans * 732u * 38400u / 500000u);
    TEST_ASSERT_UINT_WITHIN(60u, expect, got);

    /* The other way: a 9600 scanner read at 500 k gives 52 bytes per byte. */
    lms_sim_defaults(&cfg);
    boot(&cfg);
    g.baud = LMS_BAUD_500000;
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_type(&c, 0u));
    lms_sim_receive(&g.sim, c.bytes, c.len, LMS_BAUD_9600, g.now); /* sent right */
    const uint32_t b1 = g.bytes;
    const lms_framer_stats_t fs = g.fr.stats; /* the 90 of the boot */
    pump_for(200u * MS);
    TEST_ASSERT_EQUAL_UINT32(0u, g.n_log);
    TEST_ASSERT_UINT_WITHIN(2u, (1u + 29u) * 500000u / 9600u, g.bytes - b1);
    TEST_ASSERT_EQUAL_UINT32(fs.telegrams + fs.acks + fs.naks,
                             g.fr.stats.telegrams + g.fr.stats.acks + g.fr.stats.naks);
}

/* --- 4. streaming --------------------------------------------------------- */

static void test_lms_sim_stream_500k_half_degree(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    boot_fast(&cfg);
    const uint64_t start = g.now;
    start_stream(LMS_MODE_STREAM_ALL);
    pump_until(start + 1000u * MS);
    /* 37.5 scans per second, the first one a period after the A0. */
    TEST_ASSERT_UINT_WITHIN(1u, 37u, g.b0);
    TEST_ASSERT_EQUAL_UINT32(0u, g.b0_bad);
    TEST_ASSERT_EQUAL_UINT32(0u, g.b0_k[0]);
    check_period(0u, g.b0, 1000000000ull * 2u, 75000u);
    TEST_ASSERT_EQUAL_UINT32(0u, lms_sim_stats(&g.sim)->scans_skipped);
    TEST_ASSERT_EQUAL_UINT32(0u, g.fr.stats.crc_errors + g.fr.stats.length_errors);
    size_t len = 0u;
    const log_ev_t *e = find_code(0u, LMS_REPLY_VALUES);
    TEST_ASSERT_NOT_NULL(e);
    const uint8_t *t = tel(e, &len);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_scan(t, len, &g_scan));
    TEST_ASSERT_EQUAL_UINT(732u, len);
    TEST_ASSERT_EQUAL_UINT16(361u, g_scan.count);
    TEST_ASSERT_EQUAL_UINT16(180u, g_scan.values[2]);
    TEST_ASSERT_EQUAL_UINT16(50u, g_scan.values[3]);
    /* 20 24 again: A0 00, the stream runs on with the next numbers. */
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_mode(&c, 0u, LMS_MODE_STREAM_ALL));
    const uint32_t from = g.n_log;
    const uint32_t n = g.b0;
    send(&c);
    pump_for(200u * MS);
    TEST_ASSERT_NOT_NULL(find_code(from, LMS_REPLY_MODE));
    TEST_ASSERT_TRUE(g.b0 >= n + 6u);
    TEST_ASSERT_EQUAL_UINT32(0u, g.k_backwards);
    TEST_ASSERT_EQUAL_UINT32(0u, g.k_jumps);
    /* 20 25 stops it: nothing after the A0. */
    stop_stream(100u * MS);
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_ON_REQUEST, status_now().operating_mode);
}

static void test_lms_sim_stream_one_degree_and_partial_at_75_hz(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    boot_fast(&cfg);
    set_variant(180u, 100u, true);
    start_stream(LMS_MODE_STREAM_ALL);
    pump_for(1000u * MS);
    TEST_ASSERT_UINT_WITHIN(1u, 75u, g.b0);
    check_period(0u, g.b0, 1000000000ull, 75000u);
    TEST_ASSERT_EQUAL_UINT32(0u, g.b0_bad);

    /* Partial scans at 0.5 deg: 75 Hz too, 181 values, partial flag. */
    boot_fast(&cfg);
    start_stream(LMS_MODE_STREAM_PARTIAL);
    pump_for(1000u * MS);
    TEST_ASSERT_UINT_WITHIN(1u, 75u, g.b0);
    check_period(0u, g.b0, 1000000000ull, 75000u);
    const log_ev_t *e = find_code(g.n_log - 2u, LMS_REPLY_VALUES);
    TEST_ASSERT_NOT_NULL(e);
    size_t len = 0u;
    const uint8_t *t = tel(e, &len);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_scan(t, len, &g_scan));
    TEST_ASSERT_TRUE(g_scan.is_partial);
    TEST_ASSERT_EQUAL_UINT16(181u, g_scan.count);
}

static void test_lms_sim_stream_at_9600_skips_rotations(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    boot(&cfg);
    start_stream(LMS_MODE_STREAM_ALL);
    pump_for(10000u * MS);
    /* 732 bytes take 762.5 ms: about 13 scans in 10 s, never two at once,
     * numbered without gaps (a skipped period does not use up a scan). */
    TEST_ASSERT_UINT_WITHIN(1u, 13u, g.b0);
    TEST_ASSERT_EQUAL_UINT32(0u, g.b0_bad);
    TEST_ASSERT_EQUAL_UINT32(0u, g.k_backwards);
    TEST_ASSERT_EQUAL_UINT32(0u, g.k_jumps);
    TEST_ASSERT_EQUAL_UINT32(g.b0 - 1u, g.b0_last_k);
    TEST_ASSERT_EQUAL_UINT32(0u, g.fr.stats.crc_errors + g.fr.stats.length_errors +
                                     g.fr.stats.bytes_skipped);
    const lms_sim_stats_t *s = lms_sim_stats(&g.sim);
    TEST_ASSERT_TRUE(s->scans_skipped > 300u);
    /* Every scan period (26.67 ms for 10 s) is either sent or skipped; at
     * most one scan is still on the wire. */
    TEST_ASSERT_UINT_WITHIN(2u, 375u, s->scans_sent + s->scans_skipped);
    TEST_ASSERT_TRUE(s->scans_sent == g.b0 || s->scans_sent == g.b0 + 1u);
    for (uint32_t i = 1u; i < g.b0; i++) {
        TEST_ASSERT_TRUE(g.b0_t[i] - g.b0_t[i - 1u] >= 762500u);
    }
}

static void test_lms_sim_stream_source_end_and_gap(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    boot_fast(&cfg);
    g.src.limit = 5u;
    g.src.gap_us = 50000u; /* a recording at 20 Hz */
    start_stream(LMS_MODE_STREAM_ALL);
    pump_for(2000u * MS);
    TEST_ASSERT_EQUAL_UINT32(5u, g.b0);
    for (uint32_t i = 1u; i < 5u; i++) {
        TEST_ASSERT_EQUAL_UINT32(50000u, (uint32_t)(g.b0_t[i] - g.b0_t[i - 1u]));
    }
    TEST_ASSERT_TRUE(lms_sim_next_event_us(&g.sim, g.now) == UINT64_MAX);
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_STREAM_ALL, status_now().operating_mode);
}

static void test_lms_sim_stream_speed_2000_halves_the_period(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    cfg.speed_permille = 2000u;
    boot_fast(&cfg);
    start_stream(LMS_MODE_STREAM_ALL);
    pump_for(1000u * MS);
    TEST_ASSERT_UINT_WITHIN(1u, 75u, g.b0);
    check_period(0u, g.b0, 1000000000ull * 2u, 75000u * 2u);
    TEST_ASSERT_EQUAL_UINT32(0u, g.b0_bad);
    /* A recording's own gaps shrink too: 50 ms -> 25 ms. */
    boot_fast(&cfg);
    g.src.gap_us = 50000u;
    start_stream(LMS_MODE_STREAM_ALL);
    pump_for(500u * MS);
    TEST_ASSERT_UINT_WITHIN(1u, 19u, g.b0);
    for (uint32_t i = 1u; i < g.b0; i++) {
        TEST_ASSERT_EQUAL_UINT32(25000u, (uint32_t)(g.b0_t[i] - g.b0_t[i - 1u]));
    }
}

/* Waking only when lms_sim_next_event_us says so gives the same bytes at
 * the same times as polling every microsecond. */
static void test_lms_sim_next_event_is_exact(void)
{
    static uint64_t times[2][BYTE_TIMES];
    uint32_t counts[2];
    uint32_t hashes[2];
    for (int run = 0; run < 2; run++) {
        lms_sim_config_t cfg;
        config_with_source(&cfg);
        cfg.speed_permille = 1700u; /* odd fractions everywhere */
        cfg.power_on_baud = LMS_BAUD_19200;
        boot(&cfg);
        lms_cmd_t c;
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_mode(&c, 0u, LMS_MODE_STREAM_PARTIAL));
        send(&c);
        const uint32_t b0 = g.bytes;
        if (run == 0) {
            pump_for(2000u * MS);
        } else {
            const uint64_t end = g.now + 2000u * MS;
            while (g.now < end) {
                g.now++;
                drain();
            }
        }
        counts[run] = g.bytes - b0;
        hashes[run] = g.hash;
        TEST_ASSERT_TRUE(g.bytes <= BYTE_TIMES);
        memcpy(times[run], &g.byte_t[b0], sizeof(uint64_t) * counts[run]);
    }
    TEST_ASSERT_TRUE(counts[0] > 4000u);
    TEST_ASSERT_EQUAL_UINT32(counts[0], counts[1]);
    TEST_ASSERT_EQUAL_HEX32(hashes[0], hashes[1]);
    TEST_ASSERT_EQUAL_MEMORY(times[0], times[1], sizeof(uint64_t) * counts[0]);
}

/* Nobody reads for a long time: the queue fills and stays consistent; the
 * backlog then comes out as whole telegrams. */
static void test_lms_sim_queue_never_overflows(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    boot_fast(&cfg);
    start_stream(LMS_MODE_STREAM_ALL);
    const uint32_t n0 = g.b0;
    /* Advance without reading (cap 0), then ask for a status. */
    for (uint32_t i = 0u; i < 200u; i++) {
        g.now += 10u * MS;
        TEST_ASSERT_EQUAL_UINT(0u, lms_sim_transmit(&g.sim, g.baud, g.now, NULL, 0u));
    }
    /* Two unread scans (1464 bytes) leave 584: four ACKs and three B1s
     * fit, the fourth B1 does not. */
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    for (int i = 0; i < 4; i++) {
        send(&c);
    }
    g.now += 1000u * MS;
    TEST_ASSERT_EQUAL_UINT(0u, lms_sim_transmit(&g.sim, g.baud, g.now, NULL, 0u));
    TEST_ASSERT_TRUE(lms_sim_next_event_us(&g.sim, g.now) == g.now);
    const lms_sim_stats_t *s = lms_sim_stats(&g.sim);
    TEST_ASSERT_TRUE(s->scans_skipped > 100u);
    TEST_ASSERT_EQUAL_UINT32(1u, s->replies_dropped);
    const uint32_t from = g.n_log;
    pump_for(100u * MS);
    TEST_ASSERT_EQUAL_UINT32(0u, g.fr.stats.crc_errors + g.fr.stats.length_errors +
                                     g.fr.stats.bytes_skipped);
    /* In order: the two old scans, the ACKs, the B1s, then new scans. */
    TEST_ASSERT_TRUE(g.n_log >= from + 10u);
    for (uint32_t i = 0u; i < 10u; i++) {
        const log_ev_t *e = &g.log[from + i];
        if (i < 2u || i == 9u) {
            TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_VALUES, e->code);
        } else if (i < 6u) {
            TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, e->ev);
        } else {
            TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_STATUS, e->code);
        }
    }
    TEST_ASSERT_TRUE(g.b0 >= n0 + 4u); /* and the stream goes on */
    TEST_ASSERT_EQUAL_UINT32(0u, g.b0_bad);
}

/* Ten hours without a call: no call does more than LMS_SIM_MAX_STEPS
 * events; lms_sim_next_event_us says "now" until the backlog is done, and
 * the stream then runs on as before. */
static void test_lms_sim_huge_time_jump_is_bounded(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    boot_fast(&cfg);
    start_stream(LMS_MODE_STREAM_ALL);
    pump_for(100u * MS);
    g.now += 36000ull * 1000000ull;
    uint32_t calls = 0u;
    do {
        (void)take_once();
        calls++;
    } while (lms_sim_next_event_us(&g.sim, g.now) <= g.now && calls < 1000u);
    TEST_ASSERT_TRUE(calls > 2u);    /* 1.35 million scan periods: several calls */
    TEST_ASSERT_TRUE(calls < 100u);
    TEST_ASSERT_TRUE(lms_sim_stats(&g.sim)->scans_skipped > 1300000u);
    const uint32_t n = g.b0;
    pump_for(500u * MS);
    TEST_ASSERT_UINT_WITHIN(1u, n + 18u, g.b0);
    TEST_ASSERT_EQUAL_UINT32(0u, g.b0_bad + g.k_jumps + g.k_backwards);
    TEST_ASSERT_EQUAL_UINT32(0u, g.fr.stats.crc_errors + g.fr.stats.length_errors);
}

/* --- 5. faults ------------------------------------------------------------ */

static void run_faulty_stream(uint32_t seed)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    cfg.power_on_baud = LMS_BAUD_500000; /* no handshake to lose */
    cfg.faults.seed = seed;
    cfg.faults.drop_ppm = 300u;
    cfg.faults.flip_ppm = 300u;
    cfg.faults.insert_ppm = 300u;
    host_init(&cfg);
    pump_for(150u * MS);
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_mode(&c, 0u, LMS_MODE_STREAM_ALL));
    send(&c); /* the host's bytes are never faulted */
    pump_for(3000u * MS);
}

static void test_lms_sim_faults_are_reproducible_and_survivable(void)
{
    run_faulty_stream(42u);
    const uint32_t hash = g.hash;
    const uint32_t bytes = g.bytes;
    const lms_sim_stats_t s1 = *lms_sim_stats(&g.sim);
    TEST_ASSERT_TRUE(s1.bytes_dropped > 0u);
    TEST_ASSERT_TRUE(s1.bytes_flipped > 0u);
    TEST_ASSERT_TRUE(s1.bytes_inserted > 0u);
    TEST_ASSERT_TRUE(g.fr.stats.crc_errors + g.fr.stats.length_errors > 0u);
    TEST_ASSERT_TRUE(g.b0 > 40u);                   /* most scans still decode */
    TEST_ASSERT_TRUE(g.b0_t[g.b0 - 1u] > g.now - 200u * MS); /* up to the end */
    TEST_ASSERT_EQUAL_UINT32(0u, g.k_backwards);
    /* Bytes out = sent - dropped + inserted, every byte of every scan. */
    TEST_ASSERT_EQUAL_UINT32(bytes, s1.bytes_out);

    run_faulty_stream(42u);
    TEST_ASSERT_EQUAL_HEX32(hash, g.hash);
    TEST_ASSERT_EQUAL_UINT32(bytes, g.bytes);
    TEST_ASSERT_EQUAL_MEMORY(&s1, lms_sim_stats(&g.sim), sizeof s1);

    run_faulty_stream(43u);
    TEST_ASSERT_TRUE(hash != g.hash);
}

static void test_lms_sim_nak_percent_100_naks_everything(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    cfg.faults.nak_percent = 100u;
    boot(&cfg);
    lms_cmd_t c[3];
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c[0], 0u));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_type(&c[1], 0u));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_mode(&c[2], 0u, LMS_MODE_BAUD_38400));
    for (int i = 0; i < 3; i++) {
        send(&c[i]);
        pump_for(100u * MS);
    }
    TEST_ASSERT_EQUAL_UINT32(3u, g.n_log);
    TEST_ASSERT_EQUAL_UINT32(3u, count_ev(0u, LMS_FRAMER_NAK));
    TEST_ASSERT_EQUAL_UINT32(3u, lms_sim_stats(&g.sim)->naks_injected);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&g.sim));
}

static void test_lms_sim_silence_fault(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    cfg.faults.silence_after_scans = 3u;
    cfg.faults.silence_us = 200000u;
    boot_fast(&cfg);
    const uint64_t t = g.now;
    start_stream(LMS_MODE_STREAM_ALL);
    g.max_gap_us = 0u;
    pump_until(t + 170u * MS); /* scans end at 51.3, 78.0, 104.6 ms */
    TEST_ASSERT_EQUAL_UINT32(3u, g.b0);
    /* Ignored while silent. */
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    const uint32_t from = g.n_log;
    send(&c);
    TEST_ASSERT_EQUAL_UINT32(c.len, lms_sim_stats(&g.sim)->host_ignored);
    pump_for(1000u * MS);
    TEST_ASSERT_EQUAL_UINT32(0u, count_ev(from, LMS_FRAMER_ACK));
    TEST_ASSERT_TRUE(g.max_gap_us >= 200000u);
    TEST_ASSERT_TRUE(g.max_gap_us < 200000u + 27000u);
    /* Resumed where it was: scan 3 next, then one per period again. */
    TEST_ASSERT_TRUE(g.b0 > 30u);
    TEST_ASSERT_EQUAL_UINT32(3u, g.b0_k[3]);
    TEST_ASSERT_EQUAL_UINT32(0u, g.k_jumps);
    TEST_ASSERT_TRUE(g.b0_t[3] - g.b0_t[2] >= 200000u);
    check_period(4u, g.b0, 1000000000ull * 2u, 75000u);
}

static void test_lms_sim_power_cycle_fault(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    cfg.unit = LMS_UNIT_MM;
    cfg.faults.power_cycle_after_scans = 2u;
    boot_fast(&cfg);
    set_variant(180u, 100u, true);
    const uint64_t t = g.now;
    start_stream(LMS_MODE_STREAM_ALL);
    pump_until(t + 60u * MS); /* scans end at 30.8 and 44.1 ms */
    TEST_ASSERT_EQUAL_UINT32(2u, g.b0);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->power_cycles);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&g.sim));
    const uint32_t from = g.n_log;
    g.baud = LMS_BAUD_9600; /* a driver finds it again at 9600 */
    pump_for(200u * MS);
    TEST_ASSERT_EQUAL_UINT32(from + 1u, g.n_log);
    TEST_ASSERT_EQUAL_HEX8(LMS_REPLY_POWER_ON, g.log[from].code);
    const lms_device_status_t st = status_now();
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_ON_REQUEST, st.operating_mode);
    TEST_ASSERT_EQUAL_UINT16(180u, st.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(50u, st.resolution_cdeg);
    TEST_ASSERT_EQUAL_UINT8(1u, st.units);
    TEST_ASSERT_EQUAL_UINT32(2u, g.b0);
    /* One-shot: a new stream runs on. */
    switch_baud(LMS_BAUD_500000);
    start_stream(LMS_MODE_STREAM_ALL);
    pump_for(500u * MS);
    TEST_ASSERT_TRUE(g.b0 > 15u);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->power_cycles);
}

static void test_lms_sim_hangup_fault_fires_once(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    cfg.faults.hangup_after_scans = 2u;
    boot_fast(&cfg);
    const uint64_t t = g.now;
    start_stream(LMS_MODE_STREAM_ALL);
    TEST_ASSERT_FALSE(lms_sim_take_hangup(&g.sim));
    pump_until(t + 60u * MS); /* scans end at 51.3 and 78.0 ms */
    TEST_ASSERT_EQUAL_UINT32(1u, g.b0);
    TEST_ASSERT_FALSE(lms_sim_take_hangup(&g.sim));
    pump_until(t + 78u * MS);
    TEST_ASSERT_EQUAL_UINT32(2u, g.b0);
    TEST_ASSERT_TRUE(lms_sim_take_hangup(&g.sim));
    TEST_ASSERT_FALSE(lms_sim_take_hangup(&g.sim));
    pump_for(500u * MS);
    TEST_ASSERT_FALSE(lms_sim_take_hangup(&g.sim));
    TEST_ASSERT_TRUE(g.b0 > 15u);
}

/* lms_sim_set_faults re-arms the one-shot faults, counted from now, and
 * replaces the probabilities (the soak's schedule, test_soak.c). */
static void test_lms_sim_set_faults_rearms_from_now(void)
{
    lms_sim_config_t cfg;
    config_with_source(&cfg);
    cfg.faults.hangup_after_scans = 2u;
    boot_fast(&cfg);
    start_stream(LMS_MODE_STREAM_ALL);
    pump_for(100u * MS);
    TEST_ASSERT_TRUE(lms_sim_take_hangup(&g.sim));
    pump_for(200u * MS);
    TEST_ASSERT_FALSE(lms_sim_take_hangup(&g.sim)); /* one-shot */
    lms_sim_faults_t f;
    memset(&f, 0, sizeof f);
    f.hangup_after_scans = 3u;
    lms_sim_set_faults(&g.sim, &f);
    const uint32_t b0 = g.b0;
    while (g.b0 < b0 + 2u) {
        pump_for(1u * MS);
    }
    TEST_ASSERT_FALSE(lms_sim_take_hangup(&g.sim));
    while (g.b0 < b0 + 3u) {
        pump_for(1u * MS);
    }
    TEST_ASSERT_TRUE(lms_sim_take_hangup(&g.sim));
    pump_for(200u * MS);
    TEST_ASSERT_FALSE(lms_sim_take_hangup(&g.sim));
    /* NAK everything, then nothing again. */
    f.hangup_after_scans = 0u;
    f.nak_percent = 100u;
    lms_sim_set_faults(&g.sim, &f);
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    send(&c);
    pump_for(50u * MS);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->naks_injected);
    f.nak_percent = 0u;
    lms_sim_set_faults(&g.sim, &f);
    send(&c);
    pump_for(50u * MS);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->naks_injected);
    lms_sim_set_faults(NULL, &f); /* ignored */
    lms_sim_set_faults(&g.sim, NULL);
}

/* --- 6. fault specifications ------------------------------------------------ */

static void test_lms_sim_parse_faults_good(void)
{
    lms_sim_faults_t f;
    memset(&f, 0xA5, sizeof f);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("", &f));
    TEST_ASSERT_TRUE(tu_all_zero(&f, sizeof f));
    TEST_ASSERT_TRUE(lms_sim_parse_faults("drop=10", &f));
    TEST_ASSERT_EQUAL_UINT32(10u, f.drop_ppm);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("flip=1000000", &f));
    TEST_ASSERT_EQUAL_UINT32(1000000u, f.flip_ppm);
    TEST_ASSERT_EQUAL_UINT32(0u, f.drop_ppm);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("insert=7", &f));
    TEST_ASSERT_EQUAL_UINT32(7u, f.insert_ppm);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("nak=100", &f));
    TEST_ASSERT_EQUAL_UINT32(100u, f.nak_percent);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("silence=100:500", &f));
    TEST_ASSERT_EQUAL_UINT32(100u, f.silence_after_scans);
    TEST_ASSERT_EQUAL_UINT32(500000u, f.silence_us);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("power=3", &f));
    TEST_ASSERT_EQUAL_UINT32(3u, f.power_cycle_after_scans);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("hangup=9", &f));
    TEST_ASSERT_EQUAL_UINT32(9u, f.hangup_after_scans);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("seed=4294967295", &f));
    TEST_ASSERT_EQUAL_UINT32(4294967295u, f.seed);
    TEST_ASSERT_TRUE(lms_sim_parse_faults(
        "drop=1,flip=2,insert=3,nak=4,silence=5:6,power=7,hangup=8,seed=9", &f));
    const lms_sim_faults_t want = {1u, 2u, 3u, 4u, 5u, 6000u, 7u, 8u, 9u};
    TEST_ASSERT_EQUAL_MEMORY(&want, &f, sizeof f);
    TEST_ASSERT_TRUE(lms_sim_parse_faults("silence=1:4294967", &f));
    TEST_ASSERT_EQUAL_UINT32(4294967000u, f.silence_us);
}

static void test_lms_sim_parse_faults_bad(void)
{
    static const char *const bad[] = {
        "bogus=1", "drop=", "drop=abc", "drop=1x", "drop=-1", "drop=+1", "drop= 1", " drop=1",
        "drop", "=5", "nak=101", "drop=1000001", "silence=5", "silence=5:", "silence=:5",
        "silence=1:4294968", "drop=99999999999", "seed=4294967296", "drop=1,", ",drop=1",
        "drop=1,,flip=2", "DROP=1", "drop=1;flip=2", "silence=1:2:3"};
    for (size_t i = 0u; i < sizeof bad / sizeof bad[0]; i++) {
        lms_sim_faults_t f;
        memset(&f, 0xA5, sizeof f);
        TEST_ASSERT_FALSE_MESSAGE(lms_sim_parse_faults(bad[i], &f), bad[i]);
        TEST_ASSERT_TRUE_MESSAGE(tu_all_zero(&f, sizeof f), bad[i]);
    }
    static char longspec[300];
    memset(longspec, 0, sizeof longspec);
    for (size_t i = 0u; i + 7u < 290u; i += 7u) {
        memcpy(&longspec[i], "drop=1,", 7u);
    }
    longspec[strlen(longspec) - 1u] = '\0';
    lms_sim_faults_t f;
    TEST_ASSERT_FALSE(lms_sim_parse_faults(longspec, &f));
    TEST_ASSERT_FALSE(lms_sim_parse_faults(NULL, &f));
    TEST_ASSERT_TRUE(tu_all_zero(&f, sizeof f));
    TEST_ASSERT_FALSE(lms_sim_parse_faults("drop=1", NULL));
}

/* --- 7. robustness -------------------------------------------------------- */

static void test_lms_sim_survives_garbage_at_the_right_rate(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    uint32_t seed = 12345u;
    uint32_t fed = 0u;
    for (uint32_t i = 0u; i < 12000u; i++) { /* 60 s: 4 bytes every 5 ms */
        uint8_t junk[4];
        for (size_t j = 0u; j < sizeof junk; j++) {
            junk[j] = tu_rand_byte(&seed);
            if (j == 0u && (i % 16u) == 0u) {
                junk[j] = LMS_STX; /* plenty of candidate starts */
            }
        }
        send_raw(junk, sizeof junk);
        fed += (uint32_t)sizeof junk;
        pump_for(5u * MS);
    }
    pump_for(100u * MS);
    const lms_sim_stats_t *s = lms_sim_stats(&g.sim);
    TEST_ASSERT_EQUAL_UINT32(0u, s->garbled_bytes);
    TEST_ASSERT_EQUAL_UINT32(0u, s->host_ignored);
    TEST_ASSERT_TRUE(s->host_bad > 0u);
    /* Every NAK the host saw is a bad candidate the scanner counted; no
     * output fault, so nothing else is on the line but ACKs and replies. */
    TEST_ASSERT_EQUAL_UINT32(s->host_bad + s->naks_injected, g.fr.stats.naks);
    TEST_ASSERT_EQUAL_UINT32(s->host_telegrams - s->other_address - s->cmds_dropped,
                             g.fr.stats.acks);
    TEST_ASSERT_EQUAL_UINT32(0u, g.fr.stats.crc_errors + g.fr.stats.length_errors);
    TEST_ASSERT_EQUAL_UINT32(g.bytes, s->bytes_out);
    TEST_ASSERT_TRUE(fed > s->host_bad);
    (void)status_now();
}

/* Random CRC-valid host telegrams of every other code: each gets at most
 * an ACK and one reply, never a NAK, and the scanner still works. */
static void test_lms_sim_survives_random_valid_telegrams(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    uint32_t seed = 777u;
    uint32_t sent = 0u;
    for (uint32_t i = 0u; i < 600u; i++) {
        uint8_t payload[40];
        uint8_t code = (uint8_t)tu_rand_range(&seed, 0x00u, 0x7Fu);
        if (code == LMS_CMD_RESET || code == LMS_CMD_MODE) {
            code = LMS_CMD_STATUS; /* keep the rate and the mode */
        }
        payload[0] = code;
        const size_t n = 1u + tu_rand_range(&seed, 0u, 38u);
        for (size_t j = 1u; j < n; j++) {
            payload[j] = tu_rand_byte(&seed);
            if (payload[j] == LMS_STX) {
                payload[j] = 0x03u; /* no second start inside */
            }
        }
        uint8_t buf[64];
        size_t written = 0u;
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(buf, sizeof buf, 0u, payload, n, -1,
                                                         &written));
        const uint32_t from = g.n_log;
        send_raw(buf, written);
        sent++;
        pump_for(250u * MS);
        TEST_ASSERT_TRUE(g.n_log - from <= 2u);
        if (g.n_log - from == 2u) {
            TEST_ASSERT_EQUAL_INT(LMS_FRAMER_ACK, g.log[from].ev);
            TEST_ASSERT_EQUAL_INT(LMS_FRAMER_TELEGRAM, g.log[from + 1u].ev);
        }
    }
    const lms_sim_stats_t *s = lms_sim_stats(&g.sim);
    TEST_ASSERT_TRUE(s->host_telegrams <= sent);
    TEST_ASSERT_TRUE(s->host_telegrams + s->host_framing >= sent);
    TEST_ASSERT_EQUAL_UINT32(s->host_telegrams, g.fr.stats.acks);
    TEST_ASSERT_EQUAL_UINT32(s->host_bad, g.fr.stats.naks);
    TEST_ASSERT_TRUE(s->not_acks > 100u);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_9600, lms_sim_baud(&g.sim));
    TEST_ASSERT_EQUAL_HEX8(LMS_MODE_ON_REQUEST, status_now().operating_mode);
}

/* A host telegram cut short is dropped after the 6 ms limit, so the next
 * one is not swallowed by it. */
static void test_lms_sim_abandons_incomplete_host_telegram(void)
{
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    /* A start claiming 444 bytes, then silence. */
    const uint8_t stub[5] = {LMS_STX, 0x00u, 0xBCu, 0x01u, 0x50u};
    send_raw(stub, sizeof stub);
    pump_for(7u * MS);
    TEST_ASSERT_EQUAL_UINT32(1u, lms_sim_stats(&g.sim)->host_framing);
    (void)status_now();

    /* Without the pause the stub would swallow the command, whose own
     * bytes the framer then finds again only after 444 more. */
    send_raw(stub, sizeof stub);
    lms_cmd_t c;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(&c, 0u));
    const uint32_t from = g.n_log;
    send(&c);
    pump_for(5u * MS);
    TEST_ASSERT_EQUAL_UINT32(from, g.n_log);
    /* The limit rescans the abandoned bytes: the command inside is found. */
    pump_for(300u * MS);
    TEST_ASSERT_NOT_NULL(find_code(from, LMS_REPLY_STATUS));
}

static void test_lms_sim_null_arguments(void)
{
    lms_sim_receive(NULL, NULL, 3u, LMS_BAUD_9600, 0u);
    TEST_ASSERT_EQUAL_UINT(0u, lms_sim_transmit(NULL, LMS_BAUD_9600, 0u, NULL, 10u));
    TEST_ASSERT_TRUE(lms_sim_next_event_us(NULL, 5u) == UINT64_MAX);
    TEST_ASSERT_FALSE(lms_sim_take_hangup(NULL));
    TEST_ASSERT_NULL(lms_sim_stats(NULL));
    lms_sim_defaults(NULL);
    lms_sim_init(NULL, NULL, 0u);
    lms_sim_config_t cfg;
    lms_sim_defaults(&cfg);
    boot(&cfg);
    lms_sim_receive(&g.sim, NULL, 7u, g.baud, g.now);
    TEST_ASSERT_EQUAL_UINT(0u, lms_sim_transmit(&g.sim, g.baud, g.now, NULL, 100u));
    (void)status_now();
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_sim_power_up_sends_90_after_the_delay_at_the_line_rate);
    RUN_TEST(test_lms_sim_power_up_ignores_host_and_honours_power_on_baud);
    RUN_TEST(test_lms_sim_status_reply_fields);
    RUN_TEST(test_lms_sim_installation_mode_password);
    RUN_TEST(test_lms_sim_type_and_errors);
    RUN_TEST(test_lms_sim_variant_accepted_and_refused);
    RUN_TEST(test_lms_sim_config_read_and_write);
    RUN_TEST(test_lms_sim_reset_reboots_at_power_on_rate);
    RUN_TEST(test_lms_sim_refuses_permanent_baud_and_unknown_commands);
    RUN_TEST(test_lms_sim_bad_crc_gets_nak_and_nothing_else);
    RUN_TEST(test_lms_sim_answers_its_own_address_and_broadcast_only);
    RUN_TEST(test_lms_sim_request_values_in_mode_25_only);
    RUN_TEST(test_lms_sim_queues_commands_in_order);
    RUN_TEST(test_lms_sim_baud_switch_after_the_a0);
    RUN_TEST(test_lms_sim_output_at_the_wrong_rate_is_noise);
    RUN_TEST(test_lms_sim_stream_500k_half_degree);
    RUN_TEST(test_lms_sim_stream_one_degree_and_partial_at_75_hz);
    RUN_TEST(test_lms_sim_stream_at_9600_skips_rotations);
    RUN_TEST(test_lms_sim_stream_source_end_and_gap);
    RUN_TEST(test_lms_sim_stream_speed_2000_halves_the_period);
    RUN_TEST(test_lms_sim_next_event_is_exact);
    RUN_TEST(test_lms_sim_queue_never_overflows);
    RUN_TEST(test_lms_sim_huge_time_jump_is_bounded);
    RUN_TEST(test_lms_sim_faults_are_reproducible_and_survivable);
    RUN_TEST(test_lms_sim_nak_percent_100_naks_everything);
    RUN_TEST(test_lms_sim_silence_fault);
    RUN_TEST(test_lms_sim_power_cycle_fault);
    RUN_TEST(test_lms_sim_hangup_fault_fires_once);
    RUN_TEST(test_lms_sim_set_faults_rearms_from_now);
    RUN_TEST(test_lms_sim_parse_faults_good);
    RUN_TEST(test_lms_sim_parse_faults_bad);
    RUN_TEST(test_lms_sim_survives_garbage_at_the_right_rate);
    RUN_TEST(test_lms_sim_survives_random_valid_telegrams);
    RUN_TEST(test_lms_sim_abandons_incomplete_host_telegram);
    RUN_TEST(test_lms_sim_null_arguments);
    return UNITY_END();
}
