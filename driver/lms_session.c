/* lms_session.c - the LMS 2xx session state machine; contract in
 * lms_session.h, states and timings in docs/session.md. */
#include "lms_session.h"

#include <string.h>

/* Phases of a step: what the current deadline means. */
enum {
    PH_IDLE = 0,  /* no deadline (STREAMING, STOPPED, FAILED) */
    PH_DRAIN,     /* PROBE: listening before the first send */
    PH_ACK,       /* command sent, waiting for 06 */
    PH_REPLY,     /* 06 came, waiting for the reply telegram */
    PH_NAK_WAIT,  /* 15 came, waiting before the resend */
    PH_WAIT,      /* LISTEN, SETTLE, BACKOFF: a plain timer */
    PH_SEND       /* a new step: its first send is due (done by the poll) */
};

#define DEFAULT_PASSWORD "SICK_LMS"
#define PASSWORD_LEN 8u

void lms_session_defaults(lms_session_config_t *config)
{
    if (config == NULL) {
        return;
    }
    memset(config, 0, sizeof *config);
    config->address = 0u;
    config->baud = LMS_BAUD_500000;
    config->unit = LMS_SESSION_KEEP;
    config->meas_mode = LMS_SESSION_KEEP;
    config->restore_9600 = true;
    memcpy(config->password, DEFAULT_PASSWORD, sizeof DEFAULT_PASSWORD);
    config->ack_timeout_us = 100000u;
    config->reply_timeout_us = 3500000u;
    config->write_timeout_us = 16000000u;
    config->nak_wait_us = 40000u;
    config->drain_us = 30000u;
    config->settle_us = 250000u;
    config->byte_gap_us = 40000u;
    config->backoff_min_us = 100000u;
    config->backoff_max_us = 5000000u;
    config->silence_scans = 8u;
    config->retries = 3u;
    config->probe_sends = 2u;
}

/* The largest timeout any field may hold: differences of the 32-bit clock
 * are only meaningful below 2^31 us. */
#define TIMEOUT_MAX 0x7FFFFFFFu

static bool timeout_ok(uint32_t us)
{
    return us > 0u && us <= TIMEOUT_MAX;
}

lms_status_t lms_session_check_config(const lms_session_config_t *c)
{
    if (c == NULL || c->address > 0x7Fu || (unsigned)c->baud >= LMS_BAUD_COUNT) {
        return LMS_ERR_ARG;
    }
    if (c->angle_deg != 0u && !lms_variant_is_legal(c->angle_deg, c->resolution_cdeg)) {
        return LMS_ERR_ARG;
    }
    if (c->unit != LMS_SESSION_KEEP && c->unit != LMS_UNIT_CM && c->unit != LMS_UNIT_MM) {
        return LMS_ERR_ARG;
    }
    if (c->meas_mode != LMS_SESSION_KEEP && lms_meas_mode_bits(c->meas_mode) == 0u) {
        return LMS_ERR_ARG;
    }
    if (memchr(c->password, '\0', sizeof c->password) != &c->password[PASSWORD_LEN]) {
        return LMS_ERR_ARG; /* exactly 8 characters, then the NUL */
    }
    if (!timeout_ok(c->ack_timeout_us) || !timeout_ok(c->reply_timeout_us) ||
        !timeout_ok(c->write_timeout_us) || !timeout_ok(c->nak_wait_us) ||
        !timeout_ok(c->drain_us) || !timeout_ok(c->settle_us) || !timeout_ok(c->byte_gap_us) ||
        !timeout_ok(c->backoff_min_us) || !timeout_ok(c->backoff_max_us) ||
        c->backoff_min_us > c->backoff_max_us || c->power_wait_us > TIMEOUT_MAX) {
        return LMS_ERR_ARG;
    }
    if (c->silence_scans == 0u || c->retries == 0u || c->probe_sends == 0u) {
        return LMS_ERR_ARG;
    }
    return LMS_OK;
}

const char *lms_session_state_name(lms_session_state_t state)
{
    static const char *const names[LMS_SESSION_STATE_COUNT] = {
        "listen",       "probe",        "confirm",      "switch",        "settle",
        "verify",       "identify",     "variant",      "install",       "read-config",
        "write-config", "check-config", "leave-install", "start",        "streaming",
        "backoff",      "stop-stream",  "stop-baud",    "stopped",       "failed"};
    if ((unsigned)state >= (unsigned)LMS_SESSION_STATE_COUNT) {
        return "?";
    }
    return names[state];
}

const char *lms_session_error_name(lms_session_error_t error)
{
    switch (error) {
    case LMS_SESSION_ERR_NONE:
        return "no error";
    case LMS_SESSION_ERR_VARIANT:
        return "the scanner refused the variant";
    case LMS_SESSION_ERR_PASSWORD:
        return "the scanner refused the installation password";
    case LMS_SESSION_ERR_CONFIG:
        return "the scanner refused the configuration (units / measuring mode)";
    case LMS_SESSION_ERR_MODE:
        return "the scanner reports a fault (A0 02)";
    }
    return "?";
}

/* a is at or after b on the wrapping clock. */
static bool reached(uint32_t now, uint32_t deadline)
{
    return (int32_t)(now - deadline) >= 0;
}

/* --- Line timing ------------------------------------------------------ */

static uint16_t variant_values(uint16_t angle_deg, uint16_t resolution_cdeg, bool partial)
{
    if (partial || resolution_cdeg == 0u) {
        return angle_deg == 100u ? 101u : 181u;
    }
    return (uint16_t)((uint32_t)angle_deg * 100u / resolution_cdeg + 1u);
}

/* Time between two B0 telegrams while streaming: a mirror rotation per
 * scan (13.3 ms per degree step pass), or the telegram's wire time at a
 * slow rate, rounded up to whole scan periods (the scanner skips the
 * scans the line cannot carry). */
uint32_t lms_session_scan_interval_us(const lms_session_t *s)
{
    const uint16_t n = variant_values(s->info.angle_deg, s->info.resolution_cdeg, s->config.partial);
    return lms_scan_interval_us(n, s->info.baud);
}

static uint32_t silence_limit_us(const lms_session_t *s)
{
    const uint64_t limit = (uint64_t)lms_session_scan_interval_us(s) * s->config.silence_scans;
    return limit > TIMEOUT_MAX ? TIMEOUT_MAX : (uint32_t)limit;
}

/* --- Discovery order -------------------------------------------------- */

/* Candidate i of a discovery round: the last rate that worked, then the
 * factory default and the rates used scanners are most often stuck at. */
static bool candidate(const lms_session_t *s, uint8_t i, lms_baud_t *out)
{
    static const lms_baud_t rest[] = {LMS_BAUD_9600, LMS_BAUD_38400, LMS_BAUD_19200,
                                      LMS_BAUD_500000};
    if (i == 0u) {
        *out = s->last_good_baud;
        return true;
    }
    uint8_t seen = 1u;
    for (size_t k = 0u; k < sizeof rest / sizeof rest[0]; k++) {
        if (rest[k] == s->last_good_baud) {
            continue;
        }
        if (seen == i) {
            *out = rest[k];
            return true;
        }
        seen++;
    }
    return false;
}

/* --- Sending ---------------------------------------------------------- */

static void set_host_baud(lms_session_t *s, lms_baud_t baud)
{
    s->io.set_baud(s->io.ctx, baud);
    s->host_baud = baud;
    /* Whatever was half received belongs to the old rate: dropped, and
     * counted as skipped, so that the framer's accounting still balances
     * (bytes_in == telegram_bytes + acks + naks + bytes_skipped + pending). */
    lms_framer_stats_t keep = s->framer.stats;
    keep.bytes_skipped += (uint32_t)lms_framer_pending(&s->framer);
    lms_framer_init(&s->framer, LMS_FROM_SCANNER);
    s->framer.stats = keep;
}

static void wait_phase(lms_session_t *s, lms_session_state_t state, uint32_t us, uint32_t now)
{
    s->state = state;
    s->phase = PH_WAIT;
    s->deadline_us = now + us;
}

static uint8_t send_limit(const lms_session_t *s)
{
    return s->state == LMS_SESSION_PROBE ? s->config.probe_sends : s->config.retries;
}

static void step_failed(lms_session_t *s, uint32_t now);

static void send_cmd(lms_session_t *s, uint32_t now)
{
    if (s->sends >= send_limit(s)) {
        step_failed(s, now);
        return;
    }
    if (s->sends > 0u) {
        s->stats.retries++;
    }
    s->sends++;
    s->stats.commands++;
    if (s->state == LMS_SESSION_PROBE) {
        s->stats.probes++;
    }
    s->io.write(s->io.ctx, s->cmd.bytes, s->cmd.len);
    s->phase = PH_ACK;
    s->deadline_us = now + s->config.ack_timeout_us;
}

/* Enters a state that sends one command and waits for its reply. */
static void begin_step(lms_session_t *s, lms_session_state_t state, uint32_t now)
{
    const uint8_t a = s->config.address;
    lms_status_t st = LMS_ERR_ARG;
    s->state = state;
    s->sends = 0u;
    switch (state) {
    case LMS_SESSION_PROBE:
    case LMS_SESSION_LEAVE_INSTALL:
    case LMS_SESSION_STOP_STREAM:
        st = lms_cmd_mode(&s->cmd, a, LMS_MODE_ON_REQUEST);
        break;
    case LMS_SESSION_CONFIRM:
    case LMS_SESSION_VERIFY:
        st = lms_cmd_status(&s->cmd, a);
        break;
    case LMS_SESSION_SWITCH:
        st = lms_cmd_baud(&s->cmd, a, s->config.baud);
        break;
    case LMS_SESSION_STOP_BAUD:
        st = lms_cmd_baud(&s->cmd, a, LMS_BAUD_9600);
        break;
    case LMS_SESSION_IDENTIFY:
        st = lms_cmd_type(&s->cmd, a);
        break;
    case LMS_SESSION_VARIANT:
        st = lms_cmd_variant(&s->cmd, a, s->config.angle_deg, s->config.resolution_cdeg);
        break;
    case LMS_SESSION_INSTALL:
        st = lms_cmd_installation(&s->cmd, a, s->config.password);
        break;
    case LMS_SESSION_READ_CONFIG:
    case LMS_SESSION_CHECK_CONFIG:
        st = lms_cmd_config_read(&s->cmd, a);
        break;
    case LMS_SESSION_WRITE_CONFIG:
        st = lms_cmd_config_write(&s->cmd, a, &s->block);
        break;
    case LMS_SESSION_START:
        st = lms_cmd_mode(&s->cmd, a,
                          s->config.partial ? LMS_MODE_STREAM_PARTIAL : LMS_MODE_STREAM_ALL);
        break;
    default:
        break;
    }
    if (st != LMS_OK) {
        /* Cannot happen with a checked config; fail loudly rather than loop. */
        s->state = LMS_SESSION_FAILED;
        s->phase = PH_IDLE;
        s->error = LMS_SESSION_ERR_CONFIG;
        s->report_failed = true;
        return;
    }
    if (state == LMS_SESSION_PROBE) {
        /* Listen first: stray bytes at this rate are drained, not parsed. */
        s->phase = PH_DRAIN;
        s->deadline_us = now + s->config.drain_us;
        return;
    }
    /* The send itself happens in the next poll (due at once): a step that
     * runs out of sends starts another step, and sending from here would
     * make that a recursion. */
    s->phase = PH_SEND;
    s->deadline_us = now;
}

/* --- State changes ---------------------------------------------------- */

static void begin_probe(lms_session_t *s, uint8_t index, uint32_t now)
{
    lms_baud_t baud = LMS_BAUD_9600;
    if (!candidate(s, index, &baud)) {
        /* A whole round found nothing: wait, listening at the factory rate
         * for a power-on telegram, then start again. */
        s->stats.discovery_rounds++;
        set_host_baud(s, LMS_BAUD_9600);
        wait_phase(s, LMS_SESSION_BACKOFF, s->backoff_us, now);
        const uint32_t next = s->backoff_us * 2u;
        s->backoff_us = next > s->config.backoff_max_us ? s->config.backoff_max_us : next;
        return;
    }
    s->probe_index = index;
    if (baud != s->host_baud) {
        set_host_baud(s, baud);
    }
    begin_step(s, LMS_SESSION_PROBE, now);
}

static void fail(lms_session_t *s, lms_session_error_t error)
{
    s->state = LMS_SESSION_FAILED;
    s->phase = PH_IDLE;
    s->error = error;
    s->report_failed = true;
}

static void finish_stop(lms_session_t *s)
{
    s->state = LMS_SESSION_STOPPED;
    s->phase = PH_IDLE;
    s->report_stopped = true;
}

/* The link is gone (or suspect): bring the scanner up again. */
static void restart(lms_session_t *s, lms_session_cause_t cause, uint32_t now)
{
    s->cause = cause;
    if (s->state == LMS_SESSION_STREAMING) {
        s->stats.restarts++;
        s->report_restart = true;
        if (cause == LMS_SESSION_CAUSE_SILENCE) {
            s->stats.restarts_silence++;
        } else if (cause == LMS_SESSION_CAUSE_POWER_ON) {
            s->stats.restarts_power_on++;
        } else {
            s->stats.restarts_link++;
        }
    }
    s->backoff_us = s->config.backoff_min_us;
    if (cause == LMS_SESSION_CAUSE_POWER_ON) {
        /* It just powered up at the rate we hear it on. */
        s->last_good_baud = s->host_baud;
        begin_step(s, LMS_SESSION_CONFIRM, now);
        return;
    }
    begin_probe(s, 0u, now);
}

/* What to change next once the rate and identity are known. */
static void configure_next(lms_session_t *s, uint32_t now)
{
    const lms_session_config_t *c = &s->config;
    if (c->angle_deg != 0u &&
        (s->info.angle_deg != c->angle_deg || s->info.resolution_cdeg != c->resolution_cdeg)) {
        begin_step(s, LMS_SESSION_VARIANT, now);
        return;
    }
    if ((c->unit != LMS_SESSION_KEEP && c->unit != s->info.units) ||
        (c->meas_mode != LMS_SESSION_KEEP && c->meas_mode != s->info.meas_mode)) {
        begin_step(s, LMS_SESSION_INSTALL, now);
        return;
    }
    begin_step(s, LMS_SESSION_START, now);
}

/* A step ran out of sends. */
static void step_failed(lms_session_t *s, uint32_t now)
{
    switch (s->state) {
    case LMS_SESSION_PROBE:
        begin_probe(s, (uint8_t)(s->probe_index + 1u), now);
        break;
    case LMS_SESSION_STOP_STREAM:
    case LMS_SESSION_STOP_BAUD:
        finish_stop(s); /* given up: nothing more can be done on this line */
        break;
    default:
        /* The two ends may disagree on the rate now: discover again. */
        begin_probe(s, 0u, now);
        break;
    }
}

static void enter_streaming(lms_session_t *s, uint32_t now)
{
    s->state = LMS_SESSION_STREAMING;
    s->phase = PH_IDLE;
    s->report_streaming = true;
    s->last_scan_us = now;
    s->backoff_us = s->config.backoff_min_us;
    s->stats.bring_ups++;
}

/* --- Replies ---------------------------------------------------------- */

static bool mode_ok(lms_session_t *s, const uint8_t *t, size_t len)
{
    lms_mode_reply_t r;
    if (lms_decode_mode_reply(t, len, &r) != LMS_OK) {
        return false;
    }
    if (r.result == LMS_MODE_RESULT_BAD_PASSWORD) {
        fail(s, LMS_SESSION_ERR_PASSWORD);
        return false;
    }
    if (r.result == LMS_MODE_RESULT_FAULT) {
        fail(s, LMS_SESSION_ERR_MODE);
        return false;
    }
    return true;
}

/* B1 at the host's rate: the rate is confirmed when its baud word agrees. */
static void on_status(lms_session_t *s, const uint8_t *t, size_t len, uint32_t now)
{
    lms_device_status_t st;
    if (lms_decode_status(t, len, &st) != LMS_OK) {
        return;
    }
    if (!st.baud_known || st.baud != s->host_baud) {
        /* Not the rate we think: try the next candidate (from CONFIRM), or
         * start discovery over (after a switch). */
        begin_probe(s, s->state == LMS_SESSION_CONFIRM ? (uint8_t)(s->probe_index + 1u) : 0u,
                    now);
        return;
    }
    s->info.baud = st.baud;
    s->info.angle_deg = st.angle_deg;
    s->info.resolution_cdeg = st.resolution_cdeg;
    s->info.units = st.units;
    s->info.meas_mode = st.meas_mode;
    s->last_good_baud = st.baud;
    if (st.baud != s->config.baud) {
        begin_step(s, LMS_SESSION_SWITCH, now);
        return;
    }
    begin_step(s, LMS_SESSION_IDENTIFY, now);
}

static bool config_matches(const lms_session_t *s, const lms_config_t *cfg)
{
    return (s->config.unit == LMS_SESSION_KEEP || lms_config_units(cfg) == s->config.unit) &&
           (s->config.meas_mode == LMS_SESSION_KEEP ||
            lms_config_meas_mode(cfg) == s->config.meas_mode);
}

/* A CRC-valid reply telegram (not B0 while streaming, not 90). */
static void on_reply(lms_session_t *s, const uint8_t *t, size_t len, uint8_t code, uint32_t now)
{
    const lms_session_state_t st = s->state;
    if (code == LMS_REPLY_NOT_ACK) {
        s->stats.not_acks++;
        if (st == LMS_SESSION_VARIANT) {
            fail(s, LMS_SESSION_ERR_VARIANT);
        } else if (st == LMS_SESSION_INSTALL || st == LMS_SESSION_WRITE_CONFIG) {
            fail(s, LMS_SESSION_ERR_CONFIG);
        } else if (s->phase == PH_ACK || s->phase == PH_REPLY) {
            step_failed(s, now);
        }
        return;
    }
    if (s->phase != PH_ACK && s->phase != PH_REPLY) {
        s->stats.stray_telegrams++;
        return;
    }
    switch (st) {
    case LMS_SESSION_PROBE:
    case LMS_SESSION_LEAVE_INSTALL:
    case LMS_SESSION_START:
    case LMS_SESSION_STOP_STREAM:
    case LMS_SESSION_SWITCH:
    case LMS_SESSION_STOP_BAUD:
    case LMS_SESSION_INSTALL:
        if (code != LMS_REPLY_MODE) {
            break;
        }
        if (!mode_ok(s, t, len)) {
            return; /* failed, or an undecodable A0: wait for the retry */
        }
        if (st == LMS_SESSION_PROBE) {
            s->last_good_baud = s->host_baud;
            s->info.reply_address = t[1];
            begin_step(s, LMS_SESSION_CONFIRM, now);
        } else if (st == LMS_SESSION_LEAVE_INSTALL) {
            begin_step(s, LMS_SESSION_START, now);
        } else if (st == LMS_SESSION_START) {
            enter_streaming(s, now);
        } else if (st == LMS_SESSION_INSTALL) {
            begin_step(s, LMS_SESSION_READ_CONFIG, now);
        } else if (st == LMS_SESSION_SWITCH) {
            s->stats.baud_switches++;
            set_host_baud(s, s->config.baud);
            wait_phase(s, LMS_SESSION_SETTLE, s->config.settle_us, now);
        } else if (st == LMS_SESSION_STOP_STREAM) {
            if (s->config.restore_9600 && s->host_baud != LMS_BAUD_9600) {
                begin_step(s, LMS_SESSION_STOP_BAUD, now);
            } else {
                finish_stop(s);
            }
        } else { /* STOP_BAUD */
            set_host_baud(s, LMS_BAUD_9600);
            s->last_good_baud = LMS_BAUD_9600;
            finish_stop(s);
        }
        return;
    case LMS_SESSION_CONFIRM:
    case LMS_SESSION_VERIFY:
        if (code == LMS_REPLY_STATUS) {
            on_status(s, t, len, now);
            return;
        }
        break;
    case LMS_SESSION_IDENTIFY: {
        lms_ident_t id;
        if (code == LMS_REPLY_TYPE && lms_decode_type(t, len, &id) == LMS_OK) {
            memcpy(s->info.type_text, id.text, sizeof s->info.type_text);
            configure_next(s, now);
            return;
        }
        break;
    }
    case LMS_SESSION_VARIANT: {
        lms_variant_reply_t v;
        if (code == LMS_REPLY_VARIANT && lms_decode_variant_reply(t, len, &v) == LMS_OK) {
            if (!v.accepted || v.angle_deg != s->config.angle_deg ||
                v.resolution_cdeg != s->config.resolution_cdeg) {
                fail(s, LMS_SESSION_ERR_VARIANT);
                return;
            }
            s->info.angle_deg = v.angle_deg;
            s->info.resolution_cdeg = v.resolution_cdeg;
            configure_next(s, now);
            return;
        }
        break;
    }
    case LMS_SESSION_READ_CONFIG:
    case LMS_SESSION_CHECK_CONFIG: {
        lms_config_reply_t r;
        if (code != LMS_REPLY_CONFIG || lms_decode_config(t, len, &r) != LMS_OK) {
            break;
        }
        if (st == LMS_SESSION_CHECK_CONFIG) {
            if (!config_matches(s, &r.config)) {
                fail(s, LMS_SESSION_ERR_CONFIG);
                return;
            }
            s->info.units = lms_config_units(&r.config);
            s->info.meas_mode = lms_config_meas_mode(&r.config);
            begin_step(s, LMS_SESSION_LEAVE_INSTALL, now);
            return;
        }
        s->block = r.config;
        if (s->config.unit != LMS_SESSION_KEEP) {
            (void)lms_config_set_unit(&s->block, (lms_unit_t)s->config.unit);
        }
        if (s->config.meas_mode != LMS_SESSION_KEEP) {
            (void)lms_config_set_meas_mode(&s->block, s->config.meas_mode);
        }
        if (memcmp(s->block.block, r.config.block, r.config.size) == 0) {
            /* Already so (B1 said otherwise): no EEPROM write. */
            s->info.units = lms_config_units(&r.config);
            s->info.meas_mode = lms_config_meas_mode(&r.config);
            begin_step(s, LMS_SESSION_LEAVE_INSTALL, now);
        } else {
            begin_step(s, LMS_SESSION_WRITE_CONFIG, now);
        }
        return;
    }
    case LMS_SESSION_WRITE_CONFIG: {
        lms_config_write_reply_t w;
        if (code == LMS_REPLY_CONFIG_WRITE &&
            lms_decode_config_write_reply(t, len, &w) == LMS_OK) {
            if (!w.accepted) {
                fail(s, LMS_SESSION_ERR_CONFIG);
                return;
            }
            s->stats.config_writes++;
            begin_step(s, LMS_SESSION_CHECK_CONFIG, now);
            return;
        }
        break;
    }
    default:
        break;
    }
    s->stats.stray_telegrams++;
}

/* A CRC-valid telegram from the framer. Returns the event to report. */
static lms_session_event_t on_telegram(lms_session_t *s, uint32_t now)
{
    size_t len = 0u;
    const uint8_t *t = lms_framer_telegram(&s->framer, &len);
    if (t == NULL || len <= LMS_HEADER_SIZE) {
        return LMS_SESSION_EV_NONE;
    }
    const uint8_t address = t[1];
    const uint8_t code = t[LMS_HEADER_SIZE];
    if (s->config.address != 0u && address != (LMS_ADDR_REPLY_BIT | s->config.address)) {
        s->stats.stray_telegrams++; /* another scanner on a shared line */
        return LMS_SESSION_EV_NONE;
    }
    if (s->state == LMS_SESSION_STOPPED || s->state == LMS_SESSION_FAILED) {
        return LMS_SESSION_EV_NONE;
    }
    if (code == LMS_REPLY_POWER_ON) {
        s->stats.power_ons++;
        if (s->state != LMS_SESSION_STOP_STREAM && s->state != LMS_SESSION_STOP_BAUD) {
            restart(s, LMS_SESSION_CAUSE_POWER_ON, now);
        }
        return LMS_SESSION_EV_NONE;
    }
    if (code == LMS_REPLY_VALUES) {
        if (s->state == LMS_SESSION_STREAMING) {
            s->last_scan_us = now;
            s->stats.scans++;
            return LMS_SESSION_EV_SCAN;
        }
        /* A stream still running during discovery or a stop: expected. */
        s->stats.stray_telegrams++;
        return LMS_SESSION_EV_NONE;
    }
    on_reply(s, t, len, code, now);
    return LMS_SESSION_EV_NONE;
}

static void on_ack(lms_session_t *s, uint32_t now)
{
    if (s->phase == PH_ACK) {
        s->phase = PH_REPLY;
        s->deadline_us = now + (s->state == LMS_SESSION_WRITE_CONFIG ? s->config.write_timeout_us
                                                                      : s->config.reply_timeout_us);
    }
}

/* Bytes that were no telegram, ACK or NAK: noise, or a reply damaged. */
static uint32_t junk_bytes(const lms_framer_t *f)
{
    return f->stats.bytes_skipped + f->stats.crc_errors + f->stats.length_errors;
}

/* Junk on the line after the ACK: the reply may be what the noise ate (or
 * the 06 was noise). Waiting out reply_timeout_us (3.5 s, for mode changes)
 * would hold recovery for seconds: the command goes again ack_timeout_us
 * after the first junk, a send of its retries (a mode change still under
 * way answers the first send; its A0 is taken in either phase). Not for
 * the EEPROM write, which a second send would start again. */
static void on_junk_awaiting_reply(lms_session_t *s, uint32_t now)
{
    if (s->phase != PH_REPLY || s->state == LMS_SESSION_WRITE_CONFIG) {
        return;
    }
    const uint32_t soon = now + s->config.ack_timeout_us;
    if (!reached(soon, s->deadline_us)) {
        s->deadline_us = soon;
    }
}

static void on_nak(lms_session_t *s, uint32_t now)
{
    s->stats.naks++;
    if (s->phase == PH_ACK || s->phase == PH_REPLY) {
        s->phase = PH_NAK_WAIT;
        s->deadline_us = now + s->config.nak_wait_us;
    }
}

static lms_session_event_t on_framer_event(lms_session_t *s, lms_framer_event_t ev, uint32_t now)
{
    switch (ev) {
    case LMS_FRAMER_TELEGRAM:
        return on_telegram(s, now);
    case LMS_FRAMER_ACK:
        on_ack(s, now);
        break;
    case LMS_FRAMER_NAK:
        on_nak(s, now);
        break;
    default:
        break; /* CRC / length errors and truncation: counted by the framer */
    }
    return LMS_SESSION_EV_NONE;
}

/* An event decided earlier, reported before anything new happens. */
static lms_session_event_t take_report(lms_session_t *s)
{
    if (s->report_restart) {
        s->report_restart = false;
        return LMS_SESSION_EV_RESTART;
    }
    if (s->report_failed) {
        s->report_failed = false;
        return LMS_SESSION_EV_FAILED;
    }
    if (s->report_streaming) {
        s->report_streaming = false;
        return LMS_SESSION_EV_STREAMING;
    }
    if (s->report_stopped) {
        s->report_stopped = false;
        return LMS_SESSION_EV_STOPPED;
    }
    return LMS_SESSION_EV_NONE;
}

/* --- Public ----------------------------------------------------------- */

lms_status_t lms_session_init(lms_session_t *s, const lms_session_config_t *config,
                              const lms_session_io_t *io, uint32_t now_us)
{
    if (s == NULL) {
        return LMS_ERR_ARG;
    }
    memset(s, 0, sizeof *s);
    lms_framer_init(&s->framer, LMS_FROM_SCANNER);
    if (lms_session_check_config(config) != LMS_OK || io == NULL || io->write == NULL ||
        io->set_baud == NULL) {
        s->state = LMS_SESSION_FAILED;
        s->error = LMS_SESSION_ERR_CONFIG;
        return LMS_ERR_ARG;
    }
    s->config = *config;
    s->io = *io;
    s->last_good_baud = config->baud;
    s->backoff_us = config->backoff_min_us;
    s->last_byte_us = now_us;
    s->info.baud = config->baud;
    if (config->power_wait_us > 0u) {
        /* The power-on telegram comes at the factory rate. */
        set_host_baud(s, LMS_BAUD_9600);
        wait_phase(s, LMS_SESSION_LISTEN, config->power_wait_us, now_us);
    } else {
        s->host_baud = LMS_BAUD_COUNT; /* unknown: the first probe sets it */
        begin_probe(s, 0u, now_us);
    }
    return LMS_OK;
}

lms_session_event_t lms_session_feed(lms_session_t *s, const uint8_t *bytes, size_t len,
                                     size_t *consumed, uint32_t now_us)
{
    size_t used_total = 0u;
    lms_session_event_t ev = take_report(s);
    if (ev == LMS_SESSION_EV_NONE && bytes != NULL && len > 0u) {
        s->last_byte_us = now_us;
        const uint32_t junk_before = junk_bytes(&s->framer);
        /* Bounded: each framer call either uses bytes or reports an event
         * from its buffer, which it can do at most LMS_FRAMER_BUF_SIZE times
         * before it needs bytes again. */
        for (size_t guard = 0u; guard <= len + LMS_FRAMER_BUF_SIZE; guard++) {
            size_t used = 0u;
            const lms_framer_event_t fe =
                lms_framer_feed(&s->framer, bytes + used_total, len - used_total, &used);
            used_total += used;
            if (fe == LMS_FRAMER_NEED_MORE) {
                break;
            }
            if (s->phase == PH_DRAIN && fe != LMS_FRAMER_TELEGRAM) {
                continue; /* noise at a candidate rate before we spoke */
            }
            ev = on_framer_event(s, fe, now_us);
            if (ev == LMS_SESSION_EV_NONE) {
                ev = take_report(s);
            }
            if (ev != LMS_SESSION_EV_NONE) {
                break;
            }
        }
        if (junk_bytes(&s->framer) != junk_before) {
            on_junk_awaiting_reply(s, now_us);
        }
    }
    if (consumed != NULL) {
        *consumed = used_total;
    }
    return ev;
}

lms_session_event_t lms_session_poll(lms_session_t *s, uint32_t now_us)
{
    lms_session_event_t ev = take_report(s);
    if (ev != LMS_SESSION_EV_NONE) {
        return ev;
    }
    /* A half telegram followed by silence longer than the scanner's
     * inter-byte limit will never complete: drop it (searching its bytes
     * again, as the framer does). */
    if (lms_framer_pending(&s->framer) > 0u &&
        reached(now_us, s->last_byte_us + s->config.byte_gap_us)) {
        s->stats.flushes++;
        for (size_t guard = 0u; guard <= LMS_FRAMER_BUF_SIZE + 1u; guard++) {
            const lms_framer_event_t fe = lms_framer_flush(&s->framer);
            if (fe == LMS_FRAMER_NEED_MORE) {
                break;
            }
            ev = on_framer_event(s, fe, now_us);
            if (ev == LMS_SESSION_EV_NONE) {
                ev = take_report(s);
            }
            if (ev != LMS_SESSION_EV_NONE) {
                return ev;
            }
        }
    }
    if (s->state == LMS_SESSION_STREAMING) {
        if (reached(now_us, s->last_scan_us + silence_limit_us(s))) {
            restart(s, LMS_SESSION_CAUSE_SILENCE, now_us);
        }
        return take_report(s);
    }
    if (s->phase == PH_IDLE || !reached(now_us, s->deadline_us)) {
        return LMS_SESSION_EV_NONE;
    }
    switch (s->phase) {
    case PH_SEND:
    case PH_DRAIN:
    case PH_NAK_WAIT:
        send_cmd(s, now_us);
        break;
    case PH_ACK:
        s->stats.ack_timeouts++;
        send_cmd(s, now_us);
        break;
    case PH_REPLY:
        s->stats.reply_timeouts++;
        send_cmd(s, now_us);
        break;
    default: /* PH_WAIT */
        if (s->state == LMS_SESSION_SETTLE) {
            begin_step(s, LMS_SESSION_VERIFY, now_us);
        } else { /* LISTEN, BACKOFF */
            begin_probe(s, 0u, now_us);
        }
        break;
    }
    return take_report(s);
}

uint32_t lms_session_wait_us(const lms_session_t *s, uint32_t now_us)
{
    if (s->report_restart || s->report_failed || s->report_streaming || s->report_stopped) {
        return 0u;
    }
    uint32_t wait = TIMEOUT_MAX;
    if (s->state == LMS_SESSION_STREAMING) {
        const uint32_t due = s->last_scan_us + silence_limit_us(s);
        wait = reached(now_us, due) ? 0u : due - now_us;
    } else if (s->phase != PH_IDLE) {
        wait = reached(now_us, s->deadline_us) ? 0u : s->deadline_us - now_us;
    }
    if (lms_framer_pending(&s->framer) > 0u) {
        const uint32_t due = s->last_byte_us + s->config.byte_gap_us;
        const uint32_t w = reached(now_us, due) ? 0u : due - now_us;
        wait = w < wait ? w : wait;
    }
    return wait;
}

const uint8_t *lms_session_telegram(const lms_session_t *s, size_t *len)
{
    size_t n = 0u;
    const uint8_t *t = lms_framer_telegram(&s->framer, &n);
    if (t == NULL || n <= LMS_HEADER_SIZE || t[LMS_HEADER_SIZE] != LMS_REPLY_VALUES ||
        s->state != LMS_SESSION_STREAMING) {
        t = NULL;
        n = 0u;
    }
    if (len != NULL) {
        *len = n;
    }
    return t;
}

void lms_session_link_lost(lms_session_t *s, uint32_t now_us)
{
    if (s->state == LMS_SESSION_STOPPED || s->state == LMS_SESSION_FAILED) {
        return;
    }
    if (s->state == LMS_SESSION_STOP_STREAM || s->state == LMS_SESSION_STOP_BAUD) {
        finish_stop(s);
        return;
    }
    s->host_baud = LMS_BAUD_COUNT; /* a reopened port: its rate is unknown */
    restart(s, LMS_SESSION_CAUSE_LINK, now_us);
}

void lms_session_stop(lms_session_t *s, uint32_t now_us)
{
    switch (s->state) {
    case LMS_SESSION_STOPPED:
    case LMS_SESSION_STOP_STREAM:
    case LMS_SESSION_STOP_BAUD:
        return;
    case LMS_SESSION_LISTEN:
    case LMS_SESSION_PROBE:
    case LMS_SESSION_BACKOFF:
    case LMS_SESSION_FAILED:
        finish_stop(s); /* no scanner known on this line */
        return;
    default:
        begin_step(s, LMS_SESSION_STOP_STREAM, now_us);
        return;
    }
}

lms_session_state_t lms_session_state(const lms_session_t *s)
{
    return s->state;
}

lms_session_error_t lms_session_error(const lms_session_t *s)
{
    return s->error;
}

lms_session_cause_t lms_session_cause(const lms_session_t *s)
{
    return s->cause;
}

const lms_session_info_t *lms_session_info(const lms_session_t *s)
{
    return &s->info;
}

const lms_session_stats_t *lms_session_stats(const lms_session_t *s)
{
    return &s->stats;
}

const lms_framer_stats_t *lms_session_framer_stats(const lms_session_t *s)
{
    return lms_framer_stats(&s->framer);
}
