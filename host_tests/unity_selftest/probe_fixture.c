/* probe_fixture.c - self-test probe: setUp / tearDown behaviour.
 *
 * main() picks a mode before each RUN_TEST; setUp and tearDown act on it.
 * tearDown always prints a marker to stdout, which shows where its output
 * lands: before the PASS line, after the FAIL / IGNORE text. Not a unit
 * test: run_probe.cmake compares stdout with expected_fixture.txt.
 */
#include "unity.h"

typedef enum {
    MODE_PLAIN,          /* setUp and tearDown only print */
    MODE_SETUP_FAILS,    /* an assertion in setUp fails */
    MODE_SETUP_IGNORES,  /* setUp ignores the test */
    MODE_SETUP_MESSAGE,  /* setUp prints an INFO line */
    MODE_TEARDOWN_FAILS  /* an assertion in tearDown fails (or is skipped) */
} probe_mode_t;

static probe_mode_t mode;
static int body_ran;

void setUp(void)
{
    body_ran = 0;
    if (mode == MODE_SETUP_FAILS) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, 1, "setUp");
    }
    if (mode == MODE_SETUP_IGNORES) {
        TEST_IGNORE_MESSAGE("setUp ignores");
    }
    if (mode == MODE_SETUP_MESSAGE) {
        TEST_MESSAGE("from setUp");
    }
}

void tearDown(void)
{
    printf("[tearDown body_ran=%d]", body_ran);
    if (mode == MODE_TEARDOWN_FAILS) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, 1, "tearDown");
        /* Reached only when the assertion was skipped. */
        printf("[tearDown continued]");
    }
}

static void test_passes(void) { body_ran = 1; }
static void test_fails(void) { body_ran = 1; TEST_ASSERT_EQUAL_INT(1, 2); }
static void test_ignored(void) { body_ran = 1; TEST_IGNORE(); }

int main(void)
{
    UNITY_BEGIN();
    mode = MODE_PLAIN;
    RUN_TEST(test_passes);
    RUN_TEST(test_fails);
    RUN_TEST(test_ignored);
    mode = MODE_SETUP_FAILS;
    RUN_TEST(test_passes);
    mode = MODE_SETUP_IGNORES;
    RUN_TEST(test_passes);
    mode = MODE_SETUP_MESSAGE;
    RUN_TEST(test_passes);
    mode = MODE_TEARDOWN_FAILS;
    RUN_TEST(test_passes);
    RUN_TEST(test_fails);
    RUN_TEST(test_ignored);
    return UNITY_END();
}
