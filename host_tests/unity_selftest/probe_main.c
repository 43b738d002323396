/* probe_main.c - self-test probe of the Unity-compatible harness.
 *
 * Deliberately mixes passing, failing and ignored tests: every assertion
 * family fails once with its built-in text and once through its _MESSAGE
 * variant, and the passing tests exercise the edge cases that must pass.
 * Not a unit test: run_probe.cmake compares its stdout with
 * expected_main.txt and its exit status with the number of failures.
 * Built without UNITY_INCLUDE_DOUBLE. Line numbers are part of the expected
 * output: edit expected_main.txt together with this file.
 */
#include "unity.h"

static int skipped_code_ran; /* set only by code that must be skipped */
static const int *const some_pointer = &skipped_code_ran;

void setUp(void) {}
void tearDown(void) {}

static void fail_in_helper(int value)
{
    TEST_ASSERT_EQUAL_INT(1, value);
    skipped_code_ran = 1;
}

/* ---- Passing: edge cases that must pass --------------------------------- */

static void test_passes_boolean_and_integers(void)
{
    const int one = skipped_code_ran + 1; /* 1, opaque to analysers */
    const int *some = &one;
    const int *none = NULL;
    TEST_ASSERT(one == 1);
    TEST_ASSERT_TRUE(one);
    TEST_ASSERT_FALSE(one - 1);
    TEST_ASSERT_NULL(none);
    TEST_ASSERT_NOT_NULL(some);
    TEST_ASSERT_EQUAL(-5, -5);
    TEST_ASSERT_EQUAL_INT(INT_MIN, INT_MIN);
    TEST_ASSERT_EQUAL_INT(INTMAX_MIN, INTMAX_MIN);
    TEST_ASSERT_EQUAL_INT8(127, 0x17F);
    TEST_ASSERT_EQUAL_INT16(-1, 0xFFFF);
    TEST_ASSERT_EQUAL_INT32(INT32_MAX, 0x17FFFFFFFLL);
    TEST_ASSERT_EQUAL_UINT(UINTMAX_MAX, UINTMAX_MAX);
    TEST_ASSERT_EQUAL_UINT8(0x102, 2);
    TEST_ASSERT_EQUAL_UINT16(0x10005, 5);
    TEST_ASSERT_EQUAL_UINT32(0x100000007ULL, 7);
    TEST_ASSERT_EQUAL_HEX8(0x1A5, 0xA5);
    TEST_ASSERT_EQUAL_HEX16(0x1BEEF, 0xBEEF);
    TEST_ASSERT_EQUAL_HEX32(0xDEADBEEF, 0xDEADBEEFu);
    TEST_ASSERT_EQUAL_HEX(0x1DEADBEEFULL, 0xDEADBEEFu);
    TEST_ASSERT_INT_WITHIN(3, 10, 13);
    TEST_ASSERT_INT_WITHIN(3, 10, 7);
    TEST_ASSERT_INT_WITHIN(UINTMAX_MAX, INTMAX_MIN, INTMAX_MAX);
    TEST_ASSERT_INT16_WITHIN(0xFFFF, INT16_MIN, INT16_MAX);
    TEST_ASSERT_INT32_WITHIN(UINT32_MAX, INT32_MIN, INT32_MAX);
    TEST_ASSERT_UINT_WITHIN(1, UINT_MAX, UINT_MAX - 1u);
    TEST_ASSERT_HEX8_WITHIN(2, 0xFF, 0x1FD);
}

static void test_passes_float_memory_arrays_strings(void)
{
    static const unsigned char bytes[] = {1, 2, 3};
    static const unsigned char same[] = {1, 2, 3};
    static const int16_t i16[] = {-300, 300};
    static const int32_t i32[] = {INT32_MIN, INT32_MAX};
    const char *none = NULL;
    TEST_ASSERT_FLOAT_WITHIN(0.5f, 1.0f, 1.5f);
    TEST_ASSERT_FLOAT_WITHIN(0.5f, 1.0f, 0.5f);
    TEST_ASSERT_FLOAT_WITHIN(0.0f, NAN, NAN);
    TEST_ASSERT_FLOAT_WITHIN(0.0f, INFINITY, INFINITY);
    TEST_ASSERT_FLOAT_WITHIN(0.0f, -INFINITY, -INFINITY);
    TEST_ASSERT_FLOAT_WITHIN(-0.5f, 2.0f, 2.5f);
    TEST_ASSERT_EQUAL_MEMORY(bytes, same, sizeof bytes);
    TEST_ASSERT_EQUAL_MEMORY(bytes, bytes, sizeof bytes);
    TEST_ASSERT_EQUAL_MEMORY(NULL, NULL, 4);
    TEST_ASSERT_EQUAL_UINT8_ARRAY(bytes, same, 3);
    TEST_ASSERT_EQUAL_HEX8_ARRAY(bytes, same, 3);
    TEST_ASSERT_EQUAL_INT16_ARRAY(i16, i16, 2);
    TEST_ASSERT_EQUAL_INT32_ARRAY(i32, i32, 2);
    TEST_ASSERT_EQUAL_STRING("abc", "abc");
    TEST_ASSERT_EQUAL_STRING("", "");
    TEST_ASSERT_EQUAL_STRING(none, NULL);
}

static void test_passes_every_message_variant(void)
{
    static const uint8_t u8[] = {0x80, 0x7F};
    static const int16_t i16[] = {-1, 1};
    static const int32_t i32[] = {-1, 1};
    const int one = skipped_code_ran + 1; /* 1, opaque to analysers */
    TEST_ASSERT_MESSAGE(one == 1, "m");
    TEST_ASSERT_TRUE_MESSAGE(one, "m");
    TEST_ASSERT_FALSE_MESSAGE(one - 1, "m");
    TEST_ASSERT_NULL_MESSAGE(NULL, "m");
    TEST_ASSERT_NOT_NULL_MESSAGE(some_pointer, "m");
    TEST_ASSERT_EQUAL_MESSAGE(3, 3, "m");
    TEST_ASSERT_EQUAL_INT_MESSAGE(-3, -3, "m");
    TEST_ASSERT_EQUAL_INT8_MESSAGE(-1, 0xFF, "m");
    TEST_ASSERT_EQUAL_INT16_MESSAGE(-1, 0xFFFF, "m");
    TEST_ASSERT_EQUAL_INT32_MESSAGE(-1, 0xFFFFFFFF, "m");
    TEST_ASSERT_EQUAL_UINT_MESSAGE(7u, 7u, "m");
    TEST_ASSERT_EQUAL_UINT8_MESSAGE(0x102, 2, "m");
    TEST_ASSERT_EQUAL_UINT16_MESSAGE(0x10002, 2, "m");
    TEST_ASSERT_EQUAL_UINT32_MESSAGE(0x100000002ULL, 2, "m");
    TEST_ASSERT_EQUAL_HEX_MESSAGE(0x100000002ULL, 2, "m");
    TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x102, 2, "m");
    TEST_ASSERT_EQUAL_HEX16_MESSAGE(0x10002, 2, "m");
    TEST_ASSERT_EQUAL_HEX32_MESSAGE(0x100000002ULL, 2, "m");
    TEST_ASSERT_INT_WITHIN_MESSAGE(1, -1, 0, "m");
    TEST_ASSERT_INT16_WITHIN_MESSAGE(1, 0x10000, 1, "m");
    TEST_ASSERT_INT32_WITHIN_MESSAGE(1, 0x100000000LL, 1, "m");
    TEST_ASSERT_UINT_WITHIN_MESSAGE(1, 5u, 6u, "m");
    TEST_ASSERT_HEX8_WITHIN_MESSAGE(1, 0x100, 1, "m");
    TEST_ASSERT_FLOAT_WITHIN_MESSAGE(0.25f, 1.0f, 1.25f, "m");
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(u8, u8, sizeof u8, "m");
    TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(u8, u8, 2, "m");
    TEST_ASSERT_EQUAL_INT16_ARRAY_MESSAGE(i16, i16, 2, "m");
    TEST_ASSERT_EQUAL_INT32_ARRAY_MESSAGE(i32, i32, 2, "m");
    TEST_ASSERT_EQUAL_HEX8_ARRAY_MESSAGE(u8, u8, 2, "m");
    TEST_ASSERT_EQUAL_STRING_MESSAGE("x", "x", "m");
}

static void test_passes_with_explicit_line(void) { TEST_ASSERT_TRUE(1); }

/* ---- Control ------------------------------------------------------------ */

static void test_fail(void) { TEST_FAIL(); }
static void test_fail_message(void) { TEST_FAIL_MESSAGE("boom"); }
static void test_ignore(void) { TEST_IGNORE(); }
static void test_ignore_message(void) { TEST_IGNORE_MESSAGE("not yet"); }
static void test_message_then_pass(void) { TEST_MESSAGE("note"); TEST_MESSAGE("again"); }
static void test_message_then_fail(void) { TEST_MESSAGE("before"); TEST_FAIL(); }
static void test_message_escaped(void) { TEST_FAIL_MESSAGE("tab\there\r\n"); }

static void test_only_first_failure_reported(void)
{
    TEST_ASSERT_EQUAL_INT(1, 2);
    skipped_code_ran = 1;
    TEST_ASSERT_EQUAL_INT(3, 4);
}

static void test_failure_in_helper_leaves_test(void)
{
    fail_in_helper(2);
    skipped_code_ran = 1;
}

static void test_ignore_skips_rest(void)
{
    TEST_IGNORE_MESSAGE("skip");
    skipped_code_ran = 1;
}

static void test_skipped_code_never_ran(void) { TEST_ASSERT_EQUAL_INT(0, skipped_code_ran); }

/* ---- Boolean ------------------------------------------------------------ */

static void test_assert(void) { TEST_ASSERT(skipped_code_ran == 1); }
static void test_assert_message(void) { TEST_ASSERT_MESSAGE(0 > 1, "assert message"); }
static void test_true(void) { TEST_ASSERT_TRUE(skipped_code_ran); }
static void test_true_message(void) { TEST_ASSERT_TRUE_MESSAGE(0, "true message"); }
static void test_false(void) { TEST_ASSERT_FALSE(1); }
static void test_false_message(void) { TEST_ASSERT_FALSE_MESSAGE(1, "false message"); }
static void test_null(void) { TEST_ASSERT_NULL(some_pointer); }
static void test_null_message(void) { TEST_ASSERT_NULL_MESSAGE(some_pointer, "null message"); }
static void test_not_null(void) { TEST_ASSERT_NOT_NULL(NULL); }
static void test_not_null_message(void) { TEST_ASSERT_NOT_NULL_MESSAGE(NULL, "not null message"); }

/* ---- Signed and unsigned integers --------------------------------------- */

static void test_equal(void) { TEST_ASSERT_EQUAL(-5, 7); }
static void test_equal_message(void) { TEST_ASSERT_EQUAL_MESSAGE(-5, 7, "count"); }
static void test_int(void) { TEST_ASSERT_EQUAL_INT(INT_MIN, INT_MAX); }
static void test_int_extremes(void) { TEST_ASSERT_EQUAL_INT(INTMAX_MIN, INTMAX_MAX); }
static void test_int_message(void) { TEST_ASSERT_EQUAL_INT_MESSAGE(1, 2, "count"); }
static void test_int8(void) { TEST_ASSERT_EQUAL_INT8(-128, 0x17F); }
static void test_int8_message(void) { TEST_ASSERT_EQUAL_INT8_MESSAGE(-1, 1, "i8"); }
static void test_int16(void) { TEST_ASSERT_EQUAL_INT16(-32768, 0x7FFF); }
static void test_int16_message(void) { TEST_ASSERT_EQUAL_INT16_MESSAGE(-2, 0x10002, "i16"); }
static void test_int32(void) { TEST_ASSERT_EQUAL_INT32(INT32_MIN, 0); }
static void test_int32_message(void) { TEST_ASSERT_EQUAL_INT32_MESSAGE(0, 0xFFFFFFFF, "i32"); }
static void test_uint(void) { TEST_ASSERT_EQUAL_UINT(0, UINTMAX_MAX); }
static void test_uint_message(void) { TEST_ASSERT_EQUAL_UINT_MESSAGE(5u, 6u, "u"); }
static void test_uint8(void) { TEST_ASSERT_EQUAL_UINT8(0x102, 3); }
static void test_uint8_message(void) { TEST_ASSERT_EQUAL_UINT8_MESSAGE(255, 0x100, "u8"); }
static void test_uint16(void) { TEST_ASSERT_EQUAL_UINT16(65535, 0x10000); }
static void test_uint16_message(void) { TEST_ASSERT_EQUAL_UINT16_MESSAGE(1, 2, "u16"); }
static void test_uint32(void) { TEST_ASSERT_EQUAL_UINT32(UINT32_MAX, 1); }
static void test_uint32_message(void) { TEST_ASSERT_EQUAL_UINT32_MESSAGE(0, -1, "u32"); }

/* ---- Hex ----------------------------------------------------------------- */

static void test_hex(void) { TEST_ASSERT_EQUAL_HEX(0x10, 0x1FFFFFFFFULL); }
static void test_hex_message(void) { TEST_ASSERT_EQUAL_HEX_MESSAGE(0xA, 0xB, "h"); }
static void test_hex8(void) { TEST_ASSERT_EQUAL_HEX8(0x02, 0xA5); }
static void test_hex8_message(void) { TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x02, 0xA5, "status byte"); }
static void test_hex16(void) { TEST_ASSERT_EQUAL_HEX16(0xBEEF, 0xEF); }
static void test_hex16_message(void)
{
    TEST_ASSERT_EQUAL_HEX16_MESSAGE(0x12345, 0x2345u + 1u, "h16");
}
static void test_hex32(void) { TEST_ASSERT_EQUAL_HEX32(0xDEADBEEF, 1); }
static void test_hex32_message(void) { TEST_ASSERT_EQUAL_HEX32_MESSAGE(0, 0xABCDEF, "h32"); }

/* ---- Integer ranges ----------------------------------------------------- */

static void test_int_within(void) { TEST_ASSERT_INT_WITHIN(2, 10, 13); }
static void test_int_within_message(void) { TEST_ASSERT_INT_WITHIN_MESSAGE(2, -10, -13, "w"); }
static void test_int_within_no_wrap(void) { TEST_ASSERT_INT_WITHIN(5, INTMAX_MIN, INTMAX_MAX); }
static void test_int16_within(void) { TEST_ASSERT_INT16_WITHIN(1, -32768, 32767); }
static void test_int16_within_message(void)
{
    TEST_ASSERT_INT16_WITHIN_MESSAGE(0x10001, 0, 2, "w16");
}
static void test_int32_within(void) { TEST_ASSERT_INT32_WITHIN(5, INT32_MIN, INT32_MAX); }
static void test_int32_within_message(void) { TEST_ASSERT_INT32_WITHIN_MESSAGE(1, 1, -1, "w32"); }
static void test_uint_within(void) { TEST_ASSERT_UINT_WITHIN(5, 2, 4294967295u); }
static void test_uint_within_message(void) { TEST_ASSERT_UINT_WITHIN_MESSAGE(5, 100, 10, "wu"); }
static void test_hex8_within(void) { TEST_ASSERT_HEX8_WITHIN(5, 0x02, 0xFF); }
static void test_hex8_within_message(void)
{
    TEST_ASSERT_HEX8_WITHIN_MESSAGE(0x101, 0x10, 0x20, "wh");
}

/* ---- Floating point ----------------------------------------------------- */

static void test_float_within(void) { TEST_ASSERT_FLOAT_WITHIN(0.25f, 1.0f, 1.5f); }
static void test_float_within_message(void)
{
    TEST_ASSERT_FLOAT_WITHIN_MESSAGE(0.01f, 0.1f, 0.2f, "f");
}
static void test_float_nan(void) { TEST_ASSERT_FLOAT_WITHIN(1.0f, NAN, 1.0f); }
static void test_float_nan_actual(void) { TEST_ASSERT_FLOAT_WITHIN(1.0f, -2.0f, NAN); }
static void test_float_infinities(void) { TEST_ASSERT_FLOAT_WITHIN(1.0f, INFINITY, -INFINITY); }
static void test_float_inf_finite(void) { TEST_ASSERT_FLOAT_WITHIN(INFINITY, 3.0f, INFINITY); }
static void test_float_tiny(void) { TEST_ASSERT_FLOAT_WITHIN(1e-7f, 1e-6f, -5e-6f); }
static void test_float_digits(void) { TEST_ASSERT_FLOAT_WITHIN(0.5f, 1234567.0f, 1234569.0f); }
static void test_float_exponent(void) { TEST_ASSERT_FLOAT_WITHIN(1.0f, 1e10f, -0.0025f); }
static void test_double_disabled(void) { TEST_ASSERT_DOUBLE_WITHIN(0.1, 1.0, 1.0); }
static void test_double_disabled_message(void)
{
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.1, 1.0, 1.0, "d");
}

/* ---- Memory ------------------------------------------------------------- */

static const uint8_t mem_expected[] = {1, 2, 3, 4};
static const uint8_t mem_actual[] = {1, 2, 0xFF, 4};

static void test_memory(void) { TEST_ASSERT_EQUAL_MEMORY(mem_expected, mem_actual, 4); }
static void test_memory_message(void)
{
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(mem_expected, mem_actual, 4, "frame");
}
static void test_memory_nothing(void) { TEST_ASSERT_EQUAL_MEMORY(mem_expected, mem_actual, 0); }
static void test_memory_nothing_message(void)
{
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(NULL, NULL, 0, "empty");
}
static void test_memory_expected_null(void) { TEST_ASSERT_EQUAL_MEMORY(NULL, mem_actual, 4); }
static void test_memory_actual_null(void)
{
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(mem_expected, NULL, 4, "an");
}

/* ---- Arrays ------------------------------------------------------------- */

static const uint8_t u8_expected[] = {1, 200, 3};
static const uint8_t u8_actual[] = {1, 201, 3};
static const int16_t i16_expected[] = {5, -300};
static const int16_t i16_actual[] = {5, 300};
static const int32_t i32_expected[] = {0, INT32_MIN};
static const int32_t i32_actual[] = {0, INT32_MAX};
static const uint8_t h8_expected[] = {0x80};
static const uint8_t h8_actual[] = {0x7F};

static void test_uint8_array(void) { TEST_ASSERT_EQUAL_UINT8_ARRAY(u8_expected, u8_actual, 3); }
static void test_uint8_array_message(void)
{
    TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(u8_expected, u8_actual, 3, "a8");
}
static void test_int16_array(void) { TEST_ASSERT_EQUAL_INT16_ARRAY(i16_expected, i16_actual, 2); }
static void test_int16_array_message(void)
{
    TEST_ASSERT_EQUAL_INT16_ARRAY_MESSAGE(i16_expected, i16_actual, 2, "a16");
}
static void test_int32_array(void) { TEST_ASSERT_EQUAL_INT32_ARRAY(i32_expected, i32_actual, 2); }
static void test_int32_array_message(void)
{
    TEST_ASSERT_EQUAL_INT32_ARRAY_MESSAGE(i32_expected, i32_actual, 2, "a32");
}
static void test_hex8_array(void) { TEST_ASSERT_EQUAL_HEX8_ARRAY(h8_expected, h8_actual, 1); }
static void test_hex8_array_message(void)
{
    TEST_ASSERT_EQUAL_HEX8_ARRAY_MESSAGE(h8_expected, h8_actual, 1, "ah");
}
static void test_array_nothing(void) { TEST_ASSERT_EQUAL_INT16_ARRAY(i16_expected, i16_actual, 0); }
static void test_array_expected_null(void) { TEST_ASSERT_EQUAL_HEX8_ARRAY(NULL, h8_actual, 1); }
static void test_array_actual_null(void) { TEST_ASSERT_EQUAL_INT32_ARRAY(i32_expected, NULL, 2); }

/* ---- Strings ------------------------------------------------------------ */

static void test_string(void) { TEST_ASSERT_EQUAL_STRING("abc", "abd"); }
static void test_string_message(void) { TEST_ASSERT_EQUAL_STRING_MESSAGE("abc", "abd", "name"); }
static void test_string_expected_null(void) { TEST_ASSERT_EQUAL_STRING(NULL, "abc"); }
static void test_string_actual_null(void) { TEST_ASSERT_EQUAL_STRING_MESSAGE("abc", NULL, "sn"); }
static void test_string_shorter(void) { TEST_ASSERT_EQUAL_STRING("ab", "abc"); }
static void test_string_escaped(void) { TEST_ASSERT_EQUAL_STRING("tab\there", "line\nbreak"); }

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_passes_boolean_and_integers);
    RUN_TEST(test_passes_float_memory_arrays_strings);
    RUN_TEST(test_passes_every_message_variant);
    RUN_TEST(test_passes_with_explicit_line, 1234);

    RUN_TEST(test_fail);
    RUN_TEST(test_fail_message);
    RUN_TEST(test_ignore);
    RUN_TEST(test_ignore_message);
    RUN_TEST(test_message_then_pass);
    RUN_TEST(test_message_then_fail);
    RUN_TEST(test_message_escaped);
    RUN_TEST(test_only_first_failure_reported);
    RUN_TEST(test_failure_in_helper_leaves_test);
    RUN_TEST(test_ignore_skips_rest);
    RUN_TEST(test_skipped_code_never_ran);

    RUN_TEST(test_assert);
    RUN_TEST(test_assert_message);
    RUN_TEST(test_true);
    RUN_TEST(test_true_message);
    RUN_TEST(test_false);
    RUN_TEST(test_false_message);
    RUN_TEST(test_null);
    RUN_TEST(test_null_message);
    RUN_TEST(test_not_null);
    RUN_TEST(test_not_null_message);

    RUN_TEST(test_equal);
    RUN_TEST(test_equal_message);
    RUN_TEST(test_int);
    RUN_TEST(test_int_extremes);
    RUN_TEST(test_int_message);
    RUN_TEST(test_int8);
    RUN_TEST(test_int8_message);
    RUN_TEST(test_int16);
    RUN_TEST(test_int16_message);
    RUN_TEST(test_int32);
    RUN_TEST(test_int32_message);
    RUN_TEST(test_uint);
    RUN_TEST(test_uint_message);
    RUN_TEST(test_uint8);
    RUN_TEST(test_uint8_message);
    RUN_TEST(test_uint16);
    RUN_TEST(test_uint16_message);
    RUN_TEST(test_uint32);
    RUN_TEST(test_uint32_message);

    RUN_TEST(test_hex);
    RUN_TEST(test_hex_message);
    RUN_TEST(test_hex8);
    RUN_TEST(test_hex8_message);
    RUN_TEST(test_hex16);
    RUN_TEST(test_hex16_message);
    RUN_TEST(test_hex32);
    RUN_TEST(test_hex32_message);

    RUN_TEST(test_int_within);
    RUN_TEST(test_int_within_message);
    RUN_TEST(test_int_within_no_wrap);
    RUN_TEST(test_int16_within);
    RUN_TEST(test_int16_within_message);
    RUN_TEST(test_int32_within);
    RUN_TEST(test_int32_within_message);
    RUN_TEST(test_uint_within);
    RUN_TEST(test_uint_within_message);
    RUN_TEST(test_hex8_within);
    RUN_TEST(test_hex8_within_message);

    RUN_TEST(test_float_within);
    RUN_TEST(test_float_within_message);
    RUN_TEST(test_float_nan);
    RUN_TEST(test_float_nan_actual);
    RUN_TEST(test_float_infinities);
    RUN_TEST(test_float_inf_finite);
    RUN_TEST(test_float_tiny);
    RUN_TEST(test_float_digits);
    RUN_TEST(test_float_exponent);
    RUN_TEST(test_double_disabled);
    RUN_TEST(test_double_disabled_message);

    RUN_TEST(test_memory);
    RUN_TEST(test_memory_message);
    RUN_TEST(test_memory_nothing);
    RUN_TEST(test_memory_nothing_message);
    RUN_TEST(test_memory_expected_null);
    RUN_TEST(test_memory_actual_null);

    RUN_TEST(test_uint8_array);
    RUN_TEST(test_uint8_array_message);
    RUN_TEST(test_int16_array);
    RUN_TEST(test_int16_array_message);
    RUN_TEST(test_int32_array);
    RUN_TEST(test_int32_array_message);
    RUN_TEST(test_hex8_array);
    RUN_TEST(test_hex8_array_message);
    RUN_TEST(test_array_nothing);
    RUN_TEST(test_array_expected_null);
    RUN_TEST(test_array_actual_null);

    RUN_TEST(test_string);
    RUN_TEST(test_string_message);
    RUN_TEST(test_string_expected_null);
    RUN_TEST(test_string_actual_null);
    RUN_TEST(test_string_shorter);
    RUN_TEST(test_string_escaped);
    return UNITY_END();
}
