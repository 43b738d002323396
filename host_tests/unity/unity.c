/* unity.c - the project's Unity-compatible harness; see unity.h.
 *
 * Written from ../shared/guides/unity-subset.md (behaviour of Unity v2.7.0),
 * not from Unity's sources. Output goes through UNITY_OUTPUT_CHAR, by
 * default putchar on stdout (unity.h, "Output"); user strings (file, test
 * name, messages, compared strings) print printable ASCII as is and
 * everything else escaped (\n, \r, \xNN), so one result is always one line.
 */
#include "unity.h"

#include <stdlib.h>
#include <string.h>

/* Output hooks (unity.h, "Output"). Without UNITY_OUTPUT_CHAR: putchar and
 * fflush on stdout, as always. With it, nothing of stdio is used. */
#ifdef UNITY_OUTPUT_CHAR
#define UNITY_CUSTOM_OUTPUT_ 1
#else
#define UNITY_CUSTOM_OUTPUT_ 0
#define UNITY_OUTPUT_CHAR(c) ((void)putchar(c))
#endif
#ifndef UNITY_OUTPUT_START
#define UNITY_OUTPUT_START() ((void)0)
#endif
#ifndef UNITY_OUTPUT_FLUSH
#if UNITY_CUSTOM_OUTPUT_
#define UNITY_OUTPUT_FLUSH() ((void)0)
#else
#define UNITY_OUTPUT_FLUSH() ((void)fflush(stdout))
#endif
#endif
#ifndef UNITY_OUTPUT_ABORT
#define UNITY_OUTPUT_ABORT() abort()
#endif

/* Float printing: significant digits (printf's "%.7g", or "%.9g" with
 * doubles), and the magnitude below which a value prints as "0" (Unity's
 * UNITY_FLOAT_PRECISION / UNITY_DOUBLE_PRECISION). */
#ifdef UNITY_INCLUDE_DOUBLE
#define UNITY_FLOAT_DIGITS_ 9u
#define UNITY_FLOAT_FORMAT_ "%.9g"
#define UNITY_PRINT_ZERO_BELOW_ 1e-12
#else
#define UNITY_FLOAT_DIGITS_ 7u
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
    UNITY_OUTPUT_CHAR((unsigned char)c);
}

/* Fixed text of the harness itself, written as is. */
static void emit(const char *s)
{
    while (*s != '\0') {
        put(*s++);
    }
}

static void print_hex_digits(UNITY_UINT value, unsigned digits)
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

static void print_uint(UNITY_UINT value)
{
    char digits[sizeof(UNITY_UINT) * 3u]; /* 3 decimal digits per byte suffice */
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
static void print_int(UNITY_INT value)
{
    if (value < 0) {
        put('-');
        print_uint((UNITY_UINT)0 - (UNITY_UINT)value);
    } else {
        print_uint((UNITY_UINT)value);
    }
}

/* A value as the macros passed it: a hex style prints its low 2/4/8 digits. */
static void print_styled(UNITY_INT value, UNITY_DISPLAY_STYLE_T style)
{
    if (style == UNITY_DISPLAY_STYLE_INT) {
        print_int(value);
    } else if (style == UNITY_DISPLAY_STYLE_UINT) {
        print_uint((UNITY_UINT)value);
    } else {
        emit("0x");
        print_hex_digits((UNITY_UINT)value, (unsigned)style);
    }
}

#if UNITY_CUSTOM_OUTPUT_
/* printf's "%.<digits>g" by hand (no stdio with a custom output), for a
 * finite value of magnitude at least UNITY_PRINT_ZERO_BELOW_; digits <= 17.
 * The magnitude is scaled into [1, 10) by one power of ten (exact up to
 * 10^22) and rounded half up to <digits> significant digits. printf rounds
 * the exact binary value instead, so the last digit can differ when the
 * value lies within a rounding error of a tie; the self-test's values print
 * the same either way. */
static void print_significant(double value, unsigned digits)
{
    if (value < 0.0) {
        put('-');
        value = -value;
    }
    /* scaled = value / 10^exponent, 1 <= scaled < 10 (up to rounding). */
    int exponent = 0;
    double power = 1.0;
    double scaled;
    if (value >= 1.0) {
        while (value >= power * 10.0) {
            power *= 10.0;
            exponent++;
        }
        scaled = value / power;
    } else {
        while (value * power < 1.0) {
            power *= 10.0;
            exponent--;
        }
        scaled = value * power;
    }
    uint64_t unit = 1u; /* 10^(digits - 1) */
    for (unsigned i = 1u; i < digits; i++) {
        unit *= 10u;
    }
    uint64_t mantissa = (uint64_t)(scaled * (double)unit + 0.5);
    if (mantissa >= unit * 10u) { /* rounded up to the next power of ten */
        mantissa = unit;
        exponent++;
    } else if (mantissa < unit) { /* scaled fell just below 1 */
        mantissa = unit;
    }
    char text[20] = {0}; /* the <digits> significant digits */
    for (unsigned i = digits; i > 0u; i--) {
        text[i - 1u] = (char)('0' + (int)(mantissa % 10u));
        mantissa /= 10u;
    }
    unsigned used = digits; /* without trailing zeros, at least one digit */
    while (used > 1u && text[used - 1u] == '0') {
        used--;
    }
    if (exponent < -4 || exponent >= (int)digits) {
        /* d[.ddd]e<sign><at least two digits> */
        put(text[0]);
        if (used > 1u) {
            put('.');
            for (unsigned i = 1u; i < used; i++) {
                put(text[i]);
            }
        }
        put('e');
        put(exponent < 0 ? '-' : '+');
        const unsigned magnitude = (unsigned)(exponent < 0 ? -exponent : exponent);
        if (magnitude < 10u) {
            put('0');
        }
        print_uint(magnitude);
    } else if (exponent >= 0) {
        /* ddd[.ddd]: exponent + 1 digits before the point */
        const unsigned whole = (unsigned)exponent + 1u;
        for (unsigned i = 0u; i < whole; i++) {
            put(text[i]);
        }
        if (used > whole) {
            put('.');
            for (unsigned i = whole; i < used; i++) {
                put(text[i]);
            }
        }
    } else {
        /* 0.000ddd: -exponent - 1 zeros after the point */
        emit("0.");
        for (int i = exponent + 1; i < 0; i++) {
            put('0');
        }
        for (unsigned i = 0u; i < used; i++) {
            put(text[i]);
        }
    }
}
#endif

static void print_float(double value)
{
    if (isnan(value)) {
        emit("NaN");
    } else if (isinf(value)) {
        emit(value > 0.0 ? "Infinity" : "Negative Infinity");
    } else if (fabs(value) < UNITY_PRINT_ZERO_BELOW_) {
        emit("0");
    } else {
#if UNITY_CUSTOM_OUTPUT_
        print_significant(value, UNITY_FLOAT_DIGITS_);
#else
        char text[40];
        (void)snprintf(text, sizeof text, UNITY_FLOAT_FORMAT_, value);
        emit(text);
#endif
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
#if UNITY_CUSTOM_OUTPUT_
        emit("unity: line ");
        print_uint(line);
        emit(": TEST_ macro reported outside RUN_TEST\n");
        UNITY_OUTPUT_FLUSH();
#else
        (void)fflush(stdout);
        (void)fprintf(stderr, "unity: line %lu: TEST_ macro reported outside RUN_TEST\n",
                      line);
#endif
        UNITY_OUTPUT_ABORT();
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
    UNITY_OUTPUT_START();
    unity_.file = filename;
    unity_.name = NULL;
    unity_.tests = 0u;
    unity_.failures = 0u;
    unity_.ignores = 0u;
    unity_.running = 0;
}

void UnityDefaultTestRun(UnityTestFunction func, const char *name, int line)
{
    unity_.func = func;
    unity_.name = name;
    unity_.line = line < 0 ? 0u : (UNITY_LINE_TYPE)line;
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
    UNITY_OUTPUT_FLUSH();
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
    UNITY_OUTPUT_FLUSH();
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

void UnityAssertEqualNumber(UNITY_INT expected, UNITY_INT actual, const char *message,
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

void UnityAssertNumbersWithin(UNITY_UINT delta, UNITY_INT expected, UNITY_INT actual,
                              const char *message, UNITY_LINE_TYPE line,
                              UNITY_DISPLAY_STYLE_T style)
{
    /* Signed values are ordered as signed, the others as the UNITY_UINT
     * they stand for. The true distance always fits UNITY_UINT; modulo
     * arithmetic yields it exactly. */
    const UNITY_UINT e = (UNITY_UINT)expected;
    const UNITY_UINT a = (UNITY_UINT)actual;
    const int expected_above =
        style == UNITY_DISPLAY_STYLE_INT ? expected > actual : e > a;
    const UNITY_UINT distance = expected_above ? e - a : a - e;
    if (skipping() || distance <= delta) {
        return;
    }
    fail_begin(line);
    emit(" Values Not Within Delta ");
    if (style == UNITY_DISPLAY_STYLE_INT) {
        print_uint(delta);
    } else {
        print_styled((UNITY_INT)delta, style);
    }
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
static int blocks_need_compare(const void *expected, const void *actual, uint32_t count,
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

void UnityAssertEqualMemory(const void *expected, const void *actual, uint32_t length,
                            const char *message, UNITY_LINE_TYPE line)
{
    if (skipping() || !blocks_need_compare(expected, actual, length, message, line)) {
        return;
    }
    const unsigned char *e = expected;
    const unsigned char *a = actual;
    for (uint32_t i = 0u; i < length; i++) {
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
static UNITY_INT array_element(const void *base, uint32_t i, UNITY_ARRAY_KIND_T kind)
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

void UnityAssertEqualIntArray(const void *expected, const void *actual, uint32_t count,
                              const char *message, UNITY_LINE_TYPE line,
                              UNITY_ARRAY_KIND_T kind)
{
    if (skipping() || !blocks_need_compare(expected, actual, count, message, line)) {
        return;
    }
    for (uint32_t i = 0u; i < count; i++) {
        const UNITY_INT e = array_element(expected, i, kind);
        const UNITY_INT a = array_element(actual, i, kind);
        if (e != a) {
            fail_begin(line);
            emit(" Element ");
            print_uint(i);
            emit(" Expected ");
            const UNITY_DISPLAY_STYLE_T style =
                kind == UNITY_ARRAY_HEX8 ? UNITY_DISPLAY_STYLE_HEX8 : UNITY_DISPLAY_STYLE_INT;
            print_styled(e, style);
            emit(" Was ");
            print_styled(a, style);
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
