/* test_lms_config.c - the configuration block accessors (lms_config.h) and
 * the small protocol lookups of lms_proto.h (status names, measuring-mode
 * bits, baud rates).
 */
#include <string.h>

#include "lms_config.h"
#include "lms_proto.h"
#include "lms_vectors.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* The 34-byte block of V34 (mode 02, cm, real-time indices on). */
static lms_config_t v34_config(void)
{
    const lms_vector_t *v = lms_vector_find("V34");
    TEST_ASSERT_NOT_NULL(v);
    lms_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.size = LMS_CONFIG_SIZE_NEW;
    memcpy(cfg.block, &v->bytes[5], LMS_CONFIG_SIZE_NEW);
    return cfg;
}

static void test_lms_config_getters_on_v34(void)
{
    const lms_config_t cfg = v34_config();
    TEST_ASSERT_EQUAL_HEX8(0x02u, lms_config_meas_mode(&cfg));
    TEST_ASSERT_EQUAL_HEX8(0x00u, lms_config_units(&cfg));
    TEST_ASSERT_TRUE(lms_config_has_indices(&cfg));
}

static void test_lms_config_getters_read_their_offsets(void)
{
    lms_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.size = LMS_CONFIG_SIZE_OLD;
    cfg.block[LMS_CONFIG_OFF_MEAS_MODE] = 0x3Fu;
    cfg.block[LMS_CONFIG_OFF_UNITS] = 0x17u; /* reserved: returned raw */
    cfg.block[LMS_CONFIG_OFF_AVAILABILITY] = 0xFDu; /* every bit but bit 1 */
    TEST_ASSERT_EQUAL_HEX8(0x3Fu, lms_config_meas_mode(&cfg));
    TEST_ASSERT_EQUAL_HEX8(0x17u, lms_config_units(&cfg));
    TEST_ASSERT_FALSE(lms_config_has_indices(&cfg));
    cfg.block[LMS_CONFIG_OFF_AVAILABILITY] = 0x02u;
    TEST_ASSERT_TRUE(lms_config_has_indices(&cfg));
}

/* Each setter changes only its own byte (and only bit 1 of availability). */
static void test_lms_config_setters_touch_only_their_field(void)
{
    static const uint8_t modes[] = {0x00u, 0x01u, 0x02u, 0x03u, 0x04u,
                                    0x05u, 0x06u, 0x0Fu, 0x3Fu};
    const lms_config_t orig = v34_config();
    for (size_t k = 0u; k < sizeof modes; k++) {
        lms_config_t cfg = orig;
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_meas_mode(&cfg, modes[k]));
        TEST_ASSERT_EQUAL_HEX8(modes[k], lms_config_meas_mode(&cfg));
        lms_config_t want = orig;
        want.block[LMS_CONFIG_OFF_MEAS_MODE] = modes[k];
        TEST_ASSERT_EQUAL_HEX8_ARRAY(want.block, cfg.block, LMS_CONFIG_SIZE_NEW);
        TEST_ASSERT_EQUAL_UINT8(LMS_CONFIG_SIZE_NEW, cfg.size);
    }
    lms_config_t cfg = orig;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_unit(&cfg, LMS_UNIT_MM));
    TEST_ASSERT_EQUAL_HEX8(0x01u, lms_config_units(&cfg));
    lms_config_t want = orig;
    want.block[LMS_CONFIG_OFF_UNITS] = 0x01u;
    TEST_ASSERT_EQUAL_HEX8_ARRAY(want.block, cfg.block, LMS_CONFIG_SIZE_NEW);
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_unit(&cfg, LMS_UNIT_CM));
    TEST_ASSERT_EQUAL_HEX8_ARRAY(orig.block, cfg.block, LMS_CONFIG_SIZE_NEW);

    /* Availability: the other bits survive both ways. */
    cfg = orig;
    cfg.block[LMS_CONFIG_OFF_AVAILABILITY] = 0xFFu;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_indices(&cfg, false));
    TEST_ASSERT_EQUAL_HEX8(0xFDu, cfg.block[LMS_CONFIG_OFF_AVAILABILITY]);
    TEST_ASSERT_FALSE(lms_config_has_indices(&cfg));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_indices(&cfg, true));
    TEST_ASSERT_EQUAL_HEX8(0xFFu, cfg.block[LMS_CONFIG_OFF_AVAILABILITY]);
    cfg.block[LMS_CONFIG_OFF_AVAILABILITY] = 0x05u;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_indices(&cfg, true));
    TEST_ASSERT_EQUAL_HEX8(0x07u, cfg.block[LMS_CONFIG_OFF_AVAILABILITY]);
    TEST_ASSERT_TRUE(lms_config_has_indices(&cfg));
    want = orig;
    want.block[LMS_CONFIG_OFF_AVAILABILITY] = 0x07u;
    TEST_ASSERT_EQUAL_HEX8_ARRAY(want.block, cfg.block, LMS_CONFIG_SIZE_NEW);
}

static void test_lms_config_setters_work_on_32_byte_blocks(void)
{
    lms_config_t cfg;
    memset(&cfg, 0x44, sizeof cfg);
    cfg.size = LMS_CONFIG_SIZE_OLD;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_meas_mode(&cfg, 0x05u));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_unit(&cfg, LMS_UNIT_CM));
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_config_set_indices(&cfg, true));
    TEST_ASSERT_EQUAL_HEX8(0x05u, lms_config_meas_mode(&cfg));
    TEST_ASSERT_EQUAL_HEX8(0x00u, lms_config_units(&cfg));
    TEST_ASSERT_EQUAL_HEX8(0x46u, cfg.block[LMS_CONFIG_OFF_AVAILABILITY]);
    TEST_ASSERT_EQUAL_UINT8(LMS_CONFIG_SIZE_OLD, cfg.size);
}

static void test_lms_config_setters_reject_bad_arguments(void)
{
    const lms_config_t orig = v34_config();
    lms_config_t cfg = orig;
    /* Unknown measuring modes. */
    const uint8_t bad_modes[] = {0x07u, 0x08u, 0x0Du, 0x0Eu, 0x10u, 0x3Eu, 0x40u, 0xFFu};
    for (size_t k = 0u; k < sizeof bad_modes; k++) {
        char msg[16];
        (void)snprintf(msg, sizeof msg, "mode 0x%02X", (unsigned)bad_modes[k]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_config_set_meas_mode(&cfg, bad_modes[k]),
                                      msg);
        TEST_ASSERT_EQUAL_HEX8_ARRAY_MESSAGE(orig.block, cfg.block, LMS_CONFIG_SIZE_NEW, msg);
    }
    /* Units other than cm/mm. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_config_set_unit(&cfg, (lms_unit_t)2));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_config_set_unit(&cfg, (lms_unit_t)0x10));
    TEST_ASSERT_EQUAL_HEX8_ARRAY(orig.block, cfg.block, LMS_CONFIG_SIZE_NEW);
    /* Block sizes other than 32 / 34. */
    const uint8_t sizes[] = {0u, 31u, 33u, 35u, 0xFFu};
    for (size_t k = 0u; k < sizeof sizes; k++) {
        cfg = orig;
        cfg.size = sizes[k];
        char msg[16];
        (void)snprintf(msg, sizeof msg, "size %u", (unsigned)sizes[k]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_config_set_meas_mode(&cfg, 0x00u), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_config_set_unit(&cfg, LMS_UNIT_MM), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(LMS_ERR_ARG, lms_config_set_indices(&cfg, false), msg);
        TEST_ASSERT_EQUAL_HEX8_ARRAY_MESSAGE(orig.block, cfg.block, LMS_CONFIG_SIZE_NEW, msg);
    }
    /* NULL. */
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_config_set_meas_mode(NULL, 0x00u));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_config_set_unit(NULL, LMS_UNIT_MM));
    TEST_ASSERT_EQUAL_INT(LMS_ERR_ARG, lms_config_set_indices(NULL, true));
}

/* --- lms_proto.h lookups ------------------------------------------------- */

static void test_lms_config_proto_meas_mode_bits(void)
{
    for (unsigned m = 0u; m <= 0xFFu; m++) {
        unsigned want = 0u;
        if (m <= 0x02u) {
            want = 13u;
        } else if (m <= 0x04u) {
            want = 14u;
        } else if (m <= 0x06u) {
            want = 15u;
        } else if (m == 0x0Fu || m == 0x3Fu) {
            want = 16u;
        }
        char msg[16];
        (void)snprintf(msg, sizeof msg, "mode 0x%02X", m);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(want, lms_meas_mode_bits((uint8_t)m), msg);
    }
}

static void test_lms_config_proto_baud_bps(void)
{
    TEST_ASSERT_EQUAL_UINT32(9600u, lms_baud_bps(LMS_BAUD_9600));
    TEST_ASSERT_EQUAL_UINT32(19200u, lms_baud_bps(LMS_BAUD_19200));
    TEST_ASSERT_EQUAL_UINT32(38400u, lms_baud_bps(LMS_BAUD_38400));
    TEST_ASSERT_EQUAL_UINT32(500000u, lms_baud_bps(LMS_BAUD_500000));
    TEST_ASSERT_EQUAL_UINT32(0u, lms_baud_bps((lms_baud_t)LMS_BAUD_COUNT));
    TEST_ASSERT_EQUAL_UINT32(0u, lms_baud_bps((lms_baud_t)99));
}

static void test_lms_config_proto_status_names(void)
{
    static const lms_status_t all[] = {LMS_OK,        LMS_ERR_ARG,  LMS_ERR_FRAME,
                                       LMS_ERR_CRC,   LMS_ERR_CODE, LMS_ERR_SIZE,
                                       LMS_ERR_VALUE};
    const size_t n = sizeof all / sizeof all[0];
    for (size_t i = 0u; i < n; i++) {
        const char *a = lms_status_name(all[i]);
        TEST_ASSERT_NOT_NULL(a);
        TEST_ASSERT_TRUE(strlen(a) > 0u);
        for (size_t j = 0u; j < i; j++) {
            TEST_ASSERT_TRUE(strcmp(a, lms_status_name(all[j])) != 0);
        }
    }
    TEST_ASSERT_EQUAL_STRING("crc mismatch", lms_status_name(LMS_ERR_CRC));
    const char *unknown = lms_status_name((lms_status_t)-42);
    TEST_ASSERT_NOT_NULL(unknown);
    TEST_ASSERT_TRUE(strlen(unknown) > 0u);
}

static void test_lms_config_proto_size_constants(void)
{
    /* The largest B0: N values with indices, L = 2N + 6; 808 / 814 bytes
     * for the default 401 values. */
    TEST_ASSERT_EQUAL_UINT(2u * LMS_SCAN_MAX_VALUES + 6u, LMS_LENGTH_MAX);
    TEST_ASSERT_EQUAL_UINT(LMS_LENGTH_MAX + 6u, LMS_TELEGRAM_MAX);
    if (LMS_SCAN_MAX_VALUES == 401u) {
        TEST_ASSERT_EQUAL_UINT(808u, LMS_LENGTH_MAX);
        TEST_ASSERT_EQUAL_UINT(814u, LMS_TELEGRAM_MAX);
    }
    TEST_ASSERT_EQUAL_UINT(41u, LMS_CMD_MAX); /* V34 is the largest host telegram */
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_config_getters_on_v34);
    RUN_TEST(test_lms_config_getters_read_their_offsets);
    RUN_TEST(test_lms_config_setters_touch_only_their_field);
    RUN_TEST(test_lms_config_setters_work_on_32_byte_blocks);
    RUN_TEST(test_lms_config_setters_reject_bad_arguments);
    RUN_TEST(test_lms_config_proto_meas_mode_bits);
    RUN_TEST(test_lms_config_proto_baud_bps);
    RUN_TEST(test_lms_config_proto_status_names);
    RUN_TEST(test_lms_config_proto_size_constants);
    return UNITY_END();
}
