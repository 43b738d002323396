/* test_lms_crc.c - the LMS 2xx "CRC SICK" (lms_crc.h): published check
 * values, the CRC of every vector V01..V35, an independent bit-level
 * reference written from the protocol notes' formula, and incremental
 * updates in arbitrary splits.
 */
#include <string.h>

#include "lms_crc.h"
#include "lms_test_util.h"
#include "lms_vectors.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* Reference from the notes' formula, written differently from the driver:
 * R_i = shl1(R_{i-1}) ^ msb(R_{i-1}) * 0x8005 ^ (b_{i-1} * 2^8 + b_i). */
static uint16_t ref_crc(const uint8_t *data, size_t len)
{
    uint32_t r = 0u;
    uint32_t prev = 0u;
    for (size_t i = 0u; i < len; i++) {
        const uint32_t msb = (r >> 15) & 1u;
        r = ((r << 1) & 0xFFFFu) ^ (msb * 0x8005u) ^ ((prev << 8) | data[i]);
        prev = data[i];
    }
    return (uint16_t)r;
}

static uint16_t crc_of_string(const char *s)
{
    return lms_crc16((const uint8_t *)s, strlen(s));
}

static void test_lms_crc_check_values(void)
{
    TEST_ASSERT_EQUAL_HEX16(0xA656u, crc_of_string("123456789"));
    TEST_ASSERT_EQUAL_HEX16(0x0811u, crc_of_string("Lammert Bies"));
    TEST_ASSERT_EQUAL_HEX16(0x0020u, crc_of_string(" "));
    TEST_ASSERT_EQUAL_HEX16(0x0000u, crc_of_string(""));
    /* Continuous-output request 20 24 (V01 without its CRC). */
    const uint8_t v01_body[] = {0x02, 0x00, 0x02, 0x00, 0x20, 0x24};
    TEST_ASSERT_EQUAL_HEX16(0x0834u, lms_crc16(v01_body, sizeof v01_body));
}

static void test_lms_crc_empty_input_with_null_data(void)
{
    TEST_ASSERT_EQUAL_HEX16(0x0000u, lms_crc16(NULL, 0u));
    lms_crc_t c;
    lms_crc_init(&c);
    lms_crc_update(&c, NULL, 0u);
    TEST_ASSERT_EQUAL_HEX16(0x0000u, c.reg);
    TEST_ASSERT_EQUAL_HEX8(0x00u, c.prev);
}

static void test_lms_crc_init_resets_a_used_state(void)
{
    lms_crc_t c;
    memset(&c, 0xFF, sizeof c);
    lms_crc_init(&c);
    TEST_ASSERT_EQUAL_HEX16(0u, c.reg);
    TEST_ASSERT_EQUAL_HEX8(0u, c.prev);
    lms_crc_update(&c, (const uint8_t *)"123456789", 9u);
    TEST_ASSERT_EQUAL_HEX16(0xA656u, c.reg);
    TEST_ASSERT_EQUAL_HEX8((uint8_t)'9', c.prev);
    lms_crc_init(&c);
    lms_crc_update(&c, (const uint8_t *)"123456789", 9u);
    TEST_ASSERT_EQUAL_HEX16(0xA656u, c.reg);
}

/* The CRC of every published/synthetic telegram, over STX .. last data
 * byte, equals its last two bytes (low byte first). */
static void test_lms_crc_every_vector(void)
{
    for (size_t i = 0u; i < LMS_VECTOR_COUNT; i++) {
        const lms_vector_t *v = &lms_vectors[i];
        TEST_ASSERT_TRUE_MESSAGE(v->len >= LMS_OVERHEAD + 1u, v->id);
        const uint16_t wire = (uint16_t)(v->bytes[v->len - 2u] | (v->bytes[v->len - 1u] << 8));
        TEST_ASSERT_EQUAL_HEX16_MESSAGE(wire, lms_crc16(v->bytes, v->len - 2u), v->id);
        TEST_ASSERT_EQUAL_HEX16_MESSAGE(wire, ref_crc(v->bytes, v->len - 2u), v->id);
    }
}

/* The driver's CRC equals the formula reference on seeded random data of
 * every length 0..300 (covers bit-15 feedback in every position). */
static void test_lms_crc_matches_reference_on_random_data(void)
{
    static uint8_t buf[300];
    uint32_t rng = 0x1234567u;
    for (size_t len = 0u; len <= sizeof buf; len++) {
        for (size_t i = 0u; i < len; i++) {
            buf[i] = tu_rand_byte(&rng);
        }
        char msg[32];
        (void)snprintf(msg, sizeof msg, "len %u", (unsigned)len);
        TEST_ASSERT_EQUAL_HEX16_MESSAGE(ref_crc(buf, len), lms_crc16(buf, len), msg);
    }
    /* All-0xFF and all-0x00 runs. */
    memset(buf, 0xFF, sizeof buf);
    TEST_ASSERT_EQUAL_HEX16(ref_crc(buf, sizeof buf), lms_crc16(buf, sizeof buf));
    memset(buf, 0x00, sizeof buf);
    TEST_ASSERT_EQUAL_HEX16(0x0000u, lms_crc16(buf, sizeof buf));
}

/* Changing any single bit of a telegram's body changes its CRC. */
static void test_lms_crc_detects_every_single_bit_flip(void)
{
    const lms_vector_t *v = lms_vector_find("V35");
    TEST_ASSERT_NOT_NULL(v);
    static uint8_t buf[LMS_TELEGRAM_MAX];
    const size_t n = v->len - 2u;
    const uint16_t good = lms_crc16(v->bytes, n);
    memcpy(buf, v->bytes, n);
    for (size_t i = 0u; i < n; i++) {
        for (unsigned bit = 0u; bit < 8u; bit++) {
            buf[i] = (uint8_t)(buf[i] ^ (1u << bit));
            TEST_ASSERT_TRUE(lms_crc16(buf, n) != good);
            buf[i] = (uint8_t)(buf[i] ^ (1u << bit));
        }
    }
}

static uint16_t crc_split(const uint8_t *data, size_t len, const size_t *cuts, size_t ncuts)
{
    lms_crc_t c;
    lms_crc_init(&c);
    size_t at = 0u;
    for (size_t k = 0u; k < ncuts; k++) {
        lms_crc_update(&c, data + at, cuts[k] - at);
        at = cuts[k];
    }
    lms_crc_update(&c, data + at, len - at);
    return c.reg;
}

/* Two-piece split at every position of every vector equals the one-shot
 * value; so does an empty update in between. */
static void test_lms_crc_incremental_split_at_every_position(void)
{
    for (size_t i = 0u; i < LMS_VECTOR_COUNT; i++) {
        const lms_vector_t *v = &lms_vectors[i];
        const size_t n = v->len - 2u;
        const uint16_t one_shot = lms_crc16(v->bytes, n);
        for (size_t cut = 0u; cut <= n; cut++) {
            const size_t cuts[2] = {cut, cut};
            TEST_ASSERT_EQUAL_HEX16_MESSAGE(one_shot, crc_split(v->bytes, n, cuts, 2u), v->id);
        }
    }
}

/* Seeded random multi-piece splits (including empty pieces) of random data
 * and of the check strings. */
static void test_lms_crc_incremental_random_splits(void)
{
    static uint8_t buf[LMS_TELEGRAM_MAX];
    uint32_t rng = 0xC0FFEEu;
    for (unsigned round = 0u; round < 400u; round++) {
        const size_t len = tu_rand_range(&rng, 0u, (uint32_t)sizeof buf);
        for (size_t i = 0u; i < len; i++) {
            buf[i] = tu_rand_byte(&rng);
        }
        size_t cuts[16];
        size_t ncuts = tu_rand_range(&rng, 0u, 16u);
        size_t at = 0u;
        for (size_t k = 0u; k < ncuts; k++) {
            at += tu_rand_range(&rng, 0u, (uint32_t)((len - at) / 2u + 1u));
            if (at > len) {
                at = len;
            }
            cuts[k] = at;
        }
        char msg[32];
        (void)snprintf(msg, sizeof msg, "round %u", round);
        TEST_ASSERT_EQUAL_HEX16_MESSAGE(lms_crc16(buf, len), crc_split(buf, len, cuts, ncuts), msg);
    }
    const char *s = "123456789";
    lms_crc_t c;
    lms_crc_init(&c);
    for (size_t i = 0u; i < 9u; i++) {
        lms_crc_update(&c, (const uint8_t *)s + i, 1u);
    }
    TEST_ASSERT_EQUAL_HEX16(0xA656u, c.reg);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lms_crc_check_values);
    RUN_TEST(test_lms_crc_empty_input_with_null_data);
    RUN_TEST(test_lms_crc_init_resets_a_used_state);
    RUN_TEST(test_lms_crc_every_vector);
    RUN_TEST(test_lms_crc_matches_reference_on_random_data);
    RUN_TEST(test_lms_crc_detects_every_single_bit_flip);
    RUN_TEST(test_lms_crc_incremental_split_at_every_position);
    RUN_TEST(test_lms_crc_incremental_random_splits);
    return UNITY_END();
}
