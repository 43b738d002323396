/* test_lms_encode.c - the builders of lms_encode.h: every host vector
 * rebuilt byte for byte by its lms_cmd_* builder, lms_telegram_write,
 * lms_encode_scan (re-encoding the B0 vectors from their decoded scans and
 * round trips of seeded random scans), and every argument the builders
 * must reject.
 */
#include <string.h>

#include "lms_decode.h"
#include "lms_encode.h"
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

static void expect_cmd(const char *id, lms_status_t st, const lms_cmd_t *c)
{
    const lms_vector_t *v = vec(id);
    TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, st, id);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(v->len, c->len, id);
    TEST_ASSERT_EQUAL_HEX8_ARRAY_MESSAGE(v->bytes, c->bytes, v->len, id);
}

static lms_cmd_t g_cmd;

static lms_cmd_t *fresh_cmd(void)
{
    memset(&g_cmd, 0xA5, sizeof g_cmd);
    return &g_cmd;
}

/* --- host vectors -------------------------------------------------------- */

static void test_lms_encode_mode_vectors(void)
{
    expect_cmd("V01", lms_cmd_mode(fresh_cmd(), 0u, LMS_MODE_STREAM_ALL), &g_cmd);
    expect_cmd("V02", lms_cmd_mode(fresh_cmd(), 0u, LMS_MODE_ON_REQUEST), &g_cmd);
    expect_cmd("V18", lms_cmd_mode(fresh_cmd(), 0u, LMS_MODE_STREAM_PARTIAL), &g_cmd);
    /* The baud codes through lms_cmd_mode too. */
    expect_cmd("V03", lms_cmd_mode(fresh_cmd(), 0u, LMS_MODE_BAUD_9600), &g_cmd);
    expect_cmd("V04", lms_cmd_mode(fresh_cmd(), 0u, LMS_MODE_BAUD_19200), &g_cmd);
    expect_cmd("V05", lms_cmd_mode(fresh_cmd(), 0u, LMS_MODE_BAUD_38400), &g_cmd);
    expect_cmd("V06", lms_cmd_mode(fresh_cmd(), 0u, LMS_MODE_BAUD_500000), &g_cmd);
}

static void test_lms_encode_baud_vectors(void)
{
    expect_cmd("V03", lms_cmd_baud(fresh_cmd(), 0u, LMS_BAUD_9600), &g_cmd);
    expect_cmd("V04", lms_cmd_baud(fresh_cmd(), 0u, LMS_BAUD_19200), &g_cmd);
    expect_cmd("V05", lms_cmd_baud(fresh_cmd(), 0u, LMS_BAUD_38400), &g_cmd);
    expect_cmd("V06", lms_cmd_baud(fresh_cmd(), 0u, LMS_BAUD_500000), &g_cmd);
}

static void test_lms_encode_installation_vector(void)
{
    expect_cmd("V07", lms_cmd_installation(fresh_cmd(), 0u, NULL), &g_cmd);
    expect_cmd("V07", lms_cmd_installation(fresh_cmd(), 0u, "SICK_LMS"), &g_cmd);
    /* Another 8-character password lands at bytes 6..13. */
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_installation(fresh_cmd(), 0u, "SICK_PLS"));
    TEST_ASSERT_EQUAL_UINT(16u, g_cmd.len);
    TEST_ASSERT_EQUAL_MEMORY("SICK_PLS", &g_cmd.bytes[6], 8u);
    TEST_ASSERT_EQUAL_HEX8(0x20u, g_cmd.bytes[4]);
    TEST_ASSERT_EQUAL_HEX8(0x00u, g_cmd.bytes[5]);
    TEST_ASSERT_TRUE(tu_crc_ok(g_cmd.bytes, g_cmd.len));
}

static void test_lms_encode_installation_rejects_password_length(void)
{
    /* Exactly 8 characters; a shorter string must not be read past its NUL
     * (ASan would catch it: the 4-byte array below has nothing after it). */
    static const char short_pw[4] = {'S', 'I', 'C', '\0'};
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_installation(fresh_cmd(), 0u, short_pw));
    TEST_ASSERT_EQUAL_UINT(0u, g_cmd.len);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_installation(fresh_cmd(), 0u, ""));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_installation(fresh_cmd(), 0u, "SICK_LM"));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_installation(fresh_cmd(), 0u, "SICK_LMSX"));
    TEST_ASSERT_EQUAL_UINT(0u, g_cmd.len);
}

static void test_lms_encode_simple_command_vectors(void)
{
    expect_cmd("V08", lms_cmd_status(fresh_cmd(), 0u), &g_cmd);
    expect_cmd("V09", lms_cmd_request_values(fresh_cmd(), 0u), &g_cmd);
    expect_cmd("V10", lms_cmd_config_read(fresh_cmd(), 0u), &g_cmd);
    expect_cmd("V11", lms_cmd_type(fresh_cmd(), 0u), &g_cmd);
    expect_cmd("V12", lms_cmd_reset(fresh_cmd(), 0u), &g_cmd);
    expect_cmd("V19", lms_cmd_errors(fresh_cmd(), 0u), &g_cmd);
    expect_cmd("V20", lms_cmd_status(fresh_cmd(), 1u), &g_cmd);
}

static void test_lms_encode_variant_vectors(void)
{
    expect_cmd("V13", lms_cmd_variant(fresh_cmd(), 0u, 180u, 50u), &g_cmd);
    expect_cmd("V14", lms_cmd_variant(fresh_cmd(), 0u, 180u, 100u), &g_cmd);
    expect_cmd("V15", lms_cmd_variant(fresh_cmd(), 0u, 100u, 25u), &g_cmd);
    expect_cmd("V16", lms_cmd_variant(fresh_cmd(), 0u, 100u, 100u), &g_cmd);
    expect_cmd("V17", lms_cmd_variant(fresh_cmd(), 0u, 100u, 50u), &g_cmd);
}

static void test_lms_encode_config_write_vector(void)
{
    const lms_vector_t *v = vec("V34");
    lms_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.size = LMS_CONFIG_SIZE_NEW;
    memcpy(cfg.block, &v->bytes[5], LMS_CONFIG_SIZE_NEW);
    TEST_ASSERT_EQUAL_HEX8(0x02u, lms_config_meas_mode(&cfg));
    TEST_ASSERT_EQUAL_HEX8(0x00u, lms_config_units(&cfg));
    TEST_ASSERT_TRUE(lms_config_has_indices(&cfg));
    expect_cmd("V34", lms_cmd_config_write(fresh_cmd(), 0u, &cfg), &g_cmd);
    TEST_ASSERT_EQUAL_UINT(LMS_CMD_MAX, g_cmd.len);
}

/* A 32-byte block is written at 32 bytes: 77 + block, L = 33. */
static void test_lms_encode_config_write_old_size(void)
{
    lms_config_t cfg;
    memset(&cfg, 0xCC, sizeof cfg);
    cfg.size = LMS_CONFIG_SIZE_OLD;
    for (size_t i = 0u; i < LMS_CONFIG_SIZE_OLD; i++) {
        cfg.block[i] = (uint8_t)(i + 1u);
    }
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_config_write(fresh_cmd(), 0x12u, &cfg));
    TEST_ASSERT_EQUAL_UINT(LMS_OVERHEAD + 1u + LMS_CONFIG_SIZE_OLD, g_cmd.len);
    const uint8_t head[5] = {0x02u, 0x12u, 33u, 0x00u, 0x77u};
    TEST_ASSERT_EQUAL_HEX8_ARRAY(head, g_cmd.bytes, 5u);
    TEST_ASSERT_EQUAL_HEX8_ARRAY(cfg.block, &g_cmd.bytes[5], LMS_CONFIG_SIZE_OLD);
    TEST_ASSERT_TRUE(tu_crc_ok(g_cmd.bytes, g_cmd.len));
}

/* Every builder, at a non-zero address: address byte set, everything else
 * as at address 0 apart from the CRC, which stays valid. */
static void test_lms_encode_addresses(void)
{
    const uint8_t addrs[3] = {0x01u, 0x42u, 0x7Fu};
    for (size_t k = 0u; k < 3u; k++) {
        lms_cmd_t a;
        lms_cmd_t z;
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_variant(&a, addrs[k], 100u, 50u));
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_variant(&z, 0u, 100u, 50u));
        TEST_ASSERT_EQUAL_UINT(z.len, a.len);
        TEST_ASSERT_EQUAL_HEX8(addrs[k], a.bytes[1]);
        TEST_ASSERT_EQUAL_HEX8_ARRAY(&z.bytes[2], &a.bytes[2], (size_t)z.len - 4u);
        TEST_ASSERT_TRUE(tu_crc_ok(a.bytes, a.len));
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_installation(&a, addrs[k], NULL));
        TEST_ASSERT_EQUAL_HEX8(addrs[k], a.bytes[1]);
        TEST_ASSERT_TRUE(tu_crc_ok(a.bytes, a.len));
    }
}

/* --- what builders reject ------------------------------------------------ */

static void test_lms_encode_variant_legality(void)
{
    const uint16_t angles[] = {0u, 1u, 90u, 99u, 100u, 101u, 180u, 181u, 270u, 360u, 0xFFFFu};
    const uint16_t res[] = {0u, 1u, 24u, 25u, 26u, 50u, 75u, 100u, 200u, 0xFFFFu};
    for (size_t a = 0u; a < sizeof angles / sizeof angles[0]; a++) {
        for (size_t r = 0u; r < sizeof res / sizeof res[0]; r++) {
            const uint16_t an = angles[a];
            const uint16_t rs = res[r];
            const bool legal = (an == 180u && (rs == 100u || rs == 50u)) ||
                               (an == 100u && (rs == 100u || rs == 50u || rs == 25u));
            char msg[32];
            (void)snprintf(msg, sizeof msg, "%u / %u", (unsigned)an, (unsigned)rs);
            TEST_ASSERT_EQUAL_MESSAGE(legal, lms_variant_is_legal(an, rs), msg);
            TEST_ASSERT_EQUAL_INT_MESSAGE(legal ? LMS_OK : LMS_ERR_ARG,
                                          lms_cmd_variant(fresh_cmd(), 0u, an, rs), msg);
        }
    }
    /* The one the notes single out. */
    TEST_ASSERT_FALSE(lms_variant_is_legal(180u, 25u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_variant(fresh_cmd(), 0u, 180u, 25u));
}

static void test_lms_encode_rejects_reply_addresses(void)
{
    static const uint8_t bad[3] = {0x80u, 0x81u, 0xFFu};
    lms_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.size = LMS_CONFIG_SIZE_NEW;
    for (size_t k = 0u; k < 3u; k++) {
        const uint8_t a = bad[k];
        char msg[16];
        (void)snprintf(msg, sizeof msg, "addr 0x%02X", (unsigned)a);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_mode(fresh_cmd(), a, LMS_MODE_STREAM_ALL), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_installation(fresh_cmd(), a, NULL), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_baud(fresh_cmd(), a, LMS_BAUD_38400), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_request_values(fresh_cmd(), a), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_status(fresh_cmd(), a), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_errors(fresh_cmd(), a), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_type(fresh_cmd(), a), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_reset(fresh_cmd(), a), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_variant(fresh_cmd(), a, 180u, 50u), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_config_read(fresh_cmd(), a), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_config_write(fresh_cmd(), a, &cfg), msg);
    }
    /* 0x7F is the largest host address. */
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_status(fresh_cmd(), 0x7Fu));
}

static void test_lms_encode_rejects_modes_with_parameters(void)
{
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_mode(fresh_cmd(), 0u, LMS_MODE_INSTALLATION));
    const uint8_t bad[] = {0x10u, 0x20u, 0x23u, 0x26u, 0x27u, 0x28u, 0x29u,
                           0x2Bu, 0x50u, 0x43u, 0x66u, 0xFFu};
    for (size_t k = 0u; k < sizeof bad; k++) {
        char msg[16];
        (void)snprintf(msg, sizeof msg, "mode 0x%02X", (unsigned)bad[k]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_mode(fresh_cmd(), 0u, (lms_mode_t)bad[k]),
                                      msg);
    }
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_baud(fresh_cmd(), 0u, (lms_baud_t)LMS_BAUD_COUNT));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_baud(fresh_cmd(), 0u, (lms_baud_t)-1));
}

static void test_lms_encode_rejects_null_out(void)
{
    lms_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.size = LMS_CONFIG_SIZE_OLD;
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_mode(NULL, 0u, LMS_MODE_STREAM_ALL));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_installation(NULL, 0u, NULL));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_baud(NULL, 0u, LMS_BAUD_9600));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_request_values(NULL, 0u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_status(NULL, 0u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_errors(NULL, 0u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_type(NULL, 0u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_reset(NULL, 0u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_variant(NULL, 0u, 180u, 50u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_config_read(NULL, 0u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_config_write(NULL, 0u, &cfg));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_cmd_config_write(fresh_cmd(), 0u, NULL));
}

static void test_lms_encode_config_write_rejects_block_sizes(void)
{
    lms_config_t cfg;
    memset(&cfg, 0x11, sizeof cfg);
    const uint8_t sizes[] = {0u, 1u, 31u, 33u, 35u, 0xFFu};
    for (size_t k = 0u; k < sizeof sizes; k++) {
        cfg.size = sizes[k];
        char msg[16];
        (void)snprintf(msg, sizeof msg, "size %u", (unsigned)sizes[k]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_cmd_config_write(fresh_cmd(), 0u, &cfg), msg);
    }
}

/* --- lms_telegram_write -------------------------------------------------- */

static void test_lms_encode_telegram_write_vectors(void)
{
    uint8_t out[64];
    size_t written = 0u;
    const uint8_t status_cmd[1] = {0x31u};
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(out, sizeof out, 0x00u, status_cmd, 1u, -1,
                                                     &written));
    const lms_vector_t *v08 = vec("V08");
    TEST_ASSERT_EQUAL_UINT(v08->len, written);
    TEST_ASSERT_EQUAL_HEX8_ARRAY(v08->bytes, out, v08->len);

    /* Replies: the status byte comes from status_or_neg. */
    const uint8_t a0[2] = {0xA0u, 0x00u};
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(out, sizeof out, 0x81u, a0, 2u, 0x10,
                                                     &written));
    const lms_vector_t *v22 = vec("V22");
    TEST_ASSERT_EQUAL_UINT(v22->len, written);
    TEST_ASSERT_EQUAL_HEX8_ARRAY(v22->bytes, out, v22->len);

    const lms_vector_t *v28 = vec("V28");
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(out, v28->len, 0x80u, &v28->bytes[4],
                                                     v28->len - 7u, 0x10, &written));
    TEST_ASSERT_EQUAL_UINT(v28->len, written);
    TEST_ASSERT_EQUAL_HEX8_ARRAY(v28->bytes, out, v28->len);

    /* Status 0 is a status byte, not "none". */
    const uint8_t r91[1] = {0x91u};
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(out, sizeof out, 0x80u, r91, 1u, 0,
                                                     &written));
    TEST_ASSERT_EQUAL_UINT(8u, written);
    TEST_ASSERT_EQUAL_HEX8(2u, out[2]);
    TEST_ASSERT_EQUAL_HEX8(0u, out[5]);
    TEST_ASSERT_TRUE(tu_crc_ok(out, written));
}

static void test_lms_encode_telegram_write_limits(void)
{
    static uint8_t payload[LMS_LENGTH_MAX + 1u];
    static uint8_t out[LMS_TELEGRAM_MAX + 8u];
    memset(payload, 0x5A, sizeof payload);
    size_t written = 0u;
    /* L = LMS_LENGTH_MAX exactly fits: without a status, or with one. */
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(out, sizeof out, 0x00u, payload,
                                                     LMS_LENGTH_MAX, -1, &written));
    TEST_ASSERT_EQUAL_UINT(LMS_TELEGRAM_MAX, written);
    TEST_ASSERT_EQUAL_UINT16(LMS_LENGTH_MAX, tu_get_le16(&out[2]));
    TEST_ASSERT_TRUE(tu_crc_ok(out, written));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(out, LMS_TELEGRAM_MAX, 0x80u, payload,
                                                     LMS_LENGTH_MAX - 1u, 0x10, &written));
    TEST_ASSERT_EQUAL_UINT(LMS_TELEGRAM_MAX, written);
    /* One more is too much. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(out, sizeof out, 0x00u, payload,
                                                          LMS_LENGTH_MAX + 1u, -1, &written));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(out, sizeof out, 0x80u, payload,
                                                          LMS_LENGTH_MAX, 0x10, &written));
    /* Empty payload. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(out, sizeof out, 0x80u, payload, 0u,
                                                          0x10, &written));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(out, sizeof out, 0x00u, payload, 0u,
                                                          -1, &written));
    /* cap one byte short, exactly enough. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(out, 8u, 0x80u, payload, 2u, 0x10,
                                                          &written));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_telegram_write(out, 9u, 0x80u, payload, 2u, 0x10,
                                                     &written));
    TEST_ASSERT_EQUAL_UINT(9u, written);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(out, 6u, 0x00u, payload, 1u, -1,
                                                          &written));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(out, 0u, 0x00u, payload, 1u, -1,
                                                          &written));
    /* NULL pointers. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(NULL, 64u, 0x00u, payload, 1u, -1,
                                                          &written));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_telegram_write(out, 64u, 0x00u, NULL, 1u, -1,
                                                          &written));
}

/* --- lms_encode_scan ----------------------------------------------------- */

static lms_scan_t g_scan;
static lms_scan_t g_back;
static uint8_t g_buf[LMS_TELEGRAM_MAX + 16u];

static void test_lms_encode_scan_reencodes_b0_vectors(void)
{
    static const char *const ids[] = {"V30", "V31", "V32", "V33", "V35"};
    for (size_t k = 0u; k < sizeof ids / sizeof ids[0]; k++) {
        const lms_vector_t *v = vec(ids[k]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_decode_scan(v->bytes, v->len, &g_scan), v->id);
        memset(g_buf, 0xA5, sizeof g_buf);
        size_t written = 0u;
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_encode_scan(g_buf, sizeof g_buf, g_scan.address,
                                                              &g_scan, &written),
                                      v->id);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(v->len, written, v->id);
        TEST_ASSERT_EQUAL_HEX8_ARRAY_MESSAGE(v->bytes, g_buf, v->len, v->id);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0xA5u, g_buf[v->len], v->id); /* nothing beyond */
        /* Exactly the needed capacity is enough. */
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_encode_scan(g_buf, v->len, g_scan.address,
                                                              &g_scan, &written),
                                      v->id);
    }
}

/* Seeded random scans (181/361/401/101/201 values, either unit, partial
 * or not, with or without indices, any value words) survive encode then
 * decode unchanged, and the size is 2N + 10 (+ 2). */
static void test_lms_encode_scan_round_trip(void)
{
    static const uint16_t counts[] = {0u, 1u, 101u, 181u, 201u, 361u, 401u};
    uint32_t rng = 0xBADC0DEu;
    for (unsigned round = 0u; round < 60u; round++) {
        memset(&g_scan, 0, sizeof g_scan);
        g_scan.count = counts[tu_rand_range(&rng, 0u, 6u)];
        g_scan.unit = (tu_rand(&rng) & 1u) != 0u ? LMS_UNIT_MM : LMS_UNIT_CM;
        g_scan.is_partial = (tu_rand(&rng) & 3u) == 0u;
        /* A full scan has index 0 (the encoder need not write the index
         * bits of a non-partial scan). */
        g_scan.partial_index = g_scan.is_partial ? (uint8_t)tu_rand_range(&rng, 0u, 3u) : 0u;
        g_scan.has_indices = (tu_rand(&rng) & 1u) != 0u;
        g_scan.scan_index = tu_rand_byte(&rng);
        g_scan.telegram_index = tu_rand_byte(&rng);
        g_scan.status = tu_rand_byte(&rng);
        const uint8_t addr = (uint8_t)(0x80u | tu_rand_range(&rng, 0u, 0x7Fu));
        g_scan.address = addr;
        for (size_t i = 0u; i < g_scan.count; i++) {
            g_scan.values[i] = (uint16_t)tu_rand(&rng);
        }
        char msg[48];
        (void)snprintf(msg, sizeof msg, "round %u N %u", round, (unsigned)g_scan.count);
        size_t written = 0u;
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_encode_scan(g_buf, sizeof g_buf, addr, &g_scan,
                                                              &written),
                                      msg);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(2u * g_scan.count + 10u + (g_scan.has_indices ? 2u : 0u),
                                       written, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(addr, g_buf[1], msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(LMS_REPLY_VALUES, g_buf[4], msg);
        const uint16_t cw = tu_get_le16(&g_buf[5]);
        TEST_ASSERT_EQUAL_HEX16_MESSAGE(
            (uint16_t)(g_scan.count | ((unsigned)g_scan.partial_index << 11) |
                       (g_scan.is_partial ? 0x2000u : 0u) |
                       (g_scan.unit == LMS_UNIT_MM ? 0x4000u : 0u)),
            cw, msg);
        memset(&g_back, 0xA5, sizeof g_back);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_OK, lms_decode_scan(g_buf, written, &g_back), msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(addr, g_back.address, msg);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(g_scan.status, g_back.status, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(g_scan.unit, g_back.unit, msg);
        TEST_ASSERT_EQUAL_UINT16_MESSAGE(g_scan.count, g_back.count, msg);
        TEST_ASSERT_EQUAL_MESSAGE(g_scan.is_partial, g_back.is_partial, msg);
        TEST_ASSERT_EQUAL_UINT8_MESSAGE(g_scan.partial_index, g_back.partial_index, msg);
        TEST_ASSERT_EQUAL_MESSAGE(g_scan.has_indices, g_back.has_indices, msg);
        if (g_scan.has_indices) {
            TEST_ASSERT_EQUAL_HEX8_MESSAGE(g_scan.scan_index, g_back.scan_index, msg);
            TEST_ASSERT_EQUAL_HEX8_MESSAGE(g_scan.telegram_index, g_back.telegram_index, msg);
        }
        if (g_scan.count > 0u) {
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(g_scan.values, g_back.values,
                                             sizeof(uint16_t) * g_scan.count, msg);
        }
    }
}

static void test_lms_encode_scan_rejects_bad_arguments(void)
{
    size_t written = 0u;
    memset(&g_scan, 0, sizeof g_scan);
    g_scan.count = 181u;
    g_scan.unit = LMS_UNIT_MM;
    g_scan.status = 0x10u;
    /* Capacity: 2N + 10 needed, 2N + 12 with indices. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_encode_scan(g_buf, 371u, 0x80u, &g_scan, &written));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(g_buf, 372u, 0x80u, &g_scan, &written));
    TEST_ASSERT_EQUAL_UINT(372u, written);
    g_scan.has_indices = true;
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_encode_scan(g_buf, 373u, 0x80u, &g_scan, &written));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(g_buf, 374u, 0x80u, &g_scan, &written));
    TEST_ASSERT_EQUAL_UINT(374u, written);
    g_scan.has_indices = false;
    /* A host address. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_encode_scan(g_buf, sizeof g_buf, 0x00u, &g_scan,
                                                       &written));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_encode_scan(g_buf, sizeof g_buf, 0x7Fu, &g_scan,
                                                       &written));
    /* partial_index above 3. */
    g_scan.is_partial = true;
    g_scan.partial_index = 4u;
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_encode_scan(g_buf, sizeof g_buf, 0x80u, &g_scan,
                                                       &written));
    g_scan.partial_index = 3u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(g_buf, sizeof g_buf, 0x80u, &g_scan, &written));
    /* count above LMS_SCAN_MAX_VALUES. */
    g_scan.count = (uint16_t)(LMS_SCAN_MAX_VALUES + 1u);
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_encode_scan(g_buf, sizeof g_buf, 0x80u, &g_scan,
                                                       &written));
    g_scan.count = LMS_SCAN_MAX_VALUES;
    g_scan.has_indices = true;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(g_buf, sizeof g_buf, 0x80u, &g_scan, &written));
    TEST_ASSERT_EQUAL_UINT(LMS_TELEGRAM_MAX, written);
    /* NULL pointers. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_encode_scan(NULL, sizeof g_buf, 0x80u, &g_scan,
                                                       &written));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_encode_scan(g_buf, sizeof g_buf, 0x80u, NULL,
                                                       &written));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_encode_mode_vectors);
    RUN_TEST(test_lms_encode_baud_vectors);
    RUN_TEST(test_lms_encode_installation_vector);
    RUN_TEST(test_lms_encode_installation_rejects_password_length);
    RUN_TEST(test_lms_encode_simple_command_vectors);
    RUN_TEST(test_lms_encode_variant_vectors);
    RUN_TEST(test_lms_encode_config_write_vector);
    RUN_TEST(test_lms_encode_config_write_old_size);
    RUN_TEST(test_lms_encode_addresses);
    RUN_TEST(test_lms_encode_variant_legality);
    RUN_TEST(test_lms_encode_rejects_reply_addresses);
    RUN_TEST(test_lms_encode_rejects_modes_with_parameters);
    RUN_TEST(test_lms_encode_rejects_null_out);
    RUN_TEST(test_lms_encode_config_write_rejects_block_sizes);
    RUN_TEST(test_lms_encode_telegram_write_vectors);
    RUN_TEST(test_lms_encode_telegram_write_limits);
    RUN_TEST(test_lms_encode_scan_reencodes_b0_vectors);
    RUN_TEST(test_lms_encode_scan_round_trip);
    RUN_TEST(test_lms_encode_scan_rejects_bad_arguments);
    return UNITY_END();
}
