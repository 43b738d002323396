/* unity.c - the project's Unity-compatible harness; see unity.h.
 *
 * Written from ../shared/guides/unity-subset.md (behaviour of Unity v2.7.0),
 * not from Unity's sources. Output goes to stdout through putchar; user
 * strings (file, test name, messages, compared strings) print printable
 * ASCII as is and everything else escaped (\n, \r, \xNN), so one result is
 * always one line.
 */
#include "unity.h"

#include <stdlib.h>
#include <string.h>

/* Float printing: significant digits, and the magnitude below which a value
 * prints as "0" (Unity's UNITY_FLOAT_PRECISION / UNITY_DOUBLE_PRECISION). */
#ifdef UNITY_INCLUDE_DOUBLE
#define UNITY_FLOAT_FORMAT_ "%.9g"
#define UNITY_PRINT_ZERO_BELOW_ 1e-12
#else
#define UNITY_FLOAT_FORMAT_ "%.7g"
#define UNITY_PRINT_ZERO_BELOW_ 1e-5
#endif

static const char pointless_[] = " You Asked Me To Compare Nothing, Which Was Pointless.";

/* State of the whole run. Static, so it keeps its values across longjmp. */
static struct {
    const char *file;       /* __FILE__ given to UNITY_BEGIN */
    const char *name;       /* current test function */
    UnityTestFunction func; /* current test function */
    UNITY_LINE_TYPE line;   /* current RUN_TEST line */
    unsigned long tests;
    unsigned long failures;
    unsigned long ignores;
    int failed;   /* current test failed */
    int ignored;  /* current test ignored */
    int running;  /* inside RUN_TEST: abort_frame is valid */
    jmp_buf abort_frame;
} unity_;

/* ---- Output ------------------------------------------------------------- */

static void put(char c)
{
    (void)putchar((unsigned char)c);
}

/* Fixed text of the harness itself, written as is. */
static void emit(const char *s)
{
    while (*s != '\0') {
        put(*s++);
    }
}

static void print_hex_digits(uintmax_t value, unsigned digits)
{
    static const char hex[] = "0123456789ABCDEF";
    while (digits > 0u) {
        digits--;
        put(hex[(value >> (4u * digits)) & 0xFu]);
    }
}

static void print_char(char c)
{
    const unsigned char u = (unsigned char)c;
    if (u >= 32u && u <= 126u) {
        put(c);
    } else if (c == '\n') {
        emit("\\n");
    } else if (c == '\r') {
        emit("\\r");
    } else {
        emit("\\x");
        print_hex_digits(u, 2u);
    }
}

/* User-supplied text, escaped; NULL prints nothing. */
static void print(const char *s)
{
    if (s != NULL) {
        while (*s != '\0') {
            print_char(*s++);
        }
    }
}

static void print_uint(uintmax_t value)
{
    char digits[sizeof(uintmax_t) * 3u]; /* 3 decimal digits per byte suffice */
    size_t n = 0u;
    do {
        digits[n++] = (char)('0' + (int)(value % 10u));
        value /= 10u;
    } while (value != 0u);
    while (n > 0u) {
        put(digits[--n]);
    }
}

/* The magnitude is formed in unsigned arithmetic, so INTMAX_MIN is fine. */
static void print_int(intmax_t value)
{
    if (value < 0) {
        put('-');
        print_uint((uintmax_t)0 - (uintmax_t)value);
    } else {
        print_uint((uintmax_t)value);
    }
}

static void print_styled(uintmax_t value, UNITY_DISPLAY_STYLE_T style)
{
    if (style == UNITY_DISPLAY_STYLE_UINT) {
        print_uint(value);
    } else {
        emit("0x");
        print_hex_digits(value, (unsigned)style);
    }
}

static void print_float(double value)
{
    if (isnan(value)) {
        emit("NaN");
    } else if (isinf(value)) {
        emit(value > 0.0 ? "Infinity" : "Negative Infinity");
    } else if (fabs(value) < UNITY_PRINT_ZERO_BELOW_) {
        emit("0");
    } else {
        char text[40];
        (void)snprintf(text, sizeof text, UNITY_FLOAT_FORMAT_, value);
        emit(text);
    }
}

static void print_quoted(const char *s)
{
    if (s == NULL) {
        emit("NULL");
    } else {
        put('\'');
        print(s);
        put('\'');
    }
}

/* ---- Results ------------------------------------------------------------ */

/* "<file>:<line>:<name>:<kind>", no newline. */
static void print_result(UNITY_LINE_TYPE line, const char *kind)
{
    print(unity_.file);
    put(':');
    print_uint(line);
    put(':');
    print(unity_.name);
    put(':');
    emit(kind);
}

/* Result of a TEST_ macro; only valid inside RUN_TEST. */
static void result_begin(UNITY_LINE_TYPE line, const char *kind)
{
    if (!unity_.running) {
        (void)fflush(stdout);
        (void)fprintf(stderr, "unity: line %lu: TEST_ macro reported outside RUN_TEST\n",
                      line);
        abort();
    }
    print_result(line, kind);
}

/* Every assertion first returns if the test already failed or was ignored. */
static int skipping(void)
{
    return unity_.failed || unity_.ignored;
}

/* Appends ":<message>", marks the test failed and leaves it. */
static _Noreturn void fail_finish(const char *message)
{
    if (message != NULL) {
        put(':');
        print(message);
    }
    unity_.failed = 1;
    longjmp(unity_.abort_frame, 1);
}

/* Built-in details start with a space and follow "FAIL:". */
static void fail_begin(UNITY_LINE_TYPE line)
{
    result_begin(line, "FAIL:");
}

static _Noreturn void fail_with(UNITY_LINE_TYPE line, const char *detail, const char *message)
{
    fail_begin(line);
    emit(detail);
    fail_finish(message);
}

/* ---- Runner ------------------------------------------------------------- */

void UnityBegin(const char *filename)
{
    unity_.file = filename;
    unity_.name = NULL;
    unity_.tests = 0u;
    unity_.failures = 0u;
    unity_.ignores = 0u;
    unity_.running = 0;
}

void UnityDefaultTestRun(UnityTestFunction func, const char *name, UNITY_LINE_TYPE line)
{
    unity_.func = func;
    unity_.name = name;
    unity_.line = line;
    unity_.tests++;
    unity_.failed = 0;
    unity_.ignored = 0;
    unity_.running = 1;
    if (setjmp(unity_.abort_frame) == 0) {
        setUp();
        unity_.func();
    }
    if (setjmp(unity_.abort_frame) == 0) {
        tearDown();
    }
    unity_.running = 0;

    if (unity_.ignored) {
        unity_.ignores++;
    } else if (unity_.failed) {
        unity_.failures++;
    } else {
        print_result(unity_.line, "PASS");
    }
    put('\n');
    (void)fflush(stdout);
}

int UnityEnd(void)
{
    emit("\n-----------------------\n");
    print_uint(unity_.tests);
    emit(" Tests ");
    print_uint(unity_.failures);
    emit(" Failures ");
    print_uint(unity_.ignores);
    emit(" Ignored \n");
    emit(unity_.failures == 0u ? "OK\n" : "FAIL\n");
    (void)fflush(stdout);
    return unity_.failures > (unsigned long)INT_MAX ? INT_MAX : (int)unity_.failures;
}

/* ---- Control ------------------------------------------------------------ */

void UnityFail(const char *message, UNITY_LINE_TYPE line)
{
    if (!skipping()) {
        result_begin(line, "FAIL");
        fail_finish(message);
    }
}

void UnityIgnore(const char *message, UNITY_LINE_TYPE line)
{
    if (skipping()) {
        return;
    }
    result_begin(line, "IGNORE");
    if (message != NULL) {
        emit(": ");
        print(message);
    }
    unity_.ignored = 1;
    longjmp(unity_.abort_frame, 1);
}

void UnityMessage(const char *message, UNITY_LINE_TYPE line)
{
    result_begin(line, "INFO");
    if (message != NULL) {
        emit(": ");
        print(message);
    }
    put('\n');
}

/* ---- Integers ----------------------------------------------------------- */

void UnityAssertEqualInt(intmax_t expected, intmax_t actual, const char *message,
                         UNITY_LINE_TYPE line)
{
    if (skipping() || expected == actual) {
        return;
    }
    fail_begin(line);
    emit(" Expected ");
    print_int(expected);
    emit(" Was ");
    print_int(actual);
    fail_finish(message);
}

void UnityAssertEqualUint(uintmax_t expected, uintmax_t actual, const char *message,
                          UNITY_LINE_TYPE line, UNITY_DISPLAY_STYLE_T style)
{
    if (skipping() || expected == actual) {
        return;
    }
    fail_begin(line);
    emit(" Expected ");
    print_styled(expected, style);
    emit(" Was ");
    print_styled(actual, style);
    fail_finish(message);
}

void UnityAssertIntWithin(uintmax_t delta, intmax_t expected, intmax_t actual,
                          const char *message, UNITY_LINE_TYPE line)
{
    /* The true distance always fits the unsigned type; modulo arithmetic
     * yields it exactly. */
    const uintmax_t distance = expected > actual ? (uintmax_t)expected - (uintmax_t)actual
                                                 : (uintmax_t)actual - (uintmax_t)expected;
    if (skipping() || distance <= delta) {
        return;
    }
    fail_begin(line);
    emit(" Values Not Within Delta ");
    print_uint(delta);
    emit(" Expected ");
    print_int(expected);
    emit(" Was ");
    print_int(actual);
    fail_finish(message);
}

void UnityAssertUintWithin(uintmax_t delta, uintmax_t expected, uintmax_t actual,
                           const char *message, UNITY_LINE_TYPE line,
                           UNITY_DISPLAY_STYLE_T style)
{
    const uintmax_t distance = expected > actual ? expected - actual : actual - expected;
    if (skipping() || distance <= delta) {
        return;
    }
    fail_begin(line);
    emit(" Values Not Within Delta ");
    print_styled(delta, style);
    emit(" Expected ");
    print_styled(expected, style);
    emit(" Was ");
    print_styled(actual, style);
    fail_finish(message);
}

/* ---- Floating point ------------------------------------------------------ */

/* NaN matches only NaN and an infinity only the same infinity; otherwise the
 * difference must be finite and at most |delta|. Computed in float, as the
 * float-only Unity does. */
static int floats_within(float delta, float expected, float actual)
{
    if (isnan(expected) || isnan(actual)) {
        return isnan(expected) && isnan(actual);
    }
    if (isinf(expected) || isinf(actual)) {
        return isinf(expected) && isinf(actual) && ((expected < 0.0f) == (actual < 0.0f));
    }
    const float distance = fabsf(actual - expected);
    return !isinf(distance) && distance <= fabsf(delta);
}

void UnityAssertFloatsWithin(float delta, float expected, float actual, const char *message,
                             UNITY_LINE_TYPE line)
{
    if (skipping() || floats_within(delta, expected, actual)) {
        return;
    }
    fail_begin(line);
    emit(" Expected ");
    print_float((double)expected);
    emit(" Was ");
    print_float((double)actual);
    fail_finish(message);
}

#ifdef UNITY_INCLUDE_DOUBLE
static int doubles_within(double delta, double expected, double actual)
{
    if (isnan(expected) || isnan(actual)) {
        return isnan(expected) && isnan(actual);
    }
    if (isinf(expected) || isinf(actual)) {
        return isinf(expected) && isinf(actual) && ((expected < 0.0) == (actual < 0.0));
    }
    const double distance = fabs(actual - expected);
    return !isinf(distance) && distance <= fabs(delta);
}

void UnityAssertDoublesWithin(double delta, double expected, double actual,
                              const char *message, UNITY_LINE_TYPE line)
{
    if (skipping() || doubles_within(delta, expected, actual)) {
        return;
    }
    fail_begin(line);
    emit(" Expected ");
    print_float(expected);
    emit(" Was ");
    print_float(actual);
    fail_finish(message);
}
#endif

/* ---- Memory, arrays, strings --------------------------------------------- */

/* Checks shared by memory and array comparisons: nothing to compare fails,
 * the same pointer (both NULL included) passes, one NULL side fails.
 * Returns nonzero when the elements still need comparing. */
static int blocks_need_compare(const void *expected, const void *actual, size_t count,
                               const char *message, UNITY_LINE_TYPE line)
{
    if (count == 0u) {
        fail_with(line, pointless_, message);
    }
    if (expected == actual) {
        return 0;
    }
    if (expected == NULL) {
        fail_with(line, " Expected pointer to be NULL", message);
    }
    if (actual == NULL) {
        fail_with(line, " Actual pointer was NULL", message);
    }
    return 1;
}

void UnityAssertEqualMemory(const void *expected, const void *actual, size_t length,
                            const char *message, UNITY_LINE_TYPE line)
{
    if (skipping() || !blocks_need_compare(expected, actual, length, message, line)) {
        return;
    }
    const unsigned char *e = expected;
    const unsigned char *a = actual;
    for (size_t i = 0u; i < length; i++) {
        if (e[i] != a[i]) {
            fail_begin(line);
            emit(" Memory Mismatch. Byte ");
            print_uint(i);
            emit(" Expected 0x");
            print_hex_digits(e[i], 2u);
            emit(" Was 0x");
            print_hex_digits(a[i], 2u);
            fail_finish(message);
        }
    }
}

/* Element i of an array of the given kind; memcpy avoids alignment and
 * aliasing assumptions about the caller's buffer. */
static intmax_t array_element(const void *base, size_t i, UNITY_ARRAY_KIND_T kind)
{
    const unsigned char *bytes = base;
    if (kind == UNITY_ARRAY_INT16) {
        int16_t v;
        memcpy(&v, bytes + i * sizeof v, sizeof v);
        return v;
    }
    if (kind == UNITY_ARRAY_INT32) {
        int32_t v;
        memcpy(&v, bytes + i * sizeof v, sizeof v);
        return v;
    }
    return bytes[i];
}

void UnityAssertEqualArray(const void *expected, const void *actual, size_t count,
                           const char *message, UNITY_LINE_TYPE line, UNITY_ARRAY_KIND_T kind)
{
    if (skipping() || !blocks_need_compare(expected, actual, count, message, line)) {
        return;
    }
    for (size_t i = 0u; i < count; i++) {
        const intmax_t e = array_element(expected, i, kind);
        const intmax_t a = array_element(actual, i, kind);
        if (e != a) {
            fail_begin(line);
            emit(" Element ");
            print_uint(i);
            emit(" Expected ");
            if (kind == UNITY_ARRAY_HEX8) {
                print_styled((uintmax_t)e, UNITY_DISPLAY_STYLE_HEX8);
                emit(" Was ");
                print_styled((uintmax_t)a, UNITY_DISPLAY_STYLE_HEX8);
            } else {
                print_int(e);
                emit(" Was ");
                print_int(a);
            }
            fail_finish(message);
        }
    }
}

void UnityAssertEqualString(const char *expected, const char *actual, const char *message,
                            UNITY_LINE_TYPE line)
{
    if (skipping() || expected == actual) {
        return;
    }
    size_t i = 0u;
    if (expected != NULL && actual != NULL) {
        while (expected[i] == actual[i] && expected[i] != '\0') {
            i++;
        }
        if (expected[i] == actual[i]) {
            return;
        }
    }
    fail_begin(line);
    emit(" Expected ");
    print_quoted(expected);
    emit(" Was ");
    print_quoted(actual);
    if (expected != NULL && actual != NULL) {
        emit(" Character ");
        print_uint(i);
        emit(" Expected '");
        print_char(expected[i]);
        emit("' Was '");
        print_char(actual[i]);
        put('\'');
    }
    fail_finish(message);
}
