/* test_lms_decode_replies.c - the reply decoders A0, 90, BA, 91, 92, B1,
 * BB, F4, F7 (lms_decode.h) on the vectors and on built telegrams, and the
 * error contract every decoder (B0 included) shares: wrong code, wrong
 * size for the code, bad CRC, broken framing, NULL pointers, and *out
 * zeroed on every error.
 */
#include <string.h>

#include "lms_decode.h"
#include "lms_test_util.h"
#include "lms_vectors.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

static const lms_vector_t *vec(const char *id)
{
    const lms_vector_t *v = lms_vector_find(id);
    TEST_ASSERT_NOT_NULL_MESSAGE(v, id);
    return v;
}

/* --- the decoders behind one signature ----------------------------------- */

typedef union {
    lms_scan_t scan;
    lms_mode_reply_t mode;
    lms_ident_t ident;
    lms_bare_reply_t bare;
    lms_device_status_t status;
    lms_variant_reply_t variant;
    lms_config_reply_t config;
    lms_config_write_reply_t config_write;
} any_out_t;

static any_out_t g_out;

typedef lms_status_t (*decode_fn)(const uint8_t *bytes, size_t len, any_out_t *out);

static lms_status_t call_scan(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_scan(b, n, o != NULL ? &o->scan : NULL);
}
static lms_status_t call_mode(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_mode_reply(b, n, o != NULL ? &o->mode : NULL);
}
static lms_status_t call_power_on(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_power_on(b, n, o != NULL ? &o->ident : NULL);
}
static lms_status_t call_type(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_type(b, n, o != NULL ? &o->ident : NULL);
}
static lms_status_t call_reset_ack(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_reset_ack(b, n, o != NULL ? &o->bare : NULL);
}
static lms_status_t call_not_ack(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_not_ack(b, n, o != NULL ? &o->bare : NULL);
}
static lms_status_t call_status(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_status(b, n, o != NULL ? &o->status : NULL);
}
static lms_status_t call_variant(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_variant_reply(b, n, o != NULL ? &o->variant : NULL);
}
static lms_status_t call_config(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_config(b, n, o != NULL ? &o->config : NULL);
}
static lms_status_t call_config_write(const uint8_t *b, size_t n, any_out_t *o)
{
    return lms_decode_config_write_reply(b, n, o != NULL ? &o->config_write : NULL);
}

typedef struct {
    const char *name;
    decode_fn call;
    size_t out_size;
    uint8_t code;
    size_t good_l;      /* a legal length field (code .. status) */
    size_t bad_l[5];    /* illegal length fields for the code, 0-terminated */
} decoder_t;

/* Data bytes of the built "good" telegrams: after the code, a plausible
 * field pattern; the B0 uses a count word of N = 3. */
static const decoder_t k_decoders[] = {
    {"B0", call_scan, sizeof(lms_scan_t), 0xB0u, 10u, {2u, 3u, 9u, 11u, 13u}},
    {"A0", call_mode, sizeof(lms_mode_reply_t), 0xA0u, 3u, {2u, 4u, 5u, 0u, 0u}},
    {"90", call_power_on, sizeof(lms_ident_t), 0x90u, 23u, {2u, 22u, 24u, 0u, 0u}},
    {"BA", call_type, sizeof(lms_ident_t), 0xBAu, 23u, {2u, 22u, 24u, 0u, 0u}},
    {"91", call_reset_ack, sizeof(lms_bare_reply_t), 0x91u, 2u, {3u, 4u, 0u, 0u, 0u}},
    {"92", call_not_ack, sizeof(lms_bare_reply_t), 0x92u, 2u, {3u, 23u, 0u, 0u, 0u}},
    {"B1", call_status, sizeof(lms_device_status_t), 0xB1u, 154u, {2u, 153u, 155u, 0u, 0u}},
    {"BB", call_variant, sizeof(lms_variant_reply_t), 0xBBu, 7u, {2u, 6u, 8u, 0u, 0u}},
    {"F4", call_config, sizeof(lms_config_reply_t), 0xF4u, 36u, {2u, 33u, 35u, 37u, 0u}},
    {"F7", call_config_write, sizeof(lms_config_write_reply_t), 0xF7u, 37u,
     {3u, 34u, 36u, 38u, 0u}},
};
#define N_DECODERS (sizeof k_decoders / sizeof k_decoders[0])

/* A telegram with the decoder's code and length field l, status 0x10,
 * good CRC; data bytes that every decoder accepts when l is legal. */
static size_t build_for(const decoder_t *d, size_t l, uint8_t address, uint8_t *out, size_t cap)
{
    uint8_t payload[LMS_LENGTH_MAX];
    memset(payload, 0x31, sizeof payload); /* printable, non-zero */
    payload[0] = d->code;
    if (d->code == 0xB0u && l >= 3u) {
        payload[1] = 0x03u; /* N = 3, cm */
        payload[2] = 0x00u;
    }
    if (d->code == 0xA0u) {
        payload[1] = 0x00u; /* result ok */
    }
    if (d->code == 0xBBu) {
        payload[1] = 0x01u;
    }
    if (d->code == 0xF7u) {
        payload[1] = 0x01u;
    }
    payload[l - 1u] = 0x10u;
    return tu_telegram(out, cap, address, payload, l);
}

static void expect_error(const decoder_t *d, const uint8_t *b, size_t n, lms_status_t want,
                         const char *what)
{
    char msg[80];
    (void)snprintf(msg, sizeof msg, "%s: %s", d->name, what);
    memset(&g_out, 0xA5, sizeof g_out);
    TEST_ASSERT_EQUAL_INT_MESSAGE(want, d->call(b, n, &g_out), msg);
    TEST_ASSERT_TRUE_MESSAGE(tu_all_zero(&g_out, d->out_size), msg);
}

/* The built "good" telegram of each decoder decodes (so the error cases
 * below fail for the reason they name). */
static void test_lms_decode_replies_good_builds_decode(void)
{
    uint8_t b[LMS_TELEGRAM_MAX];
    for (size_t i = 0u; i < N_DECODERS; i++) {
        const decoder_t *d = &k_decoders[i];
        const size_t n = build_for(d, d->good_l, 0x81u, b, sizeof b);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, d->call(b, n, &g_out), d->name);
    }
}

static void test_lms_decode_replies_wrong_code(void)
{
    uint8_t b[LMS_TELEGRAM_MAX];
    for (size_t i = 0u; i < N_DECODERS; i++) {
        const decoder_t *d = &k_decoders[i];
        for (size_t j = 0u; j < N_DECODERS; j++) {
            if (j == i) {
                continue;
            }
            /* Another decoder's valid telegram. */
            const size_t n = build_for(&k_decoders[j], k_decoders[j].good_l, 0x80u, b, sizeof b);
            expect_error(d, b, n, LMS_ERR_CODE, k_decoders[j].name);
        }
        /* An unknown code (B2, errors) with the decoder's own length. */
        size_t n = build_for(d, d->good_l, 0x80u, b, sizeof b);
        b[4] = LMS_REPLY_ERRORS;
        tu_fix_crc(b, n);
        expect_error(d, b, n, LMS_ERR_CODE, "code B2");
        /* A host command is not a reply. */
        const lms_vector_t *v08 = vec("V08");
        expect_error(d, v08->bytes, v08->len, LMS_ERR_CODE, "V08 status request");
    }
}

/* Right code, wrong length field for it, correct CRC: LMS_ERR_SIZE. */
static void test_lms_decode_replies_wrong_size(void)
{
    uint8_t b[LMS_TELEGRAM_MAX];
    for (size_t i = 0u; i < N_DECODERS; i++) {
        const decoder_t *d = &k_decoders[i];
        for (size_t k = 0u; k < 5u && d->bad_l[k] != 0u; k++) {
            const size_t n = build_for(d, d->bad_l[k], 0x80u, b, sizeof b);
            char what[24];
            (void)snprintf(what, sizeof what, "L %u", (unsigned)d->bad_l[k]);
            expect_error(d, b, n, LMS_ERR_SIZE, what);
        }
    }
}

static void test_lms_decode_replies_bad_crc(void)
{
    uint8_t b[LMS_TELEGRAM_MAX];
    for (size_t i = 0u; i < N_DECODERS; i++) {
        const decoder_t *d = &k_decoders[i];
        const size_t n = build_for(d, d->good_l, 0x80u, b, sizeof b);
        b[n - 1u] ^= 0x01u;
        expect_error(d, b, n, LMS_ERR_CRC, "CRC high byte");
        b[n - 1u] ^= 0x01u;
        b[n - 2u] ^= 0x80u;
        expect_error(d, b, n, LMS_ERR_CRC, "CRC low byte");
        b[n - 2u] ^= 0x80u;
        b[5] ^= 0x04u;
        expect_error(d, b, n, LMS_ERR_CRC, "data byte");
        b[5] ^= 0x04u;
        /* Wrong code and bad CRC: the CRC is checked first. */
        b[4] = LMS_REPLY_ERRORS;
        expect_error(d, b, n, LMS_ERR_CRC, "code B2 without a new CRC");
        /* Wrong size and bad CRC. */
        const size_t m = build_for(d, d->bad_l[0], 0x80u, b, sizeof b);
        b[m - 1u] ^= 0x10u;
        expect_error(d, b, m, LMS_ERR_CRC, "wrong size and bad CRC");
    }
}

static void test_lms_decode_replies_bad_framing(void)
{
    uint8_t b[LMS_TELEGRAM_MAX + 1u];
    for (size_t i = 0u; i < N_DECODERS; i++) {
        const decoder_t *d = &k_decoders[i];
        const size_t n = build_for(d, d->good_l, 0x80u, b, sizeof b);
        for (size_t cut = 0u; cut < n; cut++) {
            expect_error(d, b, cut, LMS_ERR_FRAME, "truncated");
        }
        b[n] = 0x00u;
        expect_error(d, b, n + 1u, LMS_ERR_FRAME, "one byte too many");
        b[0] = 0x03u;
        tu_fix_crc(b, n);
        expect_error(d, b, n, LMS_ERR_FRAME, "STX 03");
        b[0] = LMS_STX;
        b[2] = (uint8_t)(b[2] + 1u);
        tu_fix_crc(b, n);
        expect_error(d, b, n, LMS_ERR_FRAME, "L one too large");
        b[2] = (uint8_t)(b[2] - 2u);
        tu_fix_crc(b, n);
        expect_error(d, b, n, LMS_ERR_FRAME, "L one too small");
        /* A reply needs at least code + status. */
        const uint8_t code_only[1] = {d->code};
        const size_t m = tu_telegram(b, sizeof b, 0x80u, code_only, 1u);
        expect_error(d, b, m, LMS_ERR_FRAME, "L 1");
    }
}

static void test_lms_decode_replies_null_pointers(void)
{
    uint8_t b[LMS_TELEGRAM_MAX];
    for (size_t i = 0u; i < N_DECODERS; i++) {
        const decoder_t *d = &k_decoders[i];
        const size_t n = build_for(d, d->good_l, 0x80u, b, sizeof b);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, d->call(b, n, NULL), d->name);
        expect_error(d, NULL, n, LMS_ERR_ARG, "NULL bytes");
    }
}

/* --- A0 ------------------------------------------------------------------ */

static void test_lms_decode_replies_mode_vectors(void)
{
    static const struct {
        const char *id;
        uint8_t address;
        lms_mode_result_t result;
    } cases[] = {
        {"V21", 0x80u, LMS_MODE_RESULT_OK},
        {"V22", 0x81u, LMS_MODE_RESULT_OK},
        {"V23", 0x80u, LMS_MODE_RESULT_BAD_PASSWORD},
    };
    for (size_t c = 0u; c < sizeof cases / sizeof cases[0]; c++) {
        const lms_vector_t *v = vec(cases[c].id);
        lms_mode_reply_t r;
        memset(&r, 0xA5, sizeof r);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_decode_mode_reply(v->bytes, v->len, &r), v->id);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(cases[c].address, r.address, v->id);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x10u, r.status, v->id);
        TEST_ASSERT_EQUAL_INT_MESSAGE(cases[c].result, r.result, v->id);
    }
}

static void test_lms_decode_replies_mode_result_codes(void)
{
    uint8_t b[16];
    for (unsigned result = 0u; result <= 0xFFu; result++) {
        const uint8_t payload[3] = {LMS_REPLY_MODE, (uint8_t)result, 0x13u};
        const size_t n = tu_telegram(b, sizeof b, 0x80u, payload, 3u);
        lms_mode_reply_t r;
        memset(&r, 0xA5, sizeof r);
        char msg[16];
        (void)snprintf(msg, sizeof msg, "result %u", result);
        const lms_status_t st = lms_decode_mode_reply(b, n, &r);
        if (result <= 2u) {
            TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, st, msg);
            TEST_ASSERT_EQUAL_INT_MESSAGE((int)result, (int)r.result, msg);
            TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x13u, r.status, msg);
        } else {
            TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_VALUE, st, msg);
            TEST_ASSERT_TRUE_MESSAGE(tu_all_zero(&r, sizeof r), msg);
        }
    }
}

/* --- 90 / BA ------------------------------------------------------------- */

static void test_lms_decode_replies_type_and_power_on_vectors(void)
{
    const lms_vector_t *v28 = vec("V28");
    const lms_vector_t *v29 = vec("V29");
    lms_ident_t id;
    memset(&id, 0xA5, sizeof id);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_type(v28->bytes, v28->len, &id));
    TEST_ASSERT_EQUAL_STRING("LMS200;301063;V02.10 ", id.text);
    TEST_ASSERT_EQUAL_HEX8(0x80u, id.address);
    TEST_ASSERT_EQUAL_HEX8(0x10u, id.status);
    memset(&id, 0xA5, sizeof id);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_power_on(v29->bytes, v29->len, &id));
    TEST_ASSERT_EQUAL_STRING("LMS200;301063;V02.10 ", id.text);
    TEST_ASSERT_EQUAL_HEX8(0x80u, id.address);
    TEST_ASSERT_EQUAL_HEX8(0x10u, id.status);
    /* Each decoder wants its own code. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_CODE, lms_decode_type(v29->bytes, v29->len, &id));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_CODE, lms_decode_power_on(v28->bytes, v28->len, &id));
}

/* Non-printable bytes become '?', the text is NUL-terminated. */
static void test_lms_decode_replies_ident_non_printable(void)
{
    static const uint8_t text[LMS_TYPE_TEXT_SIZE] = {
        'L', 'M', 'S', '2', '9', '1', ';', 'S', '0', '5', 0x01u,
        0x1Fu, 0x7Fu, 0x80u, 0xFFu, '\n', '\t', 'A', ' ', '~', 0x00u};
    char want[LMS_TYPE_TEXT_SIZE + 1u];
    for (size_t i = 0u; i < LMS_TYPE_TEXT_SIZE; i++) {
        want[i] = '?';
        if (text[i] >= 0x20u && text[i] <= 0x7Eu) {
            want[i] = (char)text[i];
        }
    }
    want[LMS_TYPE_TEXT_SIZE] = '\0';
    uint8_t payload[LMS_TYPE_TEXT_SIZE + 2u];
    payload[0] = LMS_REPLY_TYPE;
    memcpy(&payload[1], text, LMS_TYPE_TEXT_SIZE);
    payload[LMS_TYPE_TEXT_SIZE + 1u] = 0x10u;
    uint8_t b[64];
    size_t n = tu_telegram(b, sizeof b, 0x80u, payload, sizeof payload);
    lms_ident_t id;
    memset(&id, 0xA5, sizeof id);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_type(b, n, &id));
    TEST_ASSERT_EQUAL_UINT8(0u, (uint8_t)id.text[LMS_TYPE_TEXT_SIZE]);
    TEST_ASSERT_EQUAL_STRING(want, id.text);
    TEST_ASSERT_EQUAL_UINT8((uint8_t)'?', (uint8_t)id.text[10]);
    TEST_ASSERT_EQUAL_UINT8((uint8_t)'A', (uint8_t)id.text[17]);
    /* All NUL bytes: 21 question marks, still 21 characters long. */
    payload[0] = LMS_REPLY_POWER_ON;
    memset(&payload[1], 0, LMS_TYPE_TEXT_SIZE);
    n = tu_telegram(b, sizeof b, 0x80u, payload, sizeof payload);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_power_on(b, n, &id));
    TEST_ASSERT_EQUAL_UINT(LMS_TYPE_TEXT_SIZE, strlen(id.text));
    for (size_t i = 0u; i < LMS_TYPE_TEXT_SIZE; i++) {
        TEST_ASSERT_EQUAL_UINT8((uint8_t)'?', (uint8_t)id.text[i]);
    }
}

/* --- 91 / 92 ------------------------------------------------------------- */

static void test_lms_decode_replies_bare_vectors(void)
{
    const lms_vector_t *v26 = vec("V26");
    const lms_vector_t *v27 = vec("V27");
    lms_bare_reply_t r;
    memset(&r, 0xA5, sizeof r);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_reset_ack(v26->bytes, v26->len, &r));
    TEST_ASSERT_EQUAL_HEX8(0x80u, r.address);
    TEST_ASSERT_EQUAL_HEX8(0x10u, r.status);
    memset(&r, 0xA5, sizeof r);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_not_ack(v27->bytes, v27->len, &r));
    TEST_ASSERT_EQUAL_HEX8(0x80u, r.address);
    TEST_ASSERT_EQUAL_HEX8(0x10u, r.status);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_CODE, lms_decode_reset_ack(v27->bytes, v27->len, &r));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_CODE, lms_decode_not_ack(v26->bytes, v26->len, &r));
    /* A bad status byte is still a status, decoded as given. */
    const uint8_t payload[2] = {LMS_REPLY_RESET_ACK, 0xE4u};
    uint8_t b[16];
    const size_t n = tu_telegram(b, sizeof b, 0x85u, payload, 2u);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_reset_ack(b, n, &r));
    TEST_ASSERT_EQUAL_HEX8(0x85u, r.address);
    TEST_ASSERT_EQUAL_HEX8(0xE4u, r.status);
}

/* --- B1 ------------------------------------------------------------------ */

static size_t build_status(uint8_t *b, size_t cap, uint16_t baud_word, bool permanent,
                           bool mm, bool laser)
{
    uint8_t payload[1u + LMS_STATUS_DATA_SIZE + 1u];
    uint8_t *d = &payload[1];
    payload[0] = LMS_REPLY_STATUS;
    memset(d, 0xEE, LMS_STATUS_DATA_SIZE); /* neighbours of every field are non-zero */
    memcpy(&d[0], "V02.30X", 7u);
    d[7] = LMS_MODE_STREAM_ALL;
    d[8] = 0x00u;
    d[101] = LMS_MEAS_16M_FIELDS_AB;
    tu_put_le16(&d[106], 100u);
    tu_put_le16(&d[108], 25u);
    tu_put_le16(&d[115], baud_word);
    d[118] = permanent ? 1u : 0u;
    d[119] = 0x05u;
    d[121] = mm ? 1u : 0u;
    d[122] = laser ? 1u : 0u;
    payload[sizeof payload - 1u] = 0x10u;
    return tu_telegram(b, cap, 0x85u, payload, sizeof payload);
}

static void test_lms_decode_replies_status_fields(void)
{
    static const struct {
        uint16_t word;
        bool known;
        lms_baud_t baud;
    } bauds[] = {
        {0x8067u, true, LMS_BAUD_9600},    {0x8033u, true, LMS_BAUD_19200},
        {0x8019u, true, LMS_BAUD_38400},   {0x8001u, true, LMS_BAUD_500000},
        {0x1234u, false, LMS_BAUD_9600},   {0x0067u, false, LMS_BAUD_9600},
        {0x8000u, false, LMS_BAUD_9600},   {0xEEEEu, false, LMS_BAUD_9600},
    };
    uint8_t b[LMS_TELEGRAM_MAX];
    for (size_t k = 0u; k < sizeof bauds / sizeof bauds[0]; k++) {
        const bool alt = (k % 2u) == 1u;
        const size_t n = build_status(b, sizeof b, bauds[k].word, alt, !alt, alt);
        TEST_ASSERT_EQUAL_UINT(160u, n);
        char msg[24];
        (void)snprintf(msg, sizeof msg, "baud word 0x%04X", (unsigned)bauds[k].word);
        lms_device_status_t s;
        memset(&s, 0xA5, sizeof s);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_decode_status(b, n, &s), msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x85u, s.address, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x10u, s.status, msg);
        TEST_ASSERT_EQUAL_STRING_MESSAGE("V02.30X", s.firmware, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x24u, s.operating_mode, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x00u, s.device_status, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x04u, s.meas_mode, msg);
        TEST_ASSERT_EQUAL_UINT16_MESSAGE(100u, s.angle_deg, msg);
        TEST_ASSERT_EQUAL_UINT16_MESSAGE(25u, s.resolution_cdeg, msg);
        TEST_ASSERT_EQUAL_HEX16_MESSAGE(bauds[k].word, s.baud_word, msg);
        TEST_ASSERT_EQUAL_MESSAGE(bauds[k].known, s.baud_known, msg);
        if (bauds[k].known) {
            TEST_ASSERT_EQUAL_INT_MESSAGE(bauds[k].baud, s.baud, msg);
        }
        TEST_ASSERT_EQUAL_MESSAGE(alt, s.permanent_baud, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x05u, s.scanner_address, msg);
        TEST_ASSERT_EQUAL_UINT8_MESSAGE(alt ? 0u : 1u, s.units, msg);
        TEST_ASSERT_EQUAL_MESSAGE(alt, s.laser_on, msg);
    }
}

/* A nonzero device status and other raw bytes are passed through. */
static void test_lms_decode_replies_status_raw_bytes(void)
{
    uint8_t b[LMS_TELEGRAM_MAX];
    const size_t n = build_status(b, sizeof b, 0x8019u, false, true, true);
    /* data offset k is telegram byte 5 + k */
    b[5 + 8] = 0x07u;
    b[5 + 7] = LMS_MODE_ON_REQUEST;
    b[5 + 101] = LMS_MEAS_REFLECTIVITY;
    tu_put_le16(&b[5 + 106], 180u);
    tu_put_le16(&b[5 + 108], 50u);
    b[5 + 121] = 0x02u; /* reserved units: passed raw */
    tu_fix_crc(b, n);
    lms_device_status_t s;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_status(b, n, &s));
    TEST_ASSERT_EQUAL_HEX8(0x07u, s.device_status);
    TEST_ASSERT_EQUAL_HEX8(0x25u, s.operating_mode);
    TEST_ASSERT_EQUAL_HEX8(0x3Fu, s.meas_mode);
    TEST_ASSERT_EQUAL_UINT16(180u, s.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(50u, s.resolution_cdeg);
    TEST_ASSERT_EQUAL_UINT8(2u, s.units);
    TEST_ASSERT_TRUE(s.baud_known);
    TEST_ASSERT_EQUAL_INT(LMS_BAUD_38400, s.baud);
}

/* --- BB ------------------------------------------------------------------ */

static void test_lms_decode_replies_variant_vectors(void)
{
    lms_variant_reply_t r;
    const lms_vector_t *v24 = vec("V24");
    memset(&r, 0xA5, sizeof r);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_variant_reply(v24->bytes, v24->len, &r));
    TEST_ASSERT_TRUE(r.accepted);
    TEST_ASSERT_EQUAL_UINT16(180u, r.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(50u, r.resolution_cdeg);
    TEST_ASSERT_EQUAL_HEX8(0x80u, r.address);
    TEST_ASSERT_EQUAL_HEX8(0x10u, r.status);
    const lms_vector_t *v25 = vec("V25");
    memset(&r, 0xA5, sizeof r);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_variant_reply(v25->bytes, v25->len, &r));
    TEST_ASSERT_FALSE(r.accepted);
    TEST_ASSERT_EQUAL_UINT16(180u, r.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(100u, r.resolution_cdeg);
    TEST_ASSERT_EQUAL_HEX8(0x10u, r.status);
    /* 100 deg / 0.25 deg, accepted, from address 1. */
    const uint8_t payload[7] = {LMS_REPLY_VARIANT, 0x01u, 0x64u, 0x00u, 0x19u, 0x00u, 0x11u};
    uint8_t b[16];
    const size_t n = tu_telegram(b, sizeof b, 0x81u, payload, 7u);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_variant_reply(b, n, &r));
    TEST_ASSERT_TRUE(r.accepted);
    TEST_ASSERT_EQUAL_UINT16(100u, r.angle_deg);
    TEST_ASSERT_EQUAL_UINT16(25u, r.resolution_cdeg);
    TEST_ASSERT_EQUAL_HEX8(0x81u, r.address);
    TEST_ASSERT_EQUAL_HEX8(0x11u, r.status);
}

/* --- F4 / F7 ------------------------------------------------------------- */

static void fill_block(uint8_t *block, size_t size)
{
    for (size_t i = 0u; i < size; i++) {
        block[i] = (uint8_t)(0x40u + 3u * i);
    }
    block[LMS_CONFIG_OFF_AVAILABILITY] = 0x03u;
    block[LMS_CONFIG_OFF_MEAS_MODE] = 0x05u;
    block[LMS_CONFIG_OFF_UNITS] = 0x01u;
}

static void test_lms_decode_replies_config_both_sizes(void)
{
    const uint8_t sizes[2] = {LMS_CONFIG_SIZE_OLD, LMS_CONFIG_SIZE_NEW};
    for (size_t k = 0u; k < 2u; k++) {
        uint8_t payload[1u + LMS_CONFIG_SIZE_MAX + 1u];
        payload[0] = LMS_REPLY_CONFIG;
        fill_block(&payload[1], sizes[k]);
        payload[1u + sizes[k]] = 0x10u;
        uint8_t b[64];
        const size_t n = tu_telegram(b, sizeof b, 0x80u, payload, 2u + sizes[k]);
        lms_config_reply_t r;
        memset(&r, 0xA5, sizeof r);
        const char *msg = sizes[k] == 32u ? "32-byte block" : "34-byte block";
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_decode_config(b, n, &r), msg);
        TEST_ASSERT_EQUAL_UINT8_MESSAGE(sizes[k], r.config.size, msg);
        TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&payload[1], r.config.block, sizes[k], msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x80u, r.address, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x10u, r.status, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x05u, lms_config_meas_mode(&r.config), msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x01u, lms_config_units(&r.config), msg);
        TEST_ASSERT_TRUE_MESSAGE(lms_config_has_indices(&r.config), msg);
    }
}

static void test_lms_decode_replies_config_write_accepted_refused(void)
{
    const uint8_t sizes[2] = {LMS_CONFIG_SIZE_OLD, LMS_CONFIG_SIZE_NEW};
    for (size_t k = 0u; k < 2u; k++) {
        for (uint8_t result = 0u; result <= 1u; result++) {
            uint8_t payload[2u + LMS_CONFIG_SIZE_MAX + 1u];
            payload[0] = LMS_REPLY_CONFIG_WRITE;
            payload[1] = result;
            fill_block(&payload[2], sizes[k]);
            payload[2u + sizes[k]] = 0x10u;
            uint8_t b[64];
            const size_t n = tu_telegram(b, sizeof b, 0x80u, payload, 3u + sizes[k]);
            lms_config_write_reply_t r;
            memset(&r, 0xA5, sizeof r);
            char msg[32];
            (void)snprintf(msg, sizeof msg, "block %u result %u", (unsigned)sizes[k],
                           (unsigned)result);
            TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_decode_config_write_reply(b, n, &r), msg);
            TEST_ASSERT_EQUAL_MESSAGE(result == 1u, r.accepted, msg);
            TEST_ASSERT_EQUAL_UINT8_MESSAGE(sizes[k], r.config.size, msg);
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&payload[2], r.config.block, sizes[k], msg);
            TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x10u, r.status, msg);
        }
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_decode_replies_good_builds_decode);
    RUN_TEST(test_lms_decode_replies_wrong_code);
    RUN_TEST(test_lms_decode_replies_wrong_size);
    RUN_TEST(test_lms_decode_replies_bad_crc);
    RUN_TEST(test_lms_decode_replies_bad_framing);
    RUN_TEST(test_lms_decode_replies_null_pointers);
    RUN_TEST(test_lms_decode_replies_mode_vectors);
    RUN_TEST(test_lms_decode_replies_mode_result_codes);
    RUN_TEST(test_lms_decode_replies_type_and_power_on_vectors);
    RUN_TEST(test_lms_decode_replies_ident_non_printable);
    RUN_TEST(test_lms_decode_replies_bare_vectors);
    RUN_TEST(test_lms_decode_replies_status_fields);
    RUN_TEST(test_lms_decode_replies_status_raw_bytes);
    RUN_TEST(test_lms_decode_replies_variant_vectors);
    RUN_TEST(test_lms_decode_replies_config_both_sizes);
    RUN_TEST(test_lms_decode_replies_config_write_accepted_refused);
    return UNITY_END();
}
