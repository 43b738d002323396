/* probe_strict.c - compile-time self-test: the harness's macros are as
 * strict about argument types as Unity 2.7.0's.
 *
 * Never linked or run. run_compile_probe.cmake compiles it once per case of
 * expected_strict.txt, with -DPROBE_<CASE> and warnings as errors, and
 * checks that the compiler rejects or accepts it as listed there. Unity
 * passes the delta of INT_WITHIN and UINT_WITHIN uncast into a UNITY_UINT
 * parameter; a harness that cast it would accept the failing cases. The
 * check() functions take the delta as a parameter, as test code usually
 * does (a constant would be converted without a warning). Line numbers are
 * part of expected_strict.txt: edit them together.
 */
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

#if defined(PROBE_SIGNED_DELTA)
/* A signed 64-bit tolerance (test_fx_math.c had one): -Wsign-conversion. */
static void check(int64_t delta, int64_t worst)
{
    TEST_ASSERT_INT_WITHIN_MESSAGE(delta, 0, worst, "signed delta");
}
#elif defined(PROBE_UNSIGNED_DELTA)
/* The same tolerance, unsigned: accepted. */
static void check(uint32_t delta, int64_t worst)
{
    TEST_ASSERT_INT_WITHIN_MESSAGE(delta, 0, worst, "unsigned delta");
}
#elif defined(PROBE_UINT_WITHIN_INT_DELTA)
/* A plain int delta to UINT_WITHIN: -Wsign-conversion as well. */
static void check(int delta, int64_t worst)
{
    TEST_ASSERT_UINT_WITHIN(delta, 0u, (uint64_t)worst);
}
#elif defined(PROBE_DOUBLE_DELTA)
/* A floating delta to INT_WITHIN: -Wfloat-conversion (-Wconversion). */
static void check(double delta, int64_t worst)
{
    TEST_ASSERT_INT_WITHIN(delta, 0, worst);
}
#else
#error "probe_strict.c: define one PROBE_<CASE> (see expected_strict.txt)"
#endif

static void test_within(void)
{
    check(3, 2);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_within);
    return UNITY_END();
}
