#include "unity.h" /* Same line layout as the probe whose run unity-subset.md shows (sec. 4). */
void setUp(void) {}
void tearDown(void) {}
static void test_passes(void) { TEST_ASSERT_TRUE(1); }
static void test_ignored_msg(void) { TEST_IGNORE_MESSAGE("not yet"); }
static void test_message_then_pass(void) { TEST_MESSAGE("note"); }
static void test_eq_int_msg_fails(void) { TEST_ASSERT_EQUAL_INT_MESSAGE(1, 2, "count"); }
int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_passes);
    RUN_TEST(test_ignored_msg);
    RUN_TEST(test_message_then_pass);
    RUN_TEST(test_eq_int_msg_fails);
    return UNITY_END();
}
