/* probe_double.c - self-test probe built with UNITY_INCLUDE_DOUBLE (the
 * harness too): DOUBLE_WITHIN, and floats printed with 9 digits.
 * Not a unit test: run_probe.cmake compares stdout with expected_double.txt.
 */
#include "unity.h"

#ifndef UNITY_INCLUDE_DOUBLE
#error "probe_double.c must be built with UNITY_INCLUDE_DOUBLE"
#endif

void setUp(void) {}
void tearDown(void) {}

static void test_double_passes(void)
{
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.1, 0.1 + 1e-10);
    TEST_ASSERT_DOUBLE_WITHIN(0.5, 2.0, 1.5);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, NAN, NAN);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, INFINITY, INFINITY);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, -INFINITY, -INFINITY);
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(1e-12, 1e300, 1e300, "m");
    TEST_ASSERT_FLOAT_WITHIN(0.25f, 1.0f, 1.25f);
}

static void test_double_within(void) { TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.1, 0.2); }
static void test_double_within_message(void)
{
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.001, 1.0 / 3.0, 0.5, "third");
}
static void test_double_nan(void) { TEST_ASSERT_DOUBLE_WITHIN(1.0, NAN, 0.0); }
static void test_double_infinities(void) { TEST_ASSERT_DOUBLE_WITHIN(1.0, -INFINITY, INFINITY); }
static void test_double_overflowing_difference(void)
{
    TEST_ASSERT_DOUBLE_WITHIN(INFINITY, -1e308, 1e308);
}
static void test_double_tiny(void) { TEST_ASSERT_DOUBLE_WITHIN(1e-15, 1e-13, -5e-13); }
static void test_double_small(void) { TEST_ASSERT_DOUBLE_WITHIN(1e-9, 1e-6, 2.5e-6); }
static void test_double_digits(void) { TEST_ASSERT_DOUBLE_WITHIN(0.5, 123456789.0, 123456791.0); }
static void test_float_nine_digits(void) { TEST_ASSERT_FLOAT_WITHIN(0.01f, 0.1f, 0.2f); }
static void test_float_small(void) { TEST_ASSERT_FLOAT_WITHIN(1e-7f, 1e-6f, -5e-6f); }

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_double_passes);
    RUN_TEST(test_double_within);
    RUN_TEST(test_double_within_message);
    RUN_TEST(test_double_nan);
    RUN_TEST(test_double_infinities);
    RUN_TEST(test_double_overflowing_difference);
    RUN_TEST(test_double_tiny);
    RUN_TEST(test_double_small);
    RUN_TEST(test_double_digits);
    RUN_TEST(test_float_nine_digits);
    RUN_TEST(test_float_small);
    return UNITY_END();
}
