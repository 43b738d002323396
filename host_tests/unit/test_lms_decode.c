/* test_lms_decode.c - lms_telegram_parse, the B0 decoder (count word,
 * units, partial scans, real-time indices), lms_value_decode for every
 * measuring mode and special code, lms_scan_layout and the status byte
 * (lms_decode.h). The other reply decoders and the error cases shared by
 * all decoders are in test_lms_decode_replies.c.
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

static lms_scan_t g_scan; /* large: keep off the stack */

static void decode_scan_ok(const char *id)
{
    const lms_vector_t *v = vec(id);
    memset(&g_scan, 0xA5, sizeof g_scan);
    TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_decode_scan(v->bytes, v->len, &g_scan), id);
}

static void expect_value(uint16_t word, uint8_t mode, lms_unit_t unit, lms_value_kind_t kind,
                         uint32_t distance_mm, uint8_t flags, const char *msg)
{
    lms_value_t val;
    memset(&val, 0xA5, sizeof val);
    TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_value_decode(word, mode, unit, &val), msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(kind, val.kind, msg);
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(distance_mm, val.distance_mm, msg);
    TEST_ASSERT_EQUAL_HEX8_MESSAGE(flags, val.flags, msg);
}

/* --- lms_telegram_parse ------------------------------------------------ */

/* Every vector parses; the fields point into the caller's bytes. */
static void test_lms_decode_parse_every_vector(void)
{
    for (size_t i = 0u; i < LMS_VECTOR_COUNT; i++) {
        const lms_vector_t *v = &lms_vectors[i];
        lms_telegram_t t;
        memset(&t, 0xA5, sizeof t);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_telegram_parse(v->bytes, v->len, &t), v->id);
        const bool reply = v->direction == LMS_FROM_SCANNER;
        const size_t l_field = v->len - LMS_OVERHEAD;
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(v->bytes[1], t.address, v->id);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(v->bytes[4], t.code, v->id);
        TEST_ASSERT_TRUE_MESSAGE(t.data == v->bytes + 5, v->id);
        TEST_ASSERT_EQUAL_MESSAGE(reply, t.is_reply, v->id);
        if (reply) {
            TEST_ASSERT_EQUAL_UINT_MESSAGE(l_field - 2u, t.data_len, v->id);
            TEST_ASSERT_EQUAL_HEX8_MESSAGE(v->bytes[v->len - 3u], t.status, v->id);
            TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x10u, t.status, v->id); /* all vectors are healthy */
            const lms_status_byte_t sb = lms_status_byte_decode(t.status);
            TEST_ASSERT_EQUAL_UINT8_MESSAGE(0u, sb.severity, v->id);
            TEST_ASSERT_FALSE_MESSAGE(sb.restart || sb.implausible || sb.pollution, v->id);
        } else {
            TEST_ASSERT_EQUAL_UINT_MESSAGE(l_field - 1u, t.data_len, v->id);
            TEST_ASSERT_EQUAL_HEX8_MESSAGE(0u, t.status, v->id);
        }
    }
}

static void expect_parse_error(const uint8_t *b, size_t len, lms_status_t want, const char *msg)
{
    lms_telegram_t t;
    memset(&t, 0xA5, sizeof t);
    TEST_ASSERT_EQUAL_INT_MESSAGE(want, lms_telegram_parse(b, len, &t), msg);
    TEST_ASSERT_TRUE_MESSAGE(tu_all_zero(&t, sizeof t), msg);
}

/* STX, minimum sizes, length field against len, CRC. */
static void test_lms_decode_parse_rejects_bad_framing(void)
{
    uint8_t b[64];
    const lms_vector_t *v21 = vec("V21");
    const lms_vector_t *v08 = vec("V08");

    /* Every truncation and one extra byte: L disagrees with len. */
    for (size_t n = 0u; n < v21->len; n++) {
        expect_parse_error(v21->bytes, n, LMS_ERR_FRAME, "V21 truncated");
    }
    memcpy(b, v21->bytes, v21->len);
    b[v21->len] = 0x00u;
    expect_parse_error(b, v21->len + 1u, LMS_ERR_FRAME, "V21 + 1 byte");

    /* Wrong STX, CRC made to match. */
    memcpy(b, v21->bytes, v21->len);
    b[0] = 0x03u;
    tu_fix_crc(b, v21->len);
    expect_parse_error(b, v21->len, LMS_ERR_FRAME, "STX 03");

    /* Length field one too large / small, CRC made to match. */
    memcpy(b, v21->bytes, v21->len);
    b[2] = 0x04u;
    tu_fix_crc(b, v21->len);
    expect_parse_error(b, v21->len, LMS_ERR_FRAME, "L 4 in a 9-byte telegram");
    b[2] = 0x02u;
    tu_fix_crc(b, v21->len);
    expect_parse_error(b, v21->len, LMS_ERR_FRAME, "L 2 in a 9-byte telegram");

    /* Bad CRC, in either byte, and a data byte changed. */
    for (size_t k = 4u; k < v21->len; k++) {
        memcpy(b, v21->bytes, v21->len);
        b[k] ^= 0x01u;
        expect_parse_error(b, v21->len, LMS_ERR_CRC, "V21 one bit flipped");
    }
    memcpy(b, v08->bytes, v08->len);
    b[v08->len - 1u] ^= 0x80u;
    expect_parse_error(b, v08->len, LMS_ERR_CRC, "V08 CRC high byte");

    /* Below the minimum sizes: a reply needs code + status (L >= 2), a host
     * telegram its code (L >= 1). */
    const uint8_t code_only[] = {0xA0};
    size_t n = tu_telegram(b, sizeof b, 0x80u, code_only, 1u);
    expect_parse_error(b, n, LMS_ERR_FRAME, "reply with L 1");
    n = tu_telegram(b, sizeof b, 0x00u, code_only, 0u);
    expect_parse_error(b, n, LMS_ERR_FRAME, "host telegram with L 0");
    n = tu_telegram(b, sizeof b, 0x80u, code_only, 0u);
    expect_parse_error(b, n, LMS_ERR_FRAME, "reply with L 0");
    n = tu_telegram(b, sizeof b, 0x00u, code_only, 1u);
    lms_telegram_t t;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_parse(b, n, &t));
    TEST_ASSERT_EQUAL_UINT(0u, t.data_len);
    TEST_ASSERT_FALSE(t.is_reply);

    /* NULL pointers. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_parse(NULL, 9u, &t));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_parse(v21->bytes, v21->len, NULL));
}

/* --- B0 ---------------------------------------------------------------- */

static void test_lms_decode_scan_v30_mm_values(void)
{
    decode_scan_ok("V30");
    TEST_ASSERT_EQUAL_HEX8(0x80u, g_scan.address);
    TEST_ASSERT_EQUAL_HEX8(0x10u, g_scan.status);
    TEST_ASSERT_EQUAL_INT(LMS_UNIT_MM, g_scan.unit);
    TEST_ASSERT_EQUAL_UINT16(5u, g_scan.count);
    TEST_ASSERT_FALSE(g_scan.is_partial);
    TEST_ASSERT_EQUAL_UINT8(0u, g_scan.partial_index);
    TEST_ASSERT_FALSE(g_scan.has_indices);
    const uint16_t raw[5] = {0x03E8u, 0x1FFFu, 0x29C4u, 0x1FFEu, 0x1FF6u};
    for (size_t i = 0u; i < 5u; i++) {
        TEST_ASSERT_EQUAL_HEX16_MESSAGE(raw[i], g_scan.values[i], "V30 raw");
    }
    expect_value(g_scan.values[0], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 1000u, 0u, "V30[0]");
    expect_value(g_scan.values[1], 0x00u, g_scan.unit, LMS_VALUE_NO_RETURN, 0u, 0u, "V30[1]");
    expect_value(g_scan.values[2], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 2500u, 1u, "V30[2]");
    expect_value(g_scan.values[3], 0x00u, g_scan.unit, LMS_VALUE_DAZZLE, 0u, 0u, "V30[3]");
    expect_value(g_scan.values[4], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 8182u, 0u, "V30[4]");
    lms_status_byte_t sb = lms_status_byte_decode(g_scan.status);
    TEST_ASSERT_EQUAL_UINT8(0u, sb.severity);
}

static void test_lms_decode_scan_v31_partial_cm(void)
{
    decode_scan_ok("V31");
    TEST_ASSERT_EQUAL_INT(LMS_UNIT_CM, g_scan.unit);
    TEST_ASSERT_EQUAL_UINT16(3u, g_scan.count);
    TEST_ASSERT_TRUE(g_scan.is_partial);
    TEST_ASSERT_EQUAL_UINT8(2u, g_scan.partial_index);
    TEST_ASSERT_FALSE(g_scan.has_indices);
    TEST_ASSERT_EQUAL_HEX8(0x10u, g_scan.status);
    expect_value(g_scan.values[0], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 1000u, 0u, "V31[0]");
    expect_value(g_scan.values[1], 0x00u, g_scan.unit, LMS_VALUE_BEYOND_MAX, 0u, 0u, "V31[1]");
    expect_value(g_scan.values[2], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 2000u, 0u, "V31[2]");
}

static void test_lms_decode_scan_v32_realtime_indices(void)
{
    decode_scan_ok("V32");
    TEST_ASSERT_EQUAL_INT(LMS_UNIT_MM, g_scan.unit);
    TEST_ASSERT_EQUAL_UINT16(3u, g_scan.count);
    TEST_ASSERT_FALSE(g_scan.is_partial);
    TEST_ASSERT_TRUE(g_scan.has_indices);
    TEST_ASSERT_EQUAL_HEX8(0x2Au, g_scan.scan_index);
    TEST_ASSERT_EQUAL_HEX8(0x07u, g_scan.telegram_index);
    TEST_ASSERT_EQUAL_HEX8(0x10u, g_scan.status);
    expect_value(g_scan.values[0], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 2000u, 0u, "V32[0]");
    expect_value(g_scan.values[1], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 3000u, 0u, "V32[1]");
    expect_value(g_scan.values[2], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 4000u, 0u, "V32[2]");
}

static void test_lms_decode_scan_v33_field_flags_cm(void)
{
    decode_scan_ok("V33");
    TEST_ASSERT_EQUAL_INT(LMS_UNIT_CM, g_scan.unit);
    TEST_ASSERT_EQUAL_UINT16(4u, g_scan.count);
    TEST_ASSERT_FALSE(g_scan.is_partial);
    TEST_ASSERT_FALSE(g_scan.has_indices);
    expect_value(g_scan.values[0], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 3000u, 0u, "V33[0]");
    expect_value(g_scan.values[1], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 3000u, 1u, "V33[1]");
    expect_value(g_scan.values[2], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 3000u, 2u, "V33[2]");
    expect_value(g_scan.values[3], 0x00u, g_scan.unit, LMS_VALUE_NO_RETURN, 0u, 0u, "V33[3]");
}

static void test_lms_decode_scan_v35_full_181(void)
{
    decode_scan_ok("V35");
    TEST_ASSERT_EQUAL_INT(LMS_UNIT_MM, g_scan.unit);
    TEST_ASSERT_EQUAL_UINT16(181u, g_scan.count);
    TEST_ASSERT_FALSE(g_scan.is_partial);
    TEST_ASSERT_FALSE(g_scan.has_indices);
    TEST_ASSERT_EQUAL_HEX8(0x10u, g_scan.status);
    for (uint32_t i = 0u; i < 181u; i++) {
        expect_value(g_scan.values[i], 0x00u, g_scan.unit, LMS_VALUE_RANGE, 1000u + 10u * i, 0u,
                     "V35 value");
    }
    lms_layout_t lay;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_scan_layout(&g_scan, &lay));
    TEST_ASSERT_EQUAL_UINT16(180u, lay.field_deg);
    TEST_ASSERT_EQUAL_UINT16(0u, lay.start_cdeg);
    TEST_ASSERT_EQUAL_UINT16(100u, lay.step_cdeg);
}

/* A B0 with a given count word and n value words (value i = 100 + i). */
static size_t build_b0(uint8_t *out, size_t cap, uint16_t count_word, size_t n, bool indices,
                       uint8_t status)
{
    static uint8_t payload[LMS_TELEGRAM_MAX];
    size_t p = 0u;
    payload[p++] = LMS_REPLY_VALUES;
    tu_put_le16(&payload[p], count_word);
    p += 2u;
    for (size_t i = 0u; i < n; i++) {
        tu_put_le16(&payload[p], (uint16_t)(100u + i));
        p += 2u;
    }
    if (indices) {
        payload[p++] = 0xC3u;
        payload[p++] = 0x3Cu;
    }
    payload[p++] = status;
    return tu_telegram(out, cap, 0x80u, payload, p);
}

/* N is bits 0-9 only: bit 10 (reserved), the partial index (11-12), the
 * partial flag (13) and the unit (14) must not leak into it. */
static void test_lms_decode_scan_count_word_bits(void)
{
    static uint8_t b[LMS_TELEGRAM_MAX];
    static const struct {
        uint16_t word;
        uint16_t n;
        lms_unit_t unit;
        bool partial;
        uint8_t index;
    } cases[] = {
        {0x0003u, 3u, LMS_UNIT_CM, false, 0u}, {0x0403u, 3u, LMS_UNIT_CM, false, 0u},
        {0x0803u, 3u, LMS_UNIT_CM, false, 1u}, {0x1003u, 3u, LMS_UNIT_CM, false, 2u},
        {0x1803u, 3u, LMS_UNIT_CM, false, 3u}, {0x2003u, 3u, LMS_UNIT_CM, true, 0u},
        {0x3C03u, 3u, LMS_UNIT_CM, true, 3u},  {0x4003u, 3u, LMS_UNIT_MM, false, 0u},
        {0x7C03u, 3u, LMS_UNIT_MM, true, 3u},  {0x6803u, 3u, LMS_UNIT_MM, true, 1u},
        {0x40B5u, 181u, LMS_UNIT_MM, false, 0u}, /* V35's count word */
        {0x0569u, 361u, LMS_UNIT_CM, false, 0u}, /* bit 10 set: 0x569 would be 1385 */
        {0x7D91u, 401u, LMS_UNIT_MM, true, 3u},  /* 0x191 = 401, with 0x7C00 set */
        {0x0000u, 0u, LMS_UNIT_CM, false, 0u},
    };
    for (size_t c = 0u; c < sizeof cases / sizeof cases[0]; c++) {
        char msg[40];
        (void)snprintf(msg, sizeof msg, "count word 0x%04X", (unsigned)cases[c].word);
        const size_t n = build_b0(b, sizeof b, cases[c].word, cases[c].n, false, 0x10u);
        TEST_ASSERT_TRUE_MESSAGE(n > 0u, msg);
        memset(&g_scan, 0xA5, sizeof g_scan);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_decode_scan(b, n, &g_scan), msg);
        TEST_ASSERT_EQUAL_UINT16_MESSAGE(cases[c].n, g_scan.count, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(cases[c].unit, g_scan.unit, msg);
        TEST_ASSERT_EQUAL_MESSAGE(cases[c].partial, g_scan.is_partial, msg);
        TEST_ASSERT_EQUAL_UINT8_MESSAGE(cases[c].index, g_scan.partial_index, msg);
        TEST_ASSERT_FALSE_MESSAGE(g_scan.has_indices, msg);
        for (size_t i = 0u; i < cases[c].n; i++) {
            TEST_ASSERT_EQUAL_HEX16_MESSAGE(100u + i, g_scan.values[i], msg);
        }
    }
}

/* Units 1x in bits 14-15 are reserved: LMS_ERR_VALUE, *out zeroed. */
static void test_lms_decode_scan_reserved_units(void)
{
    static uint8_t b[LMS_TELEGRAM_MAX];
    const uint16_t words[] = {0x8003u, 0xC003u, 0xBC03u, 0xFC03u};
    for (size_t k = 0u; k < sizeof words / sizeof words[0]; k++) {
        const size_t n = build_b0(b, sizeof b, words[k], 3u, false, 0x10u);
        memset(&g_scan, 0xA5, sizeof g_scan);
        TEST_ASSERT_EQUAL_INT(LMS_ERR_VALUE, lms_decode_scan(b, n, &g_scan));
        TEST_ASSERT_TRUE(tu_all_zero(&g_scan, sizeof g_scan));
    }
}

/* L must be 2N + 4 or 2N + 6, and N <= LMS_SCAN_MAX_VALUES. */
static void test_lms_decode_scan_size_rules(void)
{
    static uint8_t b[LMS_TELEGRAM_MAX];
    /* N = 3 but 2, 4 or 5 value words' worth of bytes. */
    for (size_t words = 0u; words <= 5u; words++) {
        if (words == 3u) {
            continue;
        }
        const size_t n = build_b0(b, sizeof b, 0x4003u, words, false, 0x10u);
        memset(&g_scan, 0xA5, sizeof g_scan);
        if (words == 4u) {
            /* 2N + 6: the two extra bytes are the real-time indices. */
            TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_scan(b, n, &g_scan));
            TEST_ASSERT_TRUE(g_scan.has_indices);
            TEST_ASSERT_EQUAL_HEX8(0x67u, g_scan.scan_index);    /* low byte of 100 + 3 */
            TEST_ASSERT_EQUAL_HEX8(0x00u, g_scan.telegram_index); /* its high byte */
            continue;
        }
        TEST_ASSERT_EQUAL_INT(LMS_ERR_SIZE, lms_decode_scan(b, n, &g_scan));
        TEST_ASSERT_TRUE(tu_all_zero(&g_scan, sizeof g_scan));
    }
    /* An odd L: one byte more than 2N + 4. */
    uint8_t payload[16] = {LMS_REPLY_VALUES, 0x03u, 0x40u, 1, 0, 2, 0, 3, 0, 0xEEu, 0x10u};
    size_t n = tu_telegram(b, sizeof b, 0x80u, payload, 11u);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_SIZE, lms_decode_scan(b, n, &g_scan));
    /* No count word at all: B0 + status, B0 + 1 byte + status. */
    n = tu_telegram(b, sizeof b, 0x80u, (const uint8_t[]){LMS_REPLY_VALUES, 0x10u}, 2u);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_SIZE, lms_decode_scan(b, n, &g_scan));
    n = tu_telegram(b, sizeof b, 0x80u, (const uint8_t[]){LMS_REPLY_VALUES, 0x00u, 0x10u}, 3u);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_SIZE, lms_decode_scan(b, n, &g_scan));
    /* N = LMS_SCAN_MAX_VALUES + 1 (402) with a matching L = 2N + 4 (808). */
    n = build_b0(b, sizeof b, (uint16_t)(0x4000u | (LMS_SCAN_MAX_VALUES + 1u)),
                 LMS_SCAN_MAX_VALUES + 1u, false, 0x10u);
    TEST_ASSERT_EQUAL_UINT(LMS_TELEGRAM_MAX, n);
    memset(&g_scan, 0xA5, sizeof g_scan);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_SIZE, lms_decode_scan(b, n, &g_scan));
    TEST_ASSERT_TRUE(tu_all_zero(&g_scan, sizeof g_scan));
    /* N = 401 with indices: the largest telegram, 814 bytes. */
    n = build_b0(b, sizeof b, (uint16_t)(0x4000u | LMS_SCAN_MAX_VALUES), LMS_SCAN_MAX_VALUES,
                 true, 0x12u);
    TEST_ASSERT_EQUAL_UINT(LMS_TELEGRAM_MAX, n);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_decode_scan(b, n, &g_scan));
    TEST_ASSERT_EQUAL_UINT16(LMS_SCAN_MAX_VALUES, g_scan.count);
    TEST_ASSERT_TRUE(g_scan.has_indices);
    TEST_ASSERT_EQUAL_HEX8(0xC3u, g_scan.scan_index);
    TEST_ASSERT_EQUAL_HEX8(0x3Cu, g_scan.telegram_index);
    TEST_ASSERT_EQUAL_HEX8(0x12u, g_scan.status);
    TEST_ASSERT_EQUAL_HEX16(100u + LMS_SCAN_MAX_VALUES - 1u, g_scan.values[LMS_SCAN_MAX_VALUES - 1u]);
}

/* --- lms_value_decode ---------------------------------------------------- */

typedef struct {
    uint8_t mode;
    unsigned bits;
} mode_bits_t;

static const mode_bits_t k_ranged_modes[] = {
    {0x00u, 13u}, {0x01u, 13u}, {0x02u, 13u}, {0x03u, 14u},
    {0x04u, 14u}, {0x05u, 15u}, {0x06u, 15u},
};

/* Kind of the distance part d of a mode with maximum code max. */
static lms_value_kind_t expected_kind(uint32_t d, uint32_t max)
{
    if (d + 8u < max) {
        return LMS_VALUE_RANGE;
    }
    switch (max - d) {
    case 0u:
        return LMS_VALUE_NO_RETURN;
    case 1u:
        return LMS_VALUE_DAZZLE;
    case 2u:
        return LMS_VALUE_OVERFLOW;
    case 4u:
        return LMS_VALUE_LOW_SNR;
    case 5u:
        return LMS_VALUE_CHANNEL_ERROR;
    case 8u:
        return LMS_VALUE_BEYOND_MAX;
    default:
        return LMS_VALUE_RESERVED; /* max - 3, - 6, - 7 */
    }
}

/* Modes 00-06: every flag combination above 13/14/15 distance bits,
 * distances 0, 1, a middle value, max - 9 (largest range) and every code
 * max - 8 .. max, in both units. */
static void test_lms_decode_value_ranged_modes(void)
{
    for (size_t m = 0u; m < sizeof k_ranged_modes / sizeof k_ranged_modes[0]; m++) {
        const unsigned bits = k_ranged_modes[m].bits;
        const uint32_t max = (1u << bits) - 1u;
        const uint32_t nflags = 1u << (16u - bits);
        const uint32_t dists[] = {0u, 1u, 1234u, max - 9u, max - 8u, max - 7u, max - 6u,
                                  max - 5u, max - 4u, max - 3u, max - 2u, max - 1u, max};
        for (uint32_t f = 0u; f < nflags; f++) {
            for (size_t k = 0u; k < sizeof dists / sizeof dists[0]; k++) {
                const uint16_t word = (uint16_t)((f << bits) | dists[k]);
                const lms_value_kind_t kind = expected_kind(dists[k], max);
                char msg[48];
                (void)snprintf(msg, sizeof msg, "mode %02X word 0x%04X", k_ranged_modes[m].mode,
                               (unsigned)word);
                const uint32_t mm = kind == LMS_VALUE_RANGE ? dists[k] : 0u;
                expect_value(word, k_ranged_modes[m].mode, LMS_UNIT_MM, kind, mm, (uint8_t)f, msg);
                expect_value(word, k_ranged_modes[m].mode, LMS_UNIT_CM, kind, 10u * mm, (uint8_t)f,
                             msg);
            }
        }
    }
}

/* The named constants of the notes' special-value table. */
static void test_lms_decode_value_special_codes_by_name(void)
{
    expect_value(0x1FFFu, 0x00u, LMS_UNIT_MM, LMS_VALUE_NO_RETURN, 0u, 0u, "1FFF");
    expect_value(0x1FFEu, 0x01u, LMS_UNIT_MM, LMS_VALUE_DAZZLE, 0u, 0u, "1FFE");
    expect_value(0x1FFDu, 0x02u, LMS_UNIT_CM, LMS_VALUE_OVERFLOW, 0u, 0u, "1FFD");
    expect_value(0x1FFCu, 0x00u, LMS_UNIT_MM, LMS_VALUE_RESERVED, 0u, 0u, "1FFC");
    expect_value(0x1FFBu, 0x00u, LMS_UNIT_MM, LMS_VALUE_LOW_SNR, 0u, 0u, "1FFB");
    expect_value(0x1FFAu, 0x00u, LMS_UNIT_MM, LMS_VALUE_CHANNEL_ERROR, 0u, 0u, "1FFA");
    expect_value(0x1FF9u, 0x00u, LMS_UNIT_MM, LMS_VALUE_RESERVED, 0u, 0u, "1FF9");
    expect_value(0x1FF8u, 0x00u, LMS_UNIT_MM, LMS_VALUE_RESERVED, 0u, 0u, "1FF8");
    expect_value(0x1FF7u, 0x00u, LMS_UNIT_CM, LMS_VALUE_BEYOND_MAX, 0u, 0u, "1FF7");
    expect_value(0x1FF6u, 0x00u, LMS_UNIT_MM, LMS_VALUE_RANGE, 8182u, 0u, "1FF6");
    expect_value(0x1FF6u, 0x00u, LMS_UNIT_CM, LMS_VALUE_RANGE, 81820u, 0u, "1FF6 cm");
    expect_value(0x3FF7u, 0x03u, LMS_UNIT_MM, LMS_VALUE_BEYOND_MAX, 0u, 0u, "3FF7");
    expect_value(0x3FF6u, 0x04u, LMS_UNIT_MM, LMS_VALUE_RANGE, 16374u, 0u, "3FF6");
    expect_value(0x7FF7u, 0x05u, LMS_UNIT_MM, LMS_VALUE_BEYOND_MAX, 0u, 0u, "7FF7");
    expect_value(0x7FF6u, 0x06u, LMS_UNIT_MM, LMS_VALUE_RANGE, 32758u, 0u, "7FF6");
    /* In a 14-bit mode, 0x1FFF is an ordinary range. */
    expect_value(0x1FFFu, 0x03u, LMS_UNIT_MM, LMS_VALUE_RANGE, 8191u, 0u, "1FFF mode 03");
    /* Mode 00: bit 15 is the dazzle flag on a normal value, not 0x1FFE. */
    expect_value(0x83E8u, 0x00u, LMS_UNIT_MM, LMS_VALUE_RANGE, 1000u, 4u, "dazzle flag");
    /* Mode 01: bits 13-15 are a reflector level 0-7. */
    expect_value(0xE3E8u, 0x01u, LMS_UNIT_MM, LMS_VALUE_RANGE, 1000u, 7u, "reflector 7");
    expect_value(0xA3E8u, 0x01u, LMS_UNIT_MM, LMS_VALUE_RANGE, 1000u, 5u, "reflector 5");
    /* Mode 03: bits 14-15 reflector level. */
    expect_value(0xC3E8u, 0x03u, LMS_UNIT_MM, LMS_VALUE_RANGE, 1000u, 3u, "16 m level 3");
    expect_value(0x63E8u, 0x03u, LMS_UNIT_MM, LMS_VALUE_RANGE, 0x23E8u, 1u, "16 m level 1");
}

/* 0F: all 16 bits are distance, no flags, no special codes. 3F: raw
 * reflectivity, not scaled by the unit. */
static void test_lms_decode_value_immediate_and_reflectivity(void)
{
    const uint16_t words[] = {0x0000u, 0x0001u, 0x1FFFu, 0x1FF7u, 0x7FFFu,
                              0x8000u, 0xFFF6u, 0xFFF7u, 0xFFFEu, 0xFFFFu};
    for (size_t k = 0u; k < sizeof words / sizeof words[0]; k++) {
        char msg[32];
        (void)snprintf(msg, sizeof msg, "word 0x%04X", (unsigned)words[k]);
        expect_value(words[k], 0x0Fu, LMS_UNIT_MM, LMS_VALUE_RANGE, words[k], 0u, msg);
        expect_value(words[k], 0x0Fu, LMS_UNIT_CM, LMS_VALUE_RANGE, 10u * (uint32_t)words[k], 0u,
                     msg);
        expect_value(words[k], 0x3Fu, LMS_UNIT_MM, LMS_VALUE_REFLECTIVITY, words[k], 0u, msg);
        expect_value(words[k], 0x3Fu, LMS_UNIT_CM, LMS_VALUE_REFLECTIVITY, words[k], 0u, msg);
    }
}

static void test_lms_decode_value_rejects_unknown_mode_and_unit(void)
{
    static const uint8_t known[] = {0x00u, 0x01u, 0x02u, 0x03u, 0x04u,
                                    0x05u, 0x06u, 0x0Fu, 0x3Fu};
    lms_value_t val;
    for (unsigned mode = 0u; mode <= 0xFFu; mode++) {
        bool is_known = false;
        for (size_t k = 0u; k < sizeof known; k++) {
            is_known = is_known || known[k] == mode;
        }
        char msg[16];
        (void)snprintf(msg, sizeof msg, "mode %02X", mode);
        TEST_ASSERT_EQUAL_INT_MESSAGE(is_known ? LMS_OK : LMS_ERR_ARG,
                                      lms_value_decode(0x0100u, (uint8_t)mode, LMS_UNIT_MM, &val),
                                      msg);
    }
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_value_decode(0x0100u, 0x00u, (lms_unit_t)2, &val));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_value_decode(0x0100u, 0x00u, (lms_unit_t)3, &val));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_value_decode(0x0100u, 0x00u, LMS_UNIT_MM, NULL));
}

/* --- lms_scan_layout ----------------------------------------------------- */

static void expect_layout(uint16_t count, bool partial, uint8_t index, lms_status_t want,
                          uint16_t field, uint16_t start, uint16_t step)
{
    char msg[48];
    (void)snprintf(msg, sizeof msg, "count %u partial %d index %u", (unsigned)count,
                   partial ? 1 : 0, (unsigned)index);
    memset(&g_scan, 0, sizeof g_scan);
    g_scan.count = count;
    g_scan.is_partial = partial;
    g_scan.partial_index = index;
    g_scan.unit = LMS_UNIT_MM;
    lms_layout_t lay;
    memset(&lay, 0xA5, sizeof lay);
    TEST_ASSERT_EQUAL_INT_MESSAGE(want, lms_scan_layout(&g_scan, &lay), msg);
    if (want == LMS_OK) {
        TEST_ASSERT_EQUAL_UINT16_MESSAGE(field, lay.field_deg, msg);
        TEST_ASSERT_EQUAL_UINT16_MESSAGE(start, lay.start_cdeg, msg);
        TEST_ASSERT_EQUAL_UINT16_MESSAGE(step, lay.step_cdeg, msg);
    }
}

static void test_lms_decode_layout_full_scans(void)
{
    expect_layout(181u, false, 0u, LMS_OK, 180u, 0u, 100u);
    expect_layout(361u, false, 0u, LMS_OK, 180u, 0u, 50u);
    expect_layout(101u, false, 0u, LMS_OK, 100u, 4000u, 100u);
    expect_layout(201u, false, 0u, LMS_OK, 100u, 4000u, 50u);
    expect_layout(401u, false, 0u, LMS_OK, 100u, 4000u, 25u);
}

static void test_lms_decode_layout_partial_scans(void)
{
    for (uint8_t k = 0u; k < 4u; k++) {
        expect_layout(181u, true, k, LMS_OK, 180u, (uint16_t)(25u * k), 100u);
        expect_layout(101u, true, k, LMS_OK, 100u, (uint16_t)(4000u + 25u * k), 100u);
    }
}

static void test_lms_decode_layout_rejects_other_counts(void)
{
    const uint16_t bad[] = {0u, 1u, 3u, 5u, 100u, 180u, 182u, 360u, 362u, 400u, 402u, 1023u};
    for (size_t k = 0u; k < sizeof bad / sizeof bad[0]; k++) {
        expect_layout(bad[k], false, 0u, LMS_ERR_VALUE, 0u, 0u, 0u);
        expect_layout(bad[k], true, 1u, LMS_ERR_VALUE, 0u, 0u, 0u);
    }
    /* Partial scans have 1-degree steps: 181 or 101 values only. */
    expect_layout(361u, true, 0u, LMS_ERR_VALUE, 0u, 0u, 0u);
    expect_layout(201u, true, 2u, LMS_ERR_VALUE, 0u, 0u, 0u);
    expect_layout(401u, true, 3u, LMS_ERR_VALUE, 0u, 0u, 0u);
    /* V31 is a 3-value partial scan: no layout. */
    decode_scan_ok("V31");
    lms_layout_t lay;
    TEST_ASSERT_EQUAL_INT(LMS_ERR_VALUE, lms_scan_layout(&g_scan, &lay));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_scan_layout(NULL, &lay));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_scan_layout(&g_scan, NULL));
}

/* --- status byte --------------------------------------------------------- */

static void test_lms_decode_status_byte_every_value(void)
{
    for (unsigned raw = 0u; raw <= 0xFFu; raw++) {
        const lms_status_byte_t s = lms_status_byte_decode((uint8_t)raw);
        char msg[16];
        (void)snprintf(msg, sizeof msg, "0x%02X", raw);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(raw, s.raw, msg);
        TEST_ASSERT_EQUAL_UINT8_MESSAGE(raw & 0x07u, s.severity, msg);
        TEST_ASSERT_EQUAL_MESSAGE((raw & 0x20u) != 0u, s.restart, msg);
        TEST_ASSERT_EQUAL_MESSAGE((raw & 0x40u) != 0u, s.implausible, msg);
        TEST_ASSERT_EQUAL_MESSAGE((raw & 0x80u) != 0u, s.pollution, msg);
    }
    const lms_status_byte_t ok = lms_status_byte_decode(0x10u); /* the healthy value */
    TEST_ASSERT_EQUAL_UINT8(0u, ok.severity);
    TEST_ASSERT_FALSE(ok.restart);
    TEST_ASSERT_FALSE(ok.implausible);
    TEST_ASSERT_FALSE(ok.pollution);
}

/* lms_scan_to_ranges agrees with lms_value_decode on every mode, for the
 * top codes of every width and random words: the distance in the scan's
 * unit for a range, 0 for a special code; refused modes leave the scan
 * alone. */
static void test_lms_decode_scan_to_ranges_matches_value_decode(void)
{
    static const uint8_t modes[] = {0x00u, 0x01u, 0x02u, 0x03u, 0x04u, 0x05u, 0x06u, 0x0Fu};
    static lms_scan_t scan;
    static lms_scan_t raw;
    uint32_t seed = 0x5EEDu;
    for (size_t m = 0u; m < sizeof modes; m++) {
        for (unsigned unit = 0u; unit < 2u; unit++) {
            memset(&raw, 0, sizeof raw);
            raw.count = LMS_SCAN_MAX_VALUES;
            raw.unit = unit == 0u ? LMS_UNIT_CM : LMS_UNIT_MM;
            for (uint16_t k = 0u; k < raw.count; k++) {
                /* The first 64 words: every top code of 13..16 bits. */
                const uint32_t word = (k < 64u) ? (0x2000u << (k / 16u)) - 1u - (k % 16u)
                                                : tu_rand(&seed);
                raw.values[k] = (uint16_t)word;
            }
            scan = raw;
            TEST_ASSERT_EQUAL_INT(LMS_OK, lms_scan_to_ranges(&scan, modes[m]));
            for (uint16_t k = 0u; k < raw.count; k++) {
                lms_value_t v;
                TEST_ASSERT_EQUAL_INT(LMS_OK, lms_value_decode(raw.values[k], modes[m], raw.unit, &v));
                const uint32_t want = (v.kind != LMS_VALUE_RANGE) ? 0u
                                      : (raw.unit == LMS_UNIT_CM ? v.distance_mm / 10u : v.distance_mm);
                TEST_ASSERT_EQUAL_UINT16_MESSAGE(want, scan.values[k], "word by word");
            }
        }
    }
    scan = raw;
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_scan_to_ranges(&scan, 0x3Fu));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_scan_to_ranges(&scan, 0x07u));
    TEST_ASSERT_EQUAL_MEMORY(&raw, &scan, sizeof scan);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_scan_to_ranges(NULL, 0x00u));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_decode_parse_every_vector);
    RUN_TEST(test_lms_decode_parse_rejects_bad_framing);
    RUN_TEST(test_lms_decode_scan_v30_mm_values);
    RUN_TEST(test_lms_decode_scan_v31_partial_cm);
    RUN_TEST(test_lms_decode_scan_v32_realtime_indices);
    RUN_TEST(test_lms_decode_scan_v33_field_flags_cm);
    RUN_TEST(test_lms_decode_scan_v35_full_181);
    RUN_TEST(test_lms_decode_scan_count_word_bits);
    RUN_TEST(test_lms_decode_scan_reserved_units);
    RUN_TEST(test_lms_decode_scan_size_rules);
    RUN_TEST(test_lms_decode_value_ranged_modes);
    RUN_TEST(test_lms_decode_value_special_codes_by_name);
    RUN_TEST(test_lms_decode_value_immediate_and_reflectivity);
    RUN_TEST(test_lms_decode_value_rejects_unknown_mode_and_unit);
    RUN_TEST(test_lms_decode_scan_to_ranges_matches_value_decode);
    RUN_TEST(test_lms_decode_layout_full_scans);
    RUN_TEST(test_lms_decode_layout_partial_scans);
    RUN_TEST(test_lms_decode_layout_rejects_other_counts);
    RUN_TEST(test_lms_decode_status_byte_every_value);
    return UNITY_END();
}
