/* unity.h - the project's small Unity-compatible test harness.
 *
 * Test files written against the Unity subset in
 * ../shared/guides/unity-subset.md build unchanged against this header and
 * against a real ThrowTheSwitch/Unity. Output text, ordering, line numbers,
 * summary block and the return value of UNITY_END() follow the Unity v2.7.0
 * behaviour recorded in that note. Written from the note's behavioural
 * description only; no Unity code is used.
 *
 * Control flow: a failing assertion prints its result at once (without the
 * newline) and longjmps back to UnityDefaultTestRun, so the rest of the test
 * body is skipped; tearDown still runs; the newline is written when the test
 * concludes. Once a test has failed or been ignored, every further assertion
 * of that test returns silently, so only the first failure is reported.
 * Assertions that fail outside RUN_TEST abort the process with a message on
 * stderr (by default; see "Output").
 *
 * Output: every character goes through UNITY_OUTPUT_CHAR(c) (c an int
 * holding an unsigned char value, as putchar takes it). By default that is
 * putchar on stdout, followed by fflush(stdout) after every result line and
 * the summary, and the "outside RUN_TEST" message goes to stderr before
 * abort(). A build may define these hooks (all optional; the first three
 * are Unity's configuration macros of those names, the last is this
 * harness's own), on the compiler's command line or in unity_config.h,
 * read when UNITY_INCLUDE_CONFIG_H is defined:
 *   UNITY_OUTPUT_CHAR(c)     writes one character;
 *   UNITY_OUTPUT_START()     called by UNITY_BEGIN() before any output;
 *   UNITY_OUTPUT_FLUSH()     after every result line and the summary;
 *   UNITY_OUTPUT_ABORT()     ends the program after the "outside RUN_TEST"
 *                            message (default abort(); must not return).
 * With UNITY_OUTPUT_CHAR defined the harness uses no stdio at all: that
 * message goes through UNITY_OUTPUT_CHAR too, and floats are formatted by
 * the harness itself instead of snprintf (unity.c, print_float). The
 * Cortex-M test images use this (host_tests/target_unit/unity_config.h: UART0).
 *
 * Doubles: define UNITY_INCLUDE_DOUBLE for both unity.c and the test file.
 * Without it TEST_ASSERT_DOUBLE_WITHIN* fails with
 * "Unity Double Precision Disabled", and floats print with 7 significant
 * digits instead of 9.
 *
 * Argument types: as strict as Unity 2.7.0. Every macro hands its arguments
 * to a function whose parameters have the types of Unity's (UNITY_INT,
 * UNITY_UINT, float, double, const void *, const char *, uint32_t counts),
 * with exactly the casts Unity's macros write, and no others: e.g.
 * TEST_ASSERT_EQUAL_INT16 casts both values to int16_t and then UNITY_INT,
 * while TEST_ASSERT_INT_WITHIN and TEST_ASSERT_UINT_WITHIN pass the delta
 * uncast into a UNITY_UINT parameter, so a signed or floating delta is a
 * -Wsign-conversion / -Wconversion warning here as with the real Unity
 * (../unity_selftest, probe_strict_*). UNITY_INT and UNITY_UINT are 64-bit,
 * as Unity's with UNITY_SUPPORT_64: Unity detects that on a 64-bit host;
 * for a 32-bit target the project assumes a Unity built with it
 * (-DUNITY_SUPPORT_INT64=ON), since the tests compare 64-bit values.
 *
 * Names ending in an underscore, and the Unity* functions, are internals
 * used by the public macros; test files use only the TEST_ and UNITY_BEGIN /
 * UNITY_END / RUN_TEST macros and define setUp() and tearDown().
 */
#ifndef UNITY_FRAMEWORK_H
#define UNITY_FRAMEWORK_H

/* The same standard headers the real unity.h pulls in (the note, section 1):
 * test files may rely on them transitively. */
#include <setjmp.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <limits.h>
#include <stdio.h>

/* Build-time configuration, as with Unity: see "Output" above. */
#ifdef UNITY_INCLUDE_CONFIG_H
#include "unity_config.h"
#endif

/* Integer types of the comparisons, as in Unity 2.7.0 with UNITY_SUPPORT_64
 * (see "Argument types" above): 64 bits, `long` where long has 64 bits,
 * `long long` otherwise. */
#if ULONG_MAX > 0xFFFFFFFFUL
typedef long UNITY_INT;
typedef unsigned long UNITY_UINT;
#else
typedef long long UNITY_INT;
typedef unsigned long long UNITY_UINT;
#endif

typedef unsigned long UNITY_LINE_TYPE;
typedef void (*UnityTestFunction)(void);

/* How a compared value is printed: signed or unsigned decimal, or "0x" plus
 * 2/4/8 digits (the hex styles' values are their digit counts). */
typedef enum {
    UNITY_DISPLAY_STYLE_UINT = 0,
    UNITY_DISPLAY_STYLE_INT = 1,
    UNITY_DISPLAY_STYLE_HEX8 = 2,
    UNITY_DISPLAY_STYLE_HEX16 = 4,
    UNITY_DISPLAY_STYLE_HEX32 = 8
} UNITY_DISPLAY_STYLE_T;

/* Element type of the array assertions. */
typedef enum {
    UNITY_ARRAY_UINT8,
    UNITY_ARRAY_INT16,
    UNITY_ARRAY_INT32,
    UNITY_ARRAY_HEX8
} UNITY_ARRAY_KIND_T;

/* Defined by every test executable; run before / after every test. */
void setUp(void);
void tearDown(void);

/* Runner. The line is an int, as Unity's, and RUN_TEST passes it uncast. */
void UnityBegin(const char *filename);
int UnityEnd(void);
void UnityDefaultTestRun(UnityTestFunction func, const char *name, int line);

/* Control. A NULL message means "no message". */
void UnityFail(const char *message, UNITY_LINE_TYPE line);
void UnityIgnore(const char *message, UNITY_LINE_TYPE line);
void UnityMessage(const char *message, UNITY_LINE_TYPE line);

/* Comparisons; message may be NULL. The parameter types are Unity's. With
 * UNITY_DISPLAY_STYLE_UINT and the hex styles the UNITY_INT values are
 * compared and printed as UNITY_UINT (the bits the macros' casts kept). */
void UnityAssertEqualNumber(UNITY_INT expected, UNITY_INT actual, const char *message,
                            UNITY_LINE_TYPE line, UNITY_DISPLAY_STYLE_T style);
void UnityAssertNumbersWithin(UNITY_UINT delta, UNITY_INT expected, UNITY_INT actual,
                              const char *message, UNITY_LINE_TYPE line,
                              UNITY_DISPLAY_STYLE_T style);
void UnityAssertFloatsWithin(float delta, float expected, float actual, const char *message,
                             UNITY_LINE_TYPE line);
#ifdef UNITY_INCLUDE_DOUBLE
void UnityAssertDoublesWithin(double delta, double expected, double actual,
                              const char *message, UNITY_LINE_TYPE line);
#endif
void UnityAssertEqualMemory(const void *expected, const void *actual, uint32_t length,
                            const char *message, UNITY_LINE_TYPE line);
void UnityAssertEqualIntArray(const void *expected, const void *actual, uint32_t count,
                              const char *message, UNITY_LINE_TYPE line,
                              UNITY_ARRAY_KIND_T kind);
void UnityAssertEqualString(const char *expected, const char *actual, const char *message,
                            UNITY_LINE_TYPE line);

/* ---- Runner macros ------------------------------------------------------ */

#define UNITY_BEGIN() UnityBegin(__FILE__)
#define UNITY_END() UnityEnd()

/* RUN_TEST(func) or RUN_TEST(func, line); the line defaults to the line of
 * the RUN_TEST itself. The trailing dummy keeps the variadic part non-empty. */
#define RUN_TEST(...) UNITY_RUN_TEST_(__VA_ARGS__, __LINE__, unity_dummy_)
#define UNITY_RUN_TEST_(func, line, ...) UnityDefaultTestRun((func), #func, (line))

/* ---- Internal helpers of the assertion macros ----------------------------
 *
 * Every cast below is one Unity 2.7.0 makes; an argument Unity passes uncast
 * (the delta of INT_WITHIN and UINT_WITHIN, every message) is passed uncast
 * here too, so a conversion the compiler warns about with the real Unity
 * warns here as well. */

#define UNITY_LINE_ (UNITY_LINE_TYPE)(__LINE__)
#define UNITY_TEST_ASSERT_(cond, msg) \
    do { \
        if (cond) { \
        } else { \
            UnityFail((msg), UNITY_LINE_); \
        } \
    } while (0)
/* (UNITY_INT)(e); (UNITY_INT)(T)(e) for the fixed widths. */
#define UNITY_EQ_(e, a, m, style) \
    UnityAssertEqualNumber((UNITY_INT)(e), (UNITY_INT)(a), (m), UNITY_LINE_, (style))
#define UNITY_EQ_W_(T, e, a, m, style) \
    UnityAssertEqualNumber((UNITY_INT)(T)(e), (UNITY_INT)(T)(a), (m), UNITY_LINE_, (style))
/* The delta uncast into UNITY_UINT, the values cast to UNITY_INT. */
#define UNITY_WITHIN_(d, e, a, m, style) \
    UnityAssertNumbersWithin((d), (UNITY_INT)(e), (UNITY_INT)(a), (m), UNITY_LINE_, (style))
/* The delta cast to TD, the values to T and then UNITY_INT. */
#define UNITY_WITHIN_W_(TD, T, d, e, a, m, style) \
    UnityAssertNumbersWithin((TD)(d), (UNITY_INT)(T)(e), (UNITY_INT)(T)(a), (m), UNITY_LINE_, \
                             (style))
/* HEX8_WITHIN: (UNITY_INT)(UNITY_UINT)(uint8_t)(e), as Unity writes it. */
#define UNITY_HEX8_WITHIN_(d, e, a, m) \
    UnityAssertNumbersWithin((uint8_t)(d), (UNITY_INT)(UNITY_UINT)(uint8_t)(e), \
                             (UNITY_INT)(UNITY_UINT)(uint8_t)(a), (m), UNITY_LINE_, \
                             UNITY_DISPLAY_STYLE_HEX8)
#define UNITY_ARRAY_(e, a, n, m, kind) \
    UnityAssertEqualIntArray((const void *)(e), (const void *)(a), (uint32_t)(n), (m), \
                             UNITY_LINE_, (kind))

/* ---- Control ------------------------------------------------------------ */

#define TEST_FAIL() UnityFail(NULL, UNITY_LINE_)
#define TEST_FAIL_MESSAGE(message) UnityFail((message), UNITY_LINE_)
#define TEST_IGNORE() UnityIgnore(NULL, UNITY_LINE_)
#define TEST_IGNORE_MESSAGE(message) UnityIgnore((message), UNITY_LINE_)
#define TEST_MESSAGE(message) UnityMessage((message), UNITY_LINE_)

/* ---- Boolean: a message replaces the built-in text ---------------------- */

#define TEST_ASSERT(c) UNITY_TEST_ASSERT_((c), " Expression Evaluated To FALSE")
#define TEST_ASSERT_MESSAGE(c, message) UNITY_TEST_ASSERT_((c), (message))
#define TEST_ASSERT_TRUE(c) UNITY_TEST_ASSERT_((c), " Expected TRUE Was FALSE")
#define TEST_ASSERT_TRUE_MESSAGE(c, message) UNITY_TEST_ASSERT_((c), (message))
#define TEST_ASSERT_FALSE(c) UNITY_TEST_ASSERT_(!(c), " Expected FALSE Was TRUE")
#define TEST_ASSERT_FALSE_MESSAGE(c, message) UNITY_TEST_ASSERT_(!(c), (message))
#define TEST_ASSERT_NULL(p) UNITY_TEST_ASSERT_(((p) == NULL), " Expected NULL")
#define TEST_ASSERT_NULL_MESSAGE(p, message) UNITY_TEST_ASSERT_(((p) == NULL), (message))
#define TEST_ASSERT_NOT_NULL(p) UNITY_TEST_ASSERT_(((p) != NULL), " Expected Non-NULL")
#define TEST_ASSERT_NOT_NULL_MESSAGE(p, message) UNITY_TEST_ASSERT_(((p) != NULL), (message))

/* ---- Signed integers: cast to the named width, printed in decimal ------- */

#define TEST_ASSERT_EQUAL(e, a) UNITY_EQ_(e, a, NULL, UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_MESSAGE(e, a, message) \
    UNITY_EQ_(e, a, (message), UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_INT(e, a) UNITY_EQ_(e, a, NULL, UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_INT_MESSAGE(e, a, message) \
    UNITY_EQ_(e, a, (message), UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_INT8(e, a) UNITY_EQ_W_(int8_t, e, a, NULL, UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_INT8_MESSAGE(e, a, message) \
    UNITY_EQ_W_(int8_t, e, a, (message), UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_INT16(e, a) UNITY_EQ_W_(int16_t, e, a, NULL, UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_INT16_MESSAGE(e, a, message) \
    UNITY_EQ_W_(int16_t, e, a, (message), UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_INT32(e, a) UNITY_EQ_W_(int32_t, e, a, NULL, UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_EQUAL_INT32_MESSAGE(e, a, message) \
    UNITY_EQ_W_(int32_t, e, a, (message), UNITY_DISPLAY_STYLE_INT)

/* ---- Unsigned integers: cast to the named width, printed in decimal ----- */

#define TEST_ASSERT_EQUAL_UINT(e, a) UNITY_EQ_(e, a, NULL, UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_EQUAL_UINT_MESSAGE(e, a, message) \
    UNITY_EQ_(e, a, (message), UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_EQUAL_UINT8(e, a) UNITY_EQ_W_(uint8_t, e, a, NULL, UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_EQUAL_UINT8_MESSAGE(e, a, message) \
    UNITY_EQ_W_(uint8_t, e, a, (message), UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_EQUAL_UINT16(e, a) \
    UNITY_EQ_W_(uint16_t, e, a, NULL, UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_EQUAL_UINT16_MESSAGE(e, a, message) \
    UNITY_EQ_W_(uint16_t, e, a, (message), UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_EQUAL_UINT32(e, a) \
    UNITY_EQ_W_(uint32_t, e, a, NULL, UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_EQUAL_UINT32_MESSAGE(e, a, message) \
    UNITY_EQ_W_(uint32_t, e, a, (message), UNITY_DISPLAY_STYLE_UINT)

/* ---- Hex: cast to the width, printed as 0x and 2/4/8 upper-case digits ---
 * (Unity casts to the signed type of the width; only the low bits print.) */

#define TEST_ASSERT_EQUAL_HEX(e, a) UNITY_EQ_W_(int32_t, e, a, NULL, UNITY_DISPLAY_STYLE_HEX32)
#define TEST_ASSERT_EQUAL_HEX_MESSAGE(e, a, message) \
    UNITY_EQ_W_(int32_t, e, a, (message), UNITY_DISPLAY_STYLE_HEX32)
#define TEST_ASSERT_EQUAL_HEX8(e, a) UNITY_EQ_W_(int8_t, e, a, NULL, UNITY_DISPLAY_STYLE_HEX8)
#define TEST_ASSERT_EQUAL_HEX8_MESSAGE(e, a, message) \
    UNITY_EQ_W_(int8_t, e, a, (message), UNITY_DISPLAY_STYLE_HEX8)
#define TEST_ASSERT_EQUAL_HEX16(e, a) \
    UNITY_EQ_W_(int16_t, e, a, NULL, UNITY_DISPLAY_STYLE_HEX16)
#define TEST_ASSERT_EQUAL_HEX16_MESSAGE(e, a, message) \
    UNITY_EQ_W_(int16_t, e, a, (message), UNITY_DISPLAY_STYLE_HEX16)
#define TEST_ASSERT_EQUAL_HEX32(e, a) \
    UNITY_EQ_W_(int32_t, e, a, NULL, UNITY_DISPLAY_STYLE_HEX32)
#define TEST_ASSERT_EQUAL_HEX32_MESSAGE(e, a, message) \
    UNITY_EQ_W_(int32_t, e, a, (message), UNITY_DISPLAY_STYLE_HEX32)

/* ---- Integer ranges: pass iff |e - a| <= delta, computed without wrap ----
 * INT_WITHIN and UINT_WITHIN take the delta as it is: it must convert to
 * UNITY_UINT without a warning (a signed or 64-bit-on-32 delta does not). */

#define TEST_ASSERT_INT_WITHIN(d, e, a) UNITY_WITHIN_(d, e, a, NULL, UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_INT_WITHIN_MESSAGE(d, e, a, message) \
    UNITY_WITHIN_(d, e, a, (message), UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_INT16_WITHIN(d, e, a) \
    UNITY_WITHIN_W_(uint16_t, int16_t, d, e, a, NULL, UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_INT16_WITHIN_MESSAGE(d, e, a, message) \
    UNITY_WITHIN_W_(uint16_t, int16_t, d, e, a, (message), UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_INT32_WITHIN(d, e, a) \
    UNITY_WITHIN_W_(uint32_t, int32_t, d, e, a, NULL, UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_INT32_WITHIN_MESSAGE(d, e, a, message) \
    UNITY_WITHIN_W_(uint32_t, int32_t, d, e, a, (message), UNITY_DISPLAY_STYLE_INT)
#define TEST_ASSERT_UINT_WITHIN(d, e, a) UNITY_WITHIN_(d, e, a, NULL, UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_UINT_WITHIN_MESSAGE(d, e, a, message) \
    UNITY_WITHIN_(d, e, a, (message), UNITY_DISPLAY_STYLE_UINT)
#define TEST_ASSERT_HEX8_WITHIN(d, e, a) UNITY_HEX8_WITHIN_(d, e, a, NULL)
#define TEST_ASSERT_HEX8_WITHIN_MESSAGE(d, e, a, message) UNITY_HEX8_WITHIN_(d, e, a, (message))

/* ---- Floating point ----------------------------------------------------- */

#define TEST_ASSERT_FLOAT_WITHIN(d, e, a) \
    UnityAssertFloatsWithin((float)(d), (float)(e), (float)(a), NULL, UNITY_LINE_)
#define TEST_ASSERT_FLOAT_WITHIN_MESSAGE(d, e, a, message) \
    UnityAssertFloatsWithin((float)(d), (float)(e), (float)(a), (message), UNITY_LINE_)
#ifdef UNITY_INCLUDE_DOUBLE
#define TEST_ASSERT_DOUBLE_WITHIN(d, e, a) \
    UnityAssertDoublesWithin((double)(d), (double)(e), (double)(a), NULL, UNITY_LINE_)
#define TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(d, e, a, message) \
    UnityAssertDoublesWithin((double)(d), (double)(e), (double)(a), (message), UNITY_LINE_)
#else
/* As in Unity: the arguments are not evaluated and the message is dropped. */
#define TEST_ASSERT_DOUBLE_WITHIN(d, e, a) \
    UnityFail("Unity Double Precision Disabled", UNITY_LINE_)
#define TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(d, e, a, message) \
    UnityFail("Unity Double Precision Disabled", UNITY_LINE_)
#endif

/* ---- Memory, arrays, strings -------------------------------------------- */

#define TEST_ASSERT_EQUAL_MEMORY(e, a, len) \
    UnityAssertEqualMemory((const void *)(e), (const void *)(a), (uint32_t)(len), NULL, \
                           UNITY_LINE_)
#define TEST_ASSERT_EQUAL_MEMORY_MESSAGE(e, a, len, message) \
    UnityAssertEqualMemory((const void *)(e), (const void *)(a), (uint32_t)(len), (message), \
                           UNITY_LINE_)
#define TEST_ASSERT_EQUAL_UINT8_ARRAY(e, a, n) UNITY_ARRAY_(e, a, n, NULL, UNITY_ARRAY_UINT8)
#define TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(e, a, n, message) \
    UNITY_ARRAY_(e, a, n, (message), UNITY_ARRAY_UINT8)
#define TEST_ASSERT_EQUAL_INT16_ARRAY(e, a, n) UNITY_ARRAY_(e, a, n, NULL, UNITY_ARRAY_INT16)
#define TEST_ASSERT_EQUAL_INT16_ARRAY_MESSAGE(e, a, n, message) \
    UNITY_ARRAY_(e, a, n, (message), UNITY_ARRAY_INT16)
#define TEST_ASSERT_EQUAL_INT32_ARRAY(e, a, n) UNITY_ARRAY_(e, a, n, NULL, UNITY_ARRAY_INT32)
#define TEST_ASSERT_EQUAL_INT32_ARRAY_MESSAGE(e, a, n, message) \
    UNITY_ARRAY_(e, a, n, (message), UNITY_ARRAY_INT32)
#define TEST_ASSERT_EQUAL_HEX8_ARRAY(e, a, n) UNITY_ARRAY_(e, a, n, NULL, UNITY_ARRAY_HEX8)
#define TEST_ASSERT_EQUAL_HEX8_ARRAY_MESSAGE(e, a, n, message) \
    UNITY_ARRAY_(e, a, n, (message), UNITY_ARRAY_HEX8)
#define TEST_ASSERT_EQUAL_STRING(e, a) \
    UnityAssertEqualString((const char *)(e), (const char *)(a), NULL, UNITY_LINE_)
#define TEST_ASSERT_EQUAL_STRING_MESSAGE(e, a, message) \
    UnityAssertEqualString((const char *)(e), (const char *)(a), (message), UNITY_LINE_)

#endif /* UNITY_FRAMEWORK_H */
