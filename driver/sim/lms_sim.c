/* lms_sim.c - the simulated LMS 2xx (see lms_sim.h).
 *
 * One discrete-event loop (advance) runs everything that is due by `now`
 * in time order: the next byte leaving the wire, the power-on telegram,
 * the reply of the oldest waiting command, the next scan of a stream, the
 * end of a silence, the inter-byte limit on the host's bytes. Actions that
 * must wait until some byte has left the wire (the baud switch after A0,
 * the reboot after 91, the one-shot faults after a scan) are marks on the
 * running count of sent bytes. Byte and scan times are exact fractions
 * (Bresenham-style remainders), so nothing drifts over long runs.
 */
#include "lms_sim.h"

#include <string.h>

#include "lms_encode.h"

#define STATUS_OK 0x10u          /* healthy status byte (protocol doc 1.2) */
#define PRNG_DEFAULT_SEED 0x2545F491u
#define PERMILLE 1000u
#define PPM 1000000u
#define PASSWORD_SIZE 8u
#define MODE_RESULT_OK 0x00u
#define MODE_RESULT_BAD_PASSWORD 0x01u
#define RESULT_REFUSED 0x00u
#define RESULT_ACCEPTED 0x01u
#define DEFAULT_ANGLE_DEG 180u    /* variant after every power-up [MR] */
#define DEFAULT_RESOLUTION_CDEG 50u
#define GARBAGE_TOP_BIT 0x80u     /* never STX, ACK or NAK */

/* 8N1: one byte is 10 bit times; 1e6 us per s and the permille scale give
 * the numerator of a byte's duration over bps * speed_permille. */
#define BYTE_TIME_NUM (10ull * 1000000ull * PERMILLE)
/* One mirror rotation is 1/75 s: rotations * 1e6 us * 1000 over 75 * speed. */
#define ROTATION_NUM (1000000ull * PERMILLE)
#define ROTATIONS_PER_S 75u

/* B1 data offsets (protocol doc 5.1). */
#define B1_OFF_FIRMWARE 0u
#define B1_OFF_MODE 7u
#define B1_OFF_MEAS_MODE 101u
#define B1_OFF_ANGLE 106u
#define B1_OFF_RESOLUTION 108u
#define B1_OFF_BAUD 115u
#define B1_OFF_PERMANENT_BAUD 118u
#define B1_OFF_ADDRESS 119u
#define B1_OFF_UNITS 121u
#define B1_OFF_LASER 122u
#define B1_OFF_BOOT_PROM 123u
#define B1_VERSION_SIZE 7u

/* Command data sizes after the code. */
#define MODE_DATA_SIZE 1u
#define INSTALLATION_DATA_SIZE (1u + PASSWORD_SIZE)
#define VARIANT_DATA_SIZE 4u
#define REQUEST_ALL_VALUES 0x01u

static const uint8_t k_version[B1_VERSION_SIZE] = {'V', '0', '2', '.', '1', '0', ' '};
static const char k_default_password[PASSWORD_SIZE + 1u] = "SICK_LMS";
static const char k_default_type[LMS_TYPE_TEXT_SIZE + 1u] = "LMS200;30106x;V02.10 ";

_Static_assert(sizeof k_default_type == LMS_TYPE_TEXT_SIZE + 1u, "21-character type text");
_Static_assert(B1_OFF_BOOT_PROM + B1_VERSION_SIZE <= LMS_STATUS_DATA_SIZE, "B1 layout");
_Static_assert(LMS_SIM_CMD_QUEUE <= 255u, "queue indices are 8 bits");

typedef enum {
    EV_NONE = 0,
    EV_POWER_ON,
    EV_SILENCE_END,
    EV_BYTE,
    EV_CMD,
    EV_SCAN,
    EV_FLUSH
} sim_event_t;

/* --- small helpers ------------------------------------------------------ */

static void put_le16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}

static uint16_t get_le16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

/* xorshift32 (Marsaglia 2003). */
static uint32_t prng_next(lms_sim_t *s)
{
    uint32_t x = s->prng;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    s->prng = x;
    return x;
}

static bool prng_ppm(lms_sim_t *s, uint32_t ppm)
{
    return ppm != 0u && (prng_next(s) % PPM) < ppm;
}

/* A real-scanner duration as wall time at the configured speed. */
static uint64_t scaled_us(const lms_sim_t *s, uint64_t real_us)
{
    return real_us * PERMILLE / s->config.speed_permille;
}

static uint64_t host_gap_us(const lms_sim_t *s)
{
    const uint64_t g = scaled_us(s, LMS_SIM_HOST_GAP_US);
    return g > LMS_SIM_HOST_GAP_US ? g : LMS_SIM_HOST_GAP_US;
}

static uint64_t byte_den(const lms_sim_t *s)
{
    return (uint64_t)lms_baud_bps(s->baud) * s->config.speed_permille;
}

/* Whole microseconds at or after base + (rem + num) / den. */
static uint64_t ceil_after(uint64_t base, uint64_t rem, uint64_t num, uint64_t den)
{
    const uint64_t total = rem + num;
    return base + total / den + ((total % den) != 0u ? 1u : 0u);
}

static uint16_t baud_word(lms_baud_t baud)
{
    switch (baud) {
    case LMS_BAUD_9600:
        return 0x8067u;
    case LMS_BAUD_19200:
        return 0x8033u;
    case LMS_BAUD_38400:
        return 0x8019u;
    case LMS_BAUD_500000:
        return 0x8001u;
    }
    return 0u;
}

static bool is_streaming(const lms_sim_t *s)
{
    return s->mode == (uint8_t)LMS_MODE_STREAM_ALL || s->mode == (uint8_t)LMS_MODE_STREAM_PARTIAL;
}

static uint8_t reply_address(const lms_sim_t *s)
{
    return (uint8_t)(LMS_ADDR_REPLY_BIT | s->config.address);
}

static lms_unit_t eeprom_unit(const lms_sim_t *s)
{
    return lms_config_units(&s->eeprom) == (uint8_t)LMS_UNIT_MM ? LMS_UNIT_MM : LMS_UNIT_CM;
}

/* --- the output queue and the wire -------------------------------------- */

static uint16_t ring_index(const lms_sim_t *s, uint32_t offset)
{
    return (uint16_t)(((uint32_t)s->out_head + offset) % LMS_SIM_OUT_SIZE);
}

/* Appends bytes to the queue; false (nothing queued) when they do not fit. */
static bool enqueue(lms_sim_t *s, const uint8_t *bytes, size_t len)
{
    if (len > (size_t)(LMS_SIM_OUT_SIZE - s->out_count)) {
        return false;
    }
    if (s->out_sent == s->out_count && s->wire_us < s->clock_us) {
        /* The line was idle: the first byte starts now. */
        s->wire_us = s->clock_us;
        s->wire_rem = 0u;
    }
    for (size_t i = 0u; i < len; i++) {
        s->out[ring_index(s, s->out_count)] = bytes[i];
        s->out_count++;
    }
    s->enq_seq += (uint32_t)len;
    return true;
}

static void queue_byte(lms_sim_t *s, uint8_t b)
{
    if (!enqueue(s, &b, 1u)) {
        s->stats.replies_dropped++;
    }
}

/* Ends the fraction of the wire clock at a whole microsecond, so that the
 * next byte (at a new rate, or after a gap) never starts early. */
static void wire_realign(lms_sim_t *s)
{
    if (s->wire_rem != 0u) {
        s->wire_us++;
        s->wire_rem = 0u;
    }
}

/* --- device state ------------------------------------------------------- */

static void stop_stream(lms_sim_t *s)
{
    s->have_next = false;
}

/* Power off and on again: everything but the EEPROM, the statistics, the
 * fault bookkeeping and the bytes already off the wire is reset. */
static void power_up(lms_sim_t *s)
{
    const uint16_t unsent = (uint16_t)(s->out_count - s->out_sent);
    s->out_count = s->out_sent;
    s->enq_seq -= unsent;
    wire_realign(s);
    s->switch_mark.armed = false;
    s->reboot_mark.armed = false;
    s->silence_mark.armed = false;
    s->power_mark.armed = false;
    s->hangup_mark.armed = false;
    s->silent = false;
    s->baud = s->config.power_on_baud;
    s->mode = (uint8_t)LMS_MODE_ON_REQUEST;
    s->installation = false;
    /* A real LMS powers up at 180 / 0.5; a simulator fixed to one variant
     * (a recording played back) powers up in that one, so what B1 says
     * matches the scans it sends. */
    s->angle_deg = DEFAULT_ANGLE_DEG;
    s->resolution_cdeg = DEFAULT_RESOLUTION_CDEG;
    if (s->config.fixed_angle_deg != 0u) {
        s->angle_deg = s->config.fixed_angle_deg;
        s->resolution_cdeg = s->config.fixed_resolution_cdeg;
    }
    stop_stream(s);
    s->source_done = false;
    s->cmd_count = 0u;
    s->cmd_head = 0u;
    lms_framer_init(&s->rx, LMS_FROM_HOST);
    s->powering_up = true;
    s->power_on_at_us = s->clock_us + scaled_us(s, s->config.power_on_delay_us);
}

static void reboot(lms_sim_t *s)
{
    s->stats.power_cycles++;
    power_up(s);
}

static void fire_marks(lms_sim_t *s);

/* Arms a mark on the last byte queued so far (fires at once when the
 * queue has nothing left to send). */
static void arm(lms_sim_t *s, lms_sim_mark_t *m)
{
    m->armed = true;
    m->seq = s->enq_seq;
    fire_marks(s);
}

static bool mark_due(lms_sim_mark_t *m, uint32_t done_seq)
{
    if (m->armed && m->seq == done_seq) {
        m->armed = false;
        return true;
    }
    return false;
}

static void fire_marks(lms_sim_t *s)
{
    if (mark_due(&s->switch_mark, s->done_seq) && s->baud != s->switch_baud) {
        s->baud = s->switch_baud;
        wire_realign(s);
        s->stats.baud_changes++;
    }
    if (mark_due(&s->hangup_mark, s->done_seq)) {
        s->hangup_flag = true;
    }
    if (mark_due(&s->silence_mark, s->done_seq)) {
        s->silent = true;
        s->silent_until_us = s->clock_us + scaled_us(s, s->config.faults.silence_us);
    }
    if (mark_due(&s->power_mark, s->done_seq)) {
        reboot(s);
    }
    if (mark_due(&s->reboot_mark, s->done_seq)) {
        reboot(s);
    }
}

/* The byte in front of the wire has left it. */
static void complete_byte(lms_sim_t *s)
{
    const uint64_t den = byte_den(s);
    const uint64_t total = s->wire_rem + BYTE_TIME_NUM;
    s->wire_us += total / den;
    s->wire_rem = total % den;
    s->out_baud[ring_index(s, s->out_sent)] = (uint8_t)s->baud;
    s->out_sent++;
    s->done_seq++;
    fire_marks(s);
}

/* --- replies ------------------------------------------------------------ */

/* Queues a reply telegram: payload (code and data) plus the status byte. */
static void reply(lms_sim_t *s, const uint8_t *payload, size_t len)
{
    size_t written = 0u;
    if (lms_telegram_write(s->scratch, sizeof s->scratch, reply_address(s), payload, len,
                           (int)STATUS_OK, &written) != LMS_OK) {
        s->stats.replies_dropped++;
        return;
    }
    if (!enqueue(s, s->scratch, written)) {
        s->stats.replies_dropped++;
    }
}

static void reply_not_ack(lms_sim_t *s)
{
    const uint8_t p[1] = {LMS_REPLY_NOT_ACK};
    s->stats.not_acks++;
    reply(s, p, sizeof p);
}

static void reply_mode(lms_sim_t *s, uint8_t result)
{
    const uint8_t p[2] = {LMS_REPLY_MODE, result};
    reply(s, p, sizeof p);
}

/* 90 and BA: the type text, padded with spaces to 21 characters. */
static void reply_ident(lms_sim_t *s, uint8_t code)
{
    uint8_t p[1u + LMS_TYPE_TEXT_SIZE];
    p[0] = code;
    bool ended = false;
    for (size_t i = 0u; i < LMS_TYPE_TEXT_SIZE; i++) {
        const char c = s->config.type_text[i];
        ended = ended || c == '\0';
        p[1u + i] = ended ? (uint8_t)' ' : (uint8_t)c;
    }
    reply(s, p, sizeof p);
}

/* --- streaming ---------------------------------------------------------- */

static uint32_t rotations_per_scan(const lms_sim_t *s)
{
    if (s->mode == (uint8_t)LMS_MODE_STREAM_PARTIAL || s->resolution_cdeg >= 100u) {
        return 1u;
    }
    /* Interlacing: 0.5 deg needs two rotations, 0.25 deg four (doc 4.4). */
    return s->resolution_cdeg >= 50u ? 2u : 4u;
}

/* Moves the scan due time on by one scan period (rotations at 75 Hz). */
static void next_period(lms_sim_t *s)
{
    const uint64_t den = (uint64_t)ROTATIONS_PER_S * s->config.speed_permille;
    const uint64_t total = s->scan_rem + ROTATION_NUM * rotations_per_scan(s);
    s->scan_due_us += total / den;
    s->scan_rem = total % den;
}

/* Asks the source for scan scan_k and schedules it. */
static void fetch_next(lms_sim_t *s)
{
    s->have_next = false;
    if (s->source_done) {
        return;
    }
    if (s->config.scan_source == NULL) {
        s->source_done = true;
        return;
    }
    size_t len = 0u;
    uint32_t gap_us = 0u;
    const bool partial = s->mode == (uint8_t)LMS_MODE_STREAM_PARTIAL;
    const bool ok = s->config.scan_source(s->config.scan_ctx, s->scan_k, s->angle_deg,
                                          s->resolution_cdeg, partial, eeprom_unit(s),
                                          reply_address(s), s->next_scan, sizeof s->next_scan,
                                          &len, &gap_us);
    if (!ok || len == 0u || len > sizeof s->next_scan) {
        s->source_done = true;
        return;
    }
    s->next_len = (uint16_t)len;
    if (gap_us == 0u) {
        next_period(s);
    } else {
        s->scan_due_us += scaled_us(s, gap_us);
    }
    s->have_next = true;
}

static void start_stream(lms_sim_t *s)
{
    s->scan_k = 0u;
    s->source_done = false;
    s->scan_due_us = s->clock_us;
    s->scan_rem = 0u;
    fetch_next(s);
}

static uint64_t scan_time(const lms_sim_t *s)
{
    const uint64_t den = (uint64_t)ROTATIONS_PER_S * s->config.speed_permille;
    return ceil_after(s->scan_due_us, s->scan_rem, 0u, den);
}

/* One-shot faults counted in streamed scans: armed on the scan just queued. */
static void check_scan_faults(lms_sim_t *s)
{
    const lms_sim_faults_t *f = &s->config.faults;
    if (!s->hangup_done && f->hangup_after_scans != 0u && s->streamed >= f->hangup_after_scans) {
        s->hangup_done = true;
        arm(s, &s->hangup_mark);
    }
    if (!s->silence_done && f->silence_after_scans != 0u &&
        s->streamed >= f->silence_after_scans) {
        s->silence_done = true;
        arm(s, &s->silence_mark);
    }
    if (!s->power_cycle_done && f->power_cycle_after_scans != 0u &&
        s->streamed >= f->power_cycle_after_scans) {
        s->power_cycle_done = true;
        arm(s, &s->power_mark);
    }
}

/* A scan is due. A busy line skips this scan period: the scan waits for
 * the next one (the source is not asked again, so k numbers the scans
 * sent). */
static void emit_scan(lms_sim_t *s)
{
    const bool line_idle = s->out_sent == s->out_count;
    if (!line_idle || !enqueue(s, s->next_scan, s->next_len)) {
        s->stats.scans_skipped++;
        next_period(s);
        return;
    }
    s->stats.scans_sent++;
    s->streamed++;
    s->scan_k++;
    fetch_next(s);
    check_scan_faults(s);
}

/* --- commands ----------------------------------------------------------- */

static bool password_matches(const lms_sim_t *s, const uint8_t *pw)
{
    for (size_t i = 0u; i < PASSWORD_SIZE; i++) {
        if (pw[i] != (uint8_t)s->config.password[i]) {
            return false;
        }
    }
    return true;
}

static bool baud_of_mode(uint8_t mode, lms_baud_t *baud)
{
    switch (mode) {
    case LMS_MODE_BAUD_9600:
        *baud = LMS_BAUD_9600;
        return true;
    case LMS_MODE_BAUD_19200:
        *baud = LMS_BAUD_19200;
        return true;
    case LMS_MODE_BAUD_38400:
        *baud = LMS_BAUD_38400;
        return true;
    case LMS_MODE_BAUD_500000:
        *baud = LMS_BAUD_500000;
        return true;
    default:
        return false;
    }
}

static void leave_installation(lms_sim_t *s)
{
    if (s->installation) {
        s->installation = false;
        s->mode = (uint8_t)LMS_MODE_ON_REQUEST;
    }
}

static void cmd_mode(lms_sim_t *s, const lms_sim_cmd_t *c)
{
    const uint8_t mode = c->data[0];
    lms_baud_t baud = LMS_BAUD_9600;
    if (mode == (uint8_t)LMS_MODE_INSTALLATION) {
        if (c->data_len != INSTALLATION_DATA_SIZE) {
            reply_not_ack(s);
        } else if (!password_matches(s, &c->data[1])) {
            reply_mode(s, MODE_RESULT_BAD_PASSWORD);
        } else {
            reply_mode(s, MODE_RESULT_OK);
            stop_stream(s);
            s->installation = true;
            s->mode = (uint8_t)LMS_MODE_INSTALLATION;
        }
        return;
    }
    if (c->data_len != MODE_DATA_SIZE) {
        reply_not_ack(s);
        return;
    }
    if (mode == (uint8_t)LMS_MODE_STREAM_ALL || mode == (uint8_t)LMS_MODE_STREAM_PARTIAL) {
        reply_mode(s, MODE_RESULT_OK);
        s->installation = false;
        if (s->mode != mode) {
            s->mode = mode;
            start_stream(s);
        }
    } else if (mode == (uint8_t)LMS_MODE_ON_REQUEST) {
        reply_mode(s, MODE_RESULT_OK);
        s->installation = false;
        s->mode = mode;
        stop_stream(s);
    } else if (baud_of_mode(mode, &baud)) {
        /* The A0 goes out at the old rate; switch once it is on the wire. */
        reply_mode(s, MODE_RESULT_OK);
        leave_installation(s);
        if (baud != s->baud || s->switch_mark.armed) {
            s->switch_baud = baud;
            arm(s, &s->switch_mark);
        }
    } else {
        reply_not_ack(s);
    }
}

static void cmd_request_values(lms_sim_t *s, const lms_sim_cmd_t *c)
{
    if (c->data_len != 1u || c->data[0] != REQUEST_ALL_VALUES ||
        s->mode != (uint8_t)LMS_MODE_ON_REQUEST || s->config.scan_source == NULL) {
        reply_not_ack(s);
        return;
    }
    size_t len = 0u;
    uint32_t gap_us = 0u;
    const bool ok = s->config.scan_source(s->config.scan_ctx, s->scan_k, s->angle_deg,
                                          s->resolution_cdeg, false, eeprom_unit(s),
                                          reply_address(s), s->scratch, sizeof s->scratch, &len,
                                          &gap_us);
    if (!ok || len == 0u || len > sizeof s->scratch) {
        reply_not_ack(s);
        return;
    }
    s->scan_k++;
    if (!enqueue(s, s->scratch, len)) {
        s->stats.replies_dropped++;
    }
}

static void cmd_status(lms_sim_t *s)
{
    uint8_t p[1u + LMS_STATUS_DATA_SIZE];
    memset(p, 0, sizeof p);
    p[0] = LMS_REPLY_STATUS;
    uint8_t *d = &p[1];
    memcpy(&d[B1_OFF_FIRMWARE], k_version, B1_VERSION_SIZE);
    d[B1_OFF_MODE] = s->mode;
    d[B1_OFF_MEAS_MODE] = lms_config_meas_mode(&s->eeprom);
    put_le16(&d[B1_OFF_ANGLE], s->angle_deg);
    put_le16(&d[B1_OFF_RESOLUTION], s->resolution_cdeg);
    put_le16(&d[B1_OFF_BAUD], baud_word(s->baud));
    d[B1_OFF_PERMANENT_BAUD] = s->config.power_on_baud != LMS_BAUD_9600 ? 1u : 0u;
    d[B1_OFF_ADDRESS] = s->config.address;
    d[B1_OFF_UNITS] = lms_config_units(&s->eeprom);
    d[B1_OFF_LASER] = 1u;
    memcpy(&d[B1_OFF_BOOT_PROM], k_version, B1_VERSION_SIZE);
    reply(s, p, sizeof p);
}

static void cmd_variant(lms_sim_t *s, const lms_sim_cmd_t *c)
{
    if (c->data_len != VARIANT_DATA_SIZE || is_streaming(s)) {
        reply_not_ack(s);
        return;
    }
    const uint16_t angle = get_le16(&c->data[0]);
    const uint16_t res = get_le16(&c->data[2]);
    const lms_sim_config_t *cfg = &s->config;
    const bool fixed_ok = cfg->fixed_angle_deg == 0u ||
                          (angle == cfg->fixed_angle_deg && res == cfg->fixed_resolution_cdeg);
    uint8_t result = RESULT_REFUSED;
    if (lms_variant_is_legal(angle, res) && fixed_ok) {
        s->angle_deg = angle;
        s->resolution_cdeg = res;
        result = RESULT_ACCEPTED;
    }
    uint8_t p[6];
    p[0] = LMS_REPLY_VARIANT;
    p[1] = result;
    put_le16(&p[2], s->angle_deg);
    put_le16(&p[4], s->resolution_cdeg);
    reply(s, p, sizeof p);
}

static void cmd_config_read(lms_sim_t *s)
{
    uint8_t p[1u + LMS_CONFIG_SIZE_MAX];
    p[0] = LMS_REPLY_CONFIG;
    memcpy(&p[1], s->eeprom.block, s->eeprom.size);
    reply(s, p, 1u + (size_t)s->eeprom.size);
}

static void cmd_config_write(lms_sim_t *s, const lms_sim_cmd_t *c)
{
    if (!s->installation || (c->data_len != LMS_CONFIG_SIZE_OLD &&
                             c->data_len != LMS_CONFIG_SIZE_NEW)) {
        reply_not_ack(s);
        return;
    }
    const uint8_t units = c->data[LMS_CONFIG_OFF_UNITS];
    const bool ok = c->data_len == s->eeprom.size &&
                    (units == (uint8_t)LMS_UNIT_CM || units == (uint8_t)LMS_UNIT_MM) &&
                    lms_meas_mode_bits(c->data[LMS_CONFIG_OFF_MEAS_MODE]) != 0u;
    if (ok) {
        memcpy(s->eeprom.block, c->data, c->data_len);
        s->stats.config_writes++;
    }
    uint8_t p[2u + LMS_CONFIG_SIZE_MAX];
    p[0] = LMS_REPLY_CONFIG_WRITE;
    p[1] = ok ? RESULT_ACCEPTED : RESULT_REFUSED;
    memcpy(&p[2], c->data, c->data_len);
    reply(s, p, 2u + (size_t)c->data_len);
}

static void run_command(lms_sim_t *s, const lms_sim_cmd_t *c)
{
    switch (c->code) {
    case LMS_CMD_RESET: {
        const uint8_t p[1] = {LMS_REPLY_RESET_ACK};
        reply(s, p, sizeof p);
        arm(s, &s->reboot_mark); /* reboots once the 91 is on the wire */
        break;
    }
    case LMS_CMD_MODE:
        cmd_mode(s, c);
        break;
    case LMS_CMD_REQUEST_VALUES:
        cmd_request_values(s, c);
        break;
    case LMS_CMD_STATUS:
        cmd_status(s);
        break;
    case LMS_CMD_ERRORS: {
        const uint8_t p[1] = {LMS_REPLY_ERRORS}; /* no (type, number) pairs */
        reply(s, p, sizeof p);
        break;
    }
    case LMS_CMD_TYPE:
        reply_ident(s, LMS_REPLY_TYPE);
        break;
    case LMS_CMD_VARIANT:
        cmd_variant(s, c);
        break;
    case LMS_CMD_CONFIG_READ:
        cmd_config_read(s);
        break;
    case LMS_CMD_CONFIG_WRITE:
        cmd_config_write(s, c);
        break;
    default: /* includes 66: never obeyed */
        reply_not_ack(s);
        break;
    }
}

static uint64_t cmd_due(const lms_sim_t *s)
{
    const lms_sim_cmd_t *c = &s->cmds[s->cmd_head];
    const uint64_t start = c->recv_us > s->busy_until_us ? c->recv_us : s->busy_until_us;
    const uint32_t delay = (c->code == LMS_CMD_CONFIG_WRITE && s->installation)
                               ? s->config.config_write_delay_us
                               : s->config.reply_delay_us;
    return start + scaled_us(s, delay);
}

static void pop_command(lms_sim_t *s)
{
    lms_sim_cmd_t c = s->cmds[s->cmd_head];
    s->cmd_head = (uint8_t)((s->cmd_head + 1u) % LMS_SIM_CMD_QUEUE);
    s->cmd_count--;
    s->busy_until_us = s->clock_us;
    run_command(s, &c);
}

/* A CRC-valid telegram from the host's framer. */
static void on_host_telegram(lms_sim_t *s, const uint8_t *bytes, size_t len)
{
    lms_telegram_t t;
    if (lms_telegram_parse(bytes, len, &t) != LMS_OK || t.is_reply) {
        s->stats.host_framing++; /* the framer already checked it: defensive */
        return;
    }
    s->stats.host_telegrams++;
    if (t.address != LMS_ADDR_BROADCAST && t.address != s->config.address) {
        s->stats.other_address++;
        return;
    }
    const uint32_t nak_percent = s->config.faults.nak_percent;
    if (nak_percent != 0u && prng_next(s) % 100u < nak_percent) {
        s->stats.naks_injected++;
        queue_byte(s, LMS_NAK);
        return;
    }
    if (s->cmd_count >= LMS_SIM_CMD_QUEUE) {
        s->stats.cmds_dropped++;
        return;
    }
    lms_sim_cmd_t *c = &s->cmds[(s->cmd_head + s->cmd_count) % LMS_SIM_CMD_QUEUE];
    c->recv_us = s->clock_us;
    c->code = t.code;
    c->data_len = t.data_len;
    memset(c->data, 0, sizeof c->data);
    const size_t keep = t.data_len < sizeof c->data ? t.data_len : sizeof c->data;
    memcpy(c->data, t.data, keep);
    s->cmd_count++;
    queue_byte(s, LMS_ACK);
}

static void on_rx_event(lms_sim_t *s, lms_framer_event_t ev)
{
    switch (ev) {
    case LMS_FRAMER_TELEGRAM: {
        size_t len = 0u;
        const uint8_t *t = lms_framer_telegram(&s->rx, &len);
        if (t != NULL) {
            on_host_telegram(s, t, len);
        }
        break;
    }
    case LMS_FRAMER_CRC_ERROR:
        s->stats.host_bad++;
        queue_byte(s, LMS_NAK);
        break;
    case LMS_FRAMER_LENGTH_ERROR:
    case LMS_FRAMER_TRUNCATED:
        s->stats.host_framing++;
        break;
    default:
        break;
    }
}

/* The host's bytes stopped mid-telegram for longer than the limit. */
static void flush_host(lms_sim_t *s)
{
    for (uint32_t i = 0u; i < 2u * LMS_FRAMER_BUF_SIZE + 8u; i++) {
        const lms_framer_event_t ev = lms_framer_flush(&s->rx);
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        on_rx_event(s, ev);
    }
}

/* --- the event loop ----------------------------------------------------- */

static void consider(sim_event_t ev, uint64_t at, sim_event_t *best, uint64_t *best_at)
{
    if (*best == EV_NONE || at < *best_at) {
        *best = ev;
        *best_at = at;
    }
}

/* The next thing to do and when; ties go to the earlier candidate (a byte
 * leaving the wire first, so that a scan due at that very moment finds the
 * line free). */
static sim_event_t next_event(const lms_sim_t *s, uint64_t *at)
{
    *at = UINT64_MAX;
    if (s->powering_up) {
        *at = s->power_on_at_us;
        return EV_POWER_ON;
    }
    if (s->silent) {
        *at = s->silent_until_us;
        return EV_SILENCE_END;
    }
    sim_event_t best = EV_NONE;
    if (s->out_sent < s->out_count) {
        consider(EV_BYTE, ceil_after(s->wire_us, s->wire_rem, BYTE_TIME_NUM, byte_den(s)), &best,
                 at);
    }
    if (s->cmd_count > 0u) {
        consider(EV_CMD, cmd_due(s), &best, at);
    }
    if (s->have_next && is_streaming(s)) {
        consider(EV_SCAN, scan_time(s), &best, at);
    }
    if (lms_framer_pending(&s->rx) > 0u) {
        consider(EV_FLUSH, s->last_rx_us + host_gap_us(s), &best, at);
    }
    return best;
}

static void end_silence(lms_sim_t *s)
{
    const uint64_t end = s->silent_until_us;
    s->silent = false;
    /* Whatever waited restarts at the end of the silence. */
    if (s->wire_us < end) {
        s->wire_us = end;
        s->wire_rem = 0u;
    }
    if (s->scan_due_us < end) {
        s->scan_due_us = end;
        s->scan_rem = 0u;
    }
    if (s->busy_until_us < end) {
        s->busy_until_us = end;
    }
}

static void advance(lms_sim_t *s, uint64_t now_us)
{
    if (now_us < s->last_us) {
        now_us = s->last_us;
    }
    s->last_us = now_us;
    for (uint32_t step = 0u; step < LMS_SIM_MAX_STEPS; step++) {
        uint64_t at = 0u;
        const sim_event_t ev = next_event(s, &at);
        if (ev == EV_NONE || at > now_us) {
            s->clock_us = now_us;
            return;
        }
        if (at > s->clock_us) {
            s->clock_us = at;
        }
        switch (ev) {
        case EV_POWER_ON:
            s->powering_up = false;
            reply_ident(s, LMS_REPLY_POWER_ON);
            break;
        case EV_SILENCE_END:
            end_silence(s);
            break;
        case EV_BYTE:
            complete_byte(s);
            break;
        case EV_CMD:
            pop_command(s);
            break;
        case EV_SCAN:
            emit_scan(s);
            break;
        case EV_FLUSH:
            flush_host(s);
            break;
        case EV_NONE:
        default:
            break;
        }
    }
    /* Step limit reached: the rest is done by the next call. */
}

/* --- handing bytes to the host ------------------------------------------ */

static uint8_t garbage_byte(lms_sim_t *s)
{
    s->garble_count++;
    const unsigned mix = (unsigned)s->garble_last ^ ((unsigned)s->garble_count * 0x35u);
    return (uint8_t)(GARBAGE_TOP_BIT | (mix & 0x7Fu));
}

/* Takes the oldest sent byte off the queue; writes at most one byte to
 * out (room for it is guaranteed), the rest goes to the owed counters. */
static void hand_one(lms_sim_t *s, lms_baud_t host_baud, uint8_t *out, size_t *n)
{
    uint8_t b = s->out[s->out_head];
    const uint8_t rate = s->out_baud[s->out_head];
    s->out_head = (uint16_t)((s->out_head + 1u) % LMS_SIM_OUT_SIZE);
    s->out_count--;
    s->out_sent--;
    if (lms_baud_bps(host_baud) == 0u || rate != (uint8_t)host_baud) {
        /* One garbage byte per host byte time that this byte lasted. */
        const uint32_t sent_bps = lms_baud_bps((lms_baud_t)rate);
        s->garble_acc += lms_baud_bps(host_baud);
        s->garble_owed += (uint32_t)(s->garble_acc / sent_bps);
        s->garble_acc %= sent_bps;
        s->garble_last = b;
        return;
    }
    const lms_sim_faults_t *f = &s->config.faults;
    if (prng_ppm(s, f->drop_ppm)) {
        s->stats.bytes_dropped++;
        return;
    }
    if (prng_ppm(s, f->flip_ppm)) {
        b ^= (uint8_t)(1u << (prng_next(s) % 8u));
        s->stats.bytes_flipped++;
    }
    out[(*n)++] = b;
    s->stats.bytes_out++;
    if (prng_ppm(s, f->insert_ppm)) {
        s->held = (uint8_t)(prng_next(s) >> 24);
        s->has_held = true;
        s->stats.bytes_inserted++;
    }
}

/* --- public ------------------------------------------------------------- */

void lms_sim_defaults(lms_sim_config_t *config)
{
    if (config == NULL) {
        return;
    }
    memset(config, 0, sizeof *config);
    config->address = 0u;
    config->power_on_baud = LMS_BAUD_9600;
    config->power_on_delay_us = 100000u;
    config->reply_delay_us = 10000u;
    config->config_write_delay_us = 1000000u;
    memcpy(config->type_text, k_default_type, sizeof config->type_text);
    memcpy(config->password, k_default_password, sizeof config->password);
    config->unit = LMS_UNIT_CM;
    config->meas_mode = (uint8_t)LMS_MEAS_8M_FIELDS_DAZZLE;
    config->config_size = (uint8_t)LMS_CONFIG_SIZE_NEW;
    config->speed_permille = PERMILLE;
}

static bool password_valid(const char *pw)
{
    for (size_t i = 0u; i < PASSWORD_SIZE; i++) {
        if (pw[i] == '\0') {
            return false;
        }
    }
    return pw[PASSWORD_SIZE] == '\0';
}

void lms_sim_init(lms_sim_t *sim, const lms_sim_config_t *config, uint64_t now_us)
{
    if (sim == NULL) {
        return;
    }
    memset(sim, 0, sizeof *sim);
    if (config != NULL) {
        sim->config = *config;
    } else {
        lms_sim_defaults(&sim->config);
    }
    lms_sim_config_t *c = &sim->config;
    c->address = (uint8_t)(c->address & (uint8_t)~LMS_ADDR_REPLY_BIT);
    if (lms_baud_bps(c->power_on_baud) == 0u) {
        c->power_on_baud = LMS_BAUD_9600;
    }
    c->type_text[LMS_TYPE_TEXT_SIZE] = '\0';
    if (!password_valid(c->password)) {
        memcpy(c->password, k_default_password, sizeof c->password);
    }
    if (c->unit != LMS_UNIT_CM && c->unit != LMS_UNIT_MM) {
        c->unit = LMS_UNIT_CM;
    }
    if (lms_meas_mode_bits(c->meas_mode) == 0u) {
        c->meas_mode = (uint8_t)LMS_MEAS_8M_FIELDS_DAZZLE;
    }
    if (c->config_size != LMS_CONFIG_SIZE_OLD && c->config_size != LMS_CONFIG_SIZE_NEW) {
        c->config_size = (uint8_t)LMS_CONFIG_SIZE_NEW;
    }
    if (c->speed_permille == 0u) {
        c->speed_permille = PERMILLE;
    }
    sim->eeprom.size = c->config_size;
    sim->eeprom.block[LMS_CONFIG_OFF_MEAS_MODE] = c->meas_mode;
    sim->eeprom.block[LMS_CONFIG_OFF_UNITS] = (uint8_t)c->unit;
    sim->prng = c->faults.seed != 0u ? c->faults.seed : PRNG_DEFAULT_SEED;
    sim->last_us = now_us;
    sim->clock_us = now_us;
    sim->wire_us = now_us;
    power_up(sim);
}

void lms_sim_receive(lms_sim_t *sim, const uint8_t *bytes, size_t len, lms_baud_t host_baud,
                     uint64_t now_us)
{
    if (sim == NULL) {
        return;
    }
    advance(sim, now_us);
    if (bytes == NULL || len == 0u) {
        return;
    }
    if (sim->powering_up || sim->silent) {
        sim->stats.host_ignored += (uint32_t)len;
        return;
    }
    if (host_baud != sim->baud) {
        sim->stats.garbled_bytes += (uint32_t)len;
        return;
    }
    sim->last_rx_us = sim->clock_us;
    /* Every framer call uses a byte or drops a buffered one, so this many
     * calls always suffice. */
    const size_t limit = len < SIZE_MAX / 2u - 4u * LMS_FRAMER_BUF_SIZE
                             ? 2u * len + 4u * LMS_FRAMER_BUF_SIZE
                             : SIZE_MAX;
    size_t off = 0u;
    for (size_t i = 0u; i < limit; i++) {
        size_t used = 0u;
        const lms_framer_event_t ev = lms_framer_feed(&sim->rx, &bytes[off], len - off, &used);
        off += used;
        if (ev == LMS_FRAMER_NEED_MORE) {
            break;
        }
        on_rx_event(sim, ev);
    }
}

size_t lms_sim_transmit(lms_sim_t *sim, lms_baud_t host_baud, uint64_t now_us, uint8_t *out,
                        size_t cap)
{
    if (sim == NULL) {
        return 0u;
    }
    if (out == NULL) {
        cap = 0u;
    }
    advance(sim, now_us);
    size_t n = 0u;
    for (uint32_t i = 0u; i <= LMS_SIM_OUT_SIZE; i++) {
        while (n < cap && sim->garble_owed > 0u) {
            out[n++] = garbage_byte(sim);
            sim->garble_owed--;
            sim->stats.bytes_out++;
        }
        if (n < cap && sim->has_held) {
            out[n++] = sim->held;
            sim->has_held = false;
            sim->stats.bytes_out++;
        }
        if (n >= cap || sim->out_sent == 0u || sim->garble_owed > 0u || sim->has_held) {
            break;
        }
        hand_one(sim, host_baud, out, &n);
    }
    return n;
}

uint64_t lms_sim_next_event_us(const lms_sim_t *sim, uint64_t now_us)
{
    if (sim == NULL) {
        return UINT64_MAX;
    }
    if (sim->out_sent > 0u || sim->garble_owed > 0u || sim->has_held) {
        return now_us;
    }
    uint64_t at = 0u;
    if (next_event(sim, &at) == EV_NONE) {
        return UINT64_MAX;
    }
    return at > now_us ? at : now_us;
}

/* AFTER more scans from now, as the absolute count check_scan_faults
 * compares with (saturating; 0 stays "never"). */
static uint32_t after_now(const lms_sim_t *s, uint32_t after)
{
    if (after == 0u) {
        return 0u;
    }
    return after > UINT32_MAX - s->streamed ? UINT32_MAX : s->streamed + after;
}

void lms_sim_set_faults(lms_sim_t *sim, const lms_sim_faults_t *faults)
{
    if (sim == NULL || faults == NULL) {
        return;
    }
    const uint32_t seed = sim->config.faults.seed;
    sim->config.faults = *faults;
    sim->config.faults.seed = seed;
    sim->config.faults.silence_after_scans = after_now(sim, faults->silence_after_scans);
    sim->config.faults.power_cycle_after_scans = after_now(sim, faults->power_cycle_after_scans);
    sim->config.faults.hangup_after_scans = after_now(sim, faults->hangup_after_scans);
    sim->silence_done = false;
    sim->power_cycle_done = false;
    sim->hangup_done = false;
}

lms_baud_t lms_sim_baud(const lms_sim_t *sim)
{
    return sim != NULL ? sim->baud : LMS_BAUD_9600;
}

bool lms_sim_take_hangup(lms_sim_t *sim)
{
    if (sim == NULL || !sim->hangup_flag) {
        return false;
    }
    sim->hangup_flag = false;
    return true;
}

const lms_sim_stats_t *lms_sim_stats(const lms_sim_t *sim)
{
    return sim != NULL ? &sim->stats : NULL;
}

/* --- fault specifications ------------------------------------------------ */

#define FAULT_SPEC_MAX 256u
#define SILENCE_MS_MAX (UINT32_MAX / 1000u)

/* Strict decimal in spec[from, to): digits only, at least one, <= UINT32_MAX. */
static bool parse_u32(const char *spec, size_t from, size_t to, uint32_t *out)
{
    if (to <= from) {
        return false;
    }
    uint32_t v = 0u;
    for (size_t i = from; i < to; i++) {
        const char ch = spec[i];
        if (ch < '0' || ch > '9') {
            return false;
        }
        const uint32_t d = (uint32_t)(ch - '0');
        if (v > (UINT32_MAX - d) / 10u) {
            return false;
        }
        v = v * 10u + d;
    }
    *out = v;
    return true;
}

static bool key_is(const char *spec, size_t from, size_t to, const char *key)
{
    const size_t n = strlen(key);
    return to - from == n && memcmp(&spec[from], key, n) == 0;
}

/* One KEY=VALUE item in spec[from, to). */
static bool parse_item(const char *spec, size_t from, size_t to, lms_sim_faults_t *f)
{
    size_t eq = from;
    while (eq < to && spec[eq] != '=') {
        eq++;
    }
    if (eq == to) {
        return false;
    }
    const size_t v0 = eq + 1u;
    uint32_t v = 0u;
    if (key_is(spec, from, eq, "silence")) {
        size_t colon = v0;
        while (colon < to && spec[colon] != ':') {
            colon++;
        }
        uint32_t ms = 0u;
        if (colon == to || !parse_u32(spec, v0, colon, &v) ||
            !parse_u32(spec, colon + 1u, to, &ms) || ms > SILENCE_MS_MAX) {
            return false;
        }
        f->silence_after_scans = v;
        f->silence_us = ms * 1000u;
        return true;
    }
    if (!parse_u32(spec, v0, to, &v)) {
        return false;
    }
    if (key_is(spec, from, eq, "drop") && v <= PPM) {
        f->drop_ppm = v;
    } else if (key_is(spec, from, eq, "flip") && v <= PPM) {
        f->flip_ppm = v;
    } else if (key_is(spec, from, eq, "insert") && v <= PPM) {
        f->insert_ppm = v;
    } else if (key_is(spec, from, eq, "nak") && v <= 100u) {
        f->nak_percent = v;
    } else if (key_is(spec, from, eq, "power")) {
        f->power_cycle_after_scans = v;
    } else if (key_is(spec, from, eq, "hangup")) {
        f->hangup_after_scans = v;
    } else if (key_is(spec, from, eq, "seed")) {
        f->seed = v;
    } else {
        return false;
    }
    return true;
}

bool lms_sim_parse_faults(const char *spec, lms_sim_faults_t *out)
{
    if (out != NULL) {
        memset(out, 0, sizeof *out);
    }
    if (spec == NULL || out == NULL) {
        return false;
    }
    size_t len = 0u;
    while (len <= FAULT_SPEC_MAX && spec[len] != '\0') {
        len++;
    }
    if (len > FAULT_SPEC_MAX) {
        return false;
    }
    lms_sim_faults_t f;
    memset(&f, 0, sizeof f);
    size_t from = 0u;
    /* Every item ends at a comma or at the end; an empty item fails. */
    while (from < len) {
        size_t to = from;
        while (to < len && spec[to] != ',') {
            to++;
        }
        if (!parse_item(spec, from, to, &f) || (to < len && to + 1u == len)) {
            return false;
        }
        from = to + 1u;
    }
    *out = f;
    return true;
}
