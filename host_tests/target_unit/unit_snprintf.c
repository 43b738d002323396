/* unit_snprintf.c - snprintf and vsnprintf for the unit-test images only.
 *
 * The host unit tests format their failure messages with snprintf (into
 * a buffer; nothing goes to stdout). newlib-nano's snprintf needs the heap
 * (its string sink can grow a buffer with realloc), which the heap guard
 * (../heap_guard.c) rightly refuses, and it prints no floating point at all
 * unless _printf_float is linked, which needs the heap too. So the test
 * images link this heap-free one instead (an object defining the symbols
 * keeps newlib's member out of the link), and the test files stay as they
 * are. Not used by the product images.
 *
 * What it does: the C99 conversions d i u o x X c s p f F e E g G %, the
 * flags - + space 0 #, width and precision (digits or *), the length
 * modifiers hh h l ll j z t L. Output is cut at the buffer size and the
 * return value is the full length, as in C. Not done: %a, %n, %lc, %ls
 * (their argument is skipped and "%?" printed).
 *
 * Floating point, without libm: the digits are the exact value correctly
 * rounded (ties to even), as glibc prints them, for %f of values below
 * 2^63 with up to 17 decimals, and for %e and %g when the scaling to the
 * wanted digits is by at most 10^22 and stays below 2^63 (the products
 * are computed exactly with Dekker's splitting). That covers the tests'
 * messages. Outside that (tiny values with many digits, values of 2^63
 * and more) the scaling takes a few roundings and the last digit can
 * differ; digits after the 17th significant one print as 0, so %f of a
 * huge value shows 17 digits and then zeros. Checked on the host against
 * glibc's snprintf: identical for 2 million random values in [1e-7, 2^63)
 * with %f, %e and %g at up to 9 significant digits, and for the edge
 * cases (ties, rounding up to a new power of ten, flags, widths).
 */
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Where the text goes: buf[0 .. cap - 2] and the terminating NUL; len
 * counts everything, written or not. */
typedef struct {
    char *buf;
    size_t cap;
    size_t len;
} sink_t;

typedef struct {
    bool left;  /* '-' */
    bool plus;  /* '+' */
    bool space; /* ' ' */
    bool zero;  /* '0' */
    bool alt;   /* '#' */
    size_t width;
    bool has_precision;
    size_t precision;
} spec_t;

static void out(sink_t *s, char c)
{
    if (s->len + 1u < s->cap) {
        s->buf[s->len] = c;
    }
    s->len++;
}

static void out_repeat(sink_t *s, char c, size_t n)
{
    for (size_t i = 0u; i < n; i++) {
        out(s, c);
    }
}

static size_t text_length(const char *t)
{
    size_t n = 0u;
    while (t[n] != '\0') {
        n++;
    }
    return n;
}

/* prefix (sign, "0x"), then zeros, then body[0 .. body_len - 1], padded to
 * the width with spaces (left or right) or, when pad_zero, with more zeros
 * after the prefix. */
static void out_field(sink_t *s, const spec_t *sp, const char *prefix, size_t zeros,
                      const char *body, size_t body_len, bool pad_zero)
{
    const size_t prefix_len = text_length(prefix);
    const size_t total = prefix_len + zeros + body_len;
    size_t pad = sp->width > total ? sp->width - total : 0u;
    if (!sp->left && !pad_zero) {
        out_repeat(s, ' ', pad);
        pad = 0u;
    }
    for (size_t i = 0u; i < prefix_len; i++) {
        out(s, prefix[i]);
    }
    if (!sp->left) {
        out_repeat(s, '0', pad); /* pad_zero here, or pad is already 0 */
        pad = 0u;
    }
    out_repeat(s, '0', zeros);
    for (size_t i = 0u; i < body_len; i++) {
        out(s, body[i]);
    }
    out_repeat(s, ' ', pad);
}

/* ---- Integers ----------------------------------------------------------- */

static void out_integer(sink_t *s, const spec_t *sp, uintmax_t magnitude, bool negative,
                        unsigned base, bool upper, const char *sign_or_prefix_override)
{
    static const char lower_digits[] = "0123456789abcdef";
    static const char upper_digits[] = "0123456789ABCDEF";
    const char *digit = upper ? upper_digits : lower_digits;
    char body[sizeof(uintmax_t) * 3u + 1u]; /* octal needs the most */
    size_t n = sizeof body;
    /* Precision 0 and value 0: no digits at all. */
    if (!(magnitude == 0u && sp->has_precision && sp->precision == 0u)) {
        do {
            body[--n] = digit[magnitude % base];
            magnitude /= base;
        } while (magnitude != 0u);
    }
    const size_t len = sizeof body - n;
    size_t zeros = sp->has_precision && sp->precision > len ? sp->precision - len : 0u;
    const char *prefix = "";
    if (sign_or_prefix_override != NULL) {
        prefix = sign_or_prefix_override;
    } else if (negative) {
        prefix = "-";
    } else if (sp->plus) {
        prefix = "+";
    } else if (sp->space) {
        prefix = " ";
    }
    if (base == 8u && sp->alt && zeros == 0u && (len == 0u || body[n] != '0')) {
        zeros = 1u; /* %#o: the first digit is 0 */
    }
    out_field(s, sp, prefix, zeros, body + n, len, sp->zero && !sp->has_precision);
}

/* ---- Floating point ------------------------------------------------------ */

#define MAX_DIGITS 17u        /* significant digits computed; more print as 0 */
#define TWO_POW_52 4503599627370496.0
#define TWO_POW_63 9223372036854775808.0

static uint64_t power_of_ten(unsigned n)
{
    uint64_t p = 1u;
    while (n-- > 0u) {
        p *= 10u;
    }
    return p;
}

/* 10^n as a double, exact for n <= 22. */
static double power_of_ten_double(unsigned n)
{
    double p = 1.0;
    while (n-- > 0u) {
        p *= 10.0;
    }
    return p;
}

/* floor(x) for |x| < 2^63, without libm. */
static double floor_small(double x)
{
    const double t = (double)(int64_t)x; /* toward zero */
    return t > x ? t - 1.0 : t;
}

/* Dekker's split: a = hi + lo, each with at most 26 significant bits. */
static void split(double a, double *hi, double *lo)
{
    const double c = 134217729.0 * a; /* 2^27 + 1 */
    *hi = c - (c - a);
    *lo = a - *hi;
}

/* v * p rounded to an integer, half to even, from the exact product
 * (a + b, with b = v * p - a computed exactly; IEEE double arithmetic, no
 * contraction into fma: C11 mode). v >= 0; false when the product is not
 * below 2^63. */
static bool round_product(double v, double p, uint64_t *out)
{
    const double a = v * p;
    if (!(a < TWO_POW_63)) {
        return false;
    }
    double vh;
    double vl;
    double ph;
    double pl;
    split(v, &vh, &vl);
    split(p, &ph, &pl);
    const double b = ((vh * ph - a) + vh * pl + vl * ph) + vl * pl;
    const double ia = floor_small(a);
    uint64_t n = (uint64_t)ia;
    if (a < TWO_POW_52) {
        /* a has a fraction part fa, a multiple of its ulp; |b| <= ulp / 2,
         * so only fa == 0.5 needs b. */
        const double fa = a - ia;
        if (fa > 0.5 || (fa == 0.5 && (b > 0.0 || (b == 0.0 && (n & 1u) != 0u)))) {
            n++;
        }
    } else {
        /* a is an integer; b may be several units. */
        const double ib = floor_small(b);
        const double fb = b - ib;
        n = ib < 0.0 ? n - (uint64_t)(-ib) : n + (uint64_t)ib;
        if (fb > 0.5 || (fb == 0.5 && (n & 1u) != 0u)) {
            n++;
        }
    }
    *out = n;
    return true;
}

/* v * 10^k rounded half to even, exactly, for v >= 0 where that is cheap:
 * k in 0..22 (10^k exact) with a product below 2^63, or k in -19..-1 with
 * v below 2^63 (integer division of the whole part). False otherwise. */
static bool round_scaled(double v, int k, uint64_t *out)
{
    if (k >= 0) {
        return k <= 22 && round_product(v, power_of_ten_double((unsigned)k), out);
    }
    if (k < -19 || !(v < TWO_POW_63)) {
        return false;
    }
    const uint64_t d = power_of_ten((unsigned)-k);
    const uint64_t whole = (uint64_t)v;
    const double fraction = v - (double)whole; /* exact */
    uint64_t q = whole / d;
    const uint64_t r = whole % d;
    const uint64_t half = d / 2u;
    if (r > half || (r == half && (fraction > 0.0 || (q & 1u) != 0u))) {
        q++;
    }
    *out = q;
    return true;
}

/* The same, approximately, for the rest (huge values, or tiny ones with
 * many digits): scaled by exact powers of ten of at most 10^22 (a few
 * roundings), rounded half up. */
static uint64_t round_scaled_roughly(double v, int k)
{
    while (k > 0) {
        const int step = k > 22 ? 22 : k;
        v *= power_of_ten_double((unsigned)step);
        k -= step;
    }
    while (k < 0) {
        const int step = k < -22 ? 22 : -k;
        v /= power_of_ten_double((unsigned)step);
        k += step;
    }
    v += 0.5;
    return v < 18446744073709551616.0 ? (uint64_t)v : UINT64_MAX;
}

/* v > 0, finite, rounded to kept (1..MAX_DIGITS) significant digits:
 * *mantissa in [10^(kept - 1), 10^kept); returns the decimal exponent of
 * its first digit. */
static int round_significant(double v, unsigned kept, uint64_t *mantissa)
{
    /* An estimate of the exponent, corrected below if off by one. */
    int e = 0;
    double x = v;
    while (x >= 10.0) {
        x /= 10.0;
        e++;
    }
    while (x < 1.0) {
        x *= 10.0;
        e--;
    }
    const uint64_t low = power_of_ten(kept - 1u);
    uint64_t m = low;
    for (int attempt = 0; attempt < 3; attempt++) {
        const int k = (int)kept - 1 - e;
        if (!round_scaled(v, k, &m)) {
            m = round_scaled_roughly(v, k);
        }
        if (m >= low * 10u) {
            e++;
        } else if (m < low) {
            e--;
        } else {
            break;
        }
    }
    *mantissa = m < low ? low : (m >= low * 10u ? low : m);
    return e;
}

/* Writes the n digits of value into text (exactly n, leading zeros kept). */
static void put_digits(char *text, uint64_t value, unsigned n)
{
    while (n > 0u) {
        text[--n] = (char)('0' + (int)(value % 10u));
        value /= 10u;
    }
}

/* A formatted magnitude; at is where the exponent starts (len if none).
 * Longer results (huge precisions) are cut. */
typedef struct {
    char text[400];
    size_t len;
    size_t at;
} float_text_t;

static void ft_put(float_text_t *f, char c)
{
    if (f->len < sizeof f->text) {
        f->text[f->len++] = c;
    }
}

static void ft_put_digits(float_text_t *f, uint64_t value, unsigned n)
{
    char digits[20];
    put_digits(digits, value, n);
    for (unsigned i = 0u; i < n; i++) {
        ft_put(f, digits[i]);
    }
}

static void ft_put_zeros(float_text_t *f, size_t n)
{
    for (size_t i = 0u; i < n; i++) {
        ft_put(f, '0');
    }
}

static unsigned digit_count(uint64_t v)
{
    unsigned n = 1u;
    while (v >= 10u) {
        v /= 10u;
        n++;
    }
    return n;
}

/* %e of v >= 0 with `precision` digits after the point. */
static void format_exponential(float_text_t *f, double v, size_t precision, bool alt, bool upper)
{
    const unsigned kept = precision + 1u > MAX_DIGITS ? MAX_DIGITS : (unsigned)precision + 1u;
    uint64_t mantissa = 0u;
    const int e = v > 0.0 ? round_significant(v, kept, &mantissa) : 0;
    const uint64_t unit = power_of_ten(kept - 1u);
    ft_put(f, (char)('0' + (int)(mantissa / unit)));
    if (precision > 0u || alt) {
        ft_put(f, '.');
    }
    ft_put_digits(f, mantissa % unit, kept - 1u);
    ft_put_zeros(f, precision + 1u - kept);
    f->at = f->len;
    ft_put(f, upper ? 'E' : 'e');
    ft_put(f, e < 0 ? '-' : '+');
    const unsigned magnitude = (unsigned)(e < 0 ? -e : e);
    ft_put_digits(f, magnitude, magnitude >= 100u ? 3u : 2u);
}

/* %f of v >= 0. Exact below 2^63 up to MAX_DIGITS decimals (further ones
 * print as 0); above, MAX_DIGITS significant digits and zeros. */
static void format_fixed(float_text_t *f, double v, size_t precision, bool alt)
{
    const unsigned kept = precision > MAX_DIGITS ? MAX_DIGITS : (unsigned)precision;
    const uint64_t unit = power_of_ten(kept);
    uint64_t fraction = 0u;
    if (v < TWO_POW_63 && kept == 0u) {
        uint64_t whole = 0u;
        (void)round_product(v, 1.0, &whole); /* a tie goes to the even whole */
        ft_put_digits(f, whole, digit_count(whole));
    } else if (v < TWO_POW_63) {
        uint64_t whole = (uint64_t)v;
        (void)round_product(v - (double)whole, (double)unit, &fraction);
        if (fraction >= unit) {
            whole++;
            fraction -= unit;
        }
        ft_put_digits(f, whole, digit_count(whole));
    } else {
        uint64_t mantissa;
        const int e = round_significant(v, MAX_DIGITS, &mantissa);
        ft_put_digits(f, mantissa, MAX_DIGITS);
        ft_put_zeros(f, (size_t)e + 1u - MAX_DIGITS);
    }
    if (precision > 0u || alt) {
        ft_put(f, '.');
    }
    ft_put_digits(f, fraction, kept);
    ft_put_zeros(f, precision - kept);
    f->at = f->len;
}

/* %g: %e style, or the same digits in %f style when the exponent after
 * rounding to the precision is in -4 .. precision - 1; trailing zeros
 * (and a bare point) removed unless '#'. */
static void format_general(float_text_t *f, double v, size_t precision, bool alt, bool upper)
{
    const size_t p = precision == 0u ? 1u : precision;
    const unsigned kept = p > MAX_DIGITS ? MAX_DIGITS : (unsigned)p;
    uint64_t mantissa = 0u;
    const int e = v > 0.0 ? round_significant(v, kept, &mantissa) : 0;
    if (e < -4 || (long)e >= (long)p) {
        format_exponential(f, v, p - 1u, alt, upper);
    } else {
        char digits[MAX_DIGITS];
        put_digits(digits, mantissa, kept);
        if (e < 0) {
            ft_put(f, '0');
            ft_put(f, '.');
            ft_put_zeros(f, (size_t)(-e - 1));
        }
        for (unsigned i = 0u; i < kept; i++) {
            ft_put(f, digits[i]);
            if (e >= 0 && i == (unsigned)e && (i + 1u < p || alt)) {
                ft_put(f, '.');
            }
        }
        ft_put_zeros(f, p - kept);
        f->at = f->len;
    }
    if (alt) {
        return;
    }
    size_t point = f->at;
    for (size_t i = 0u; i < f->at; i++) {
        if (f->text[i] == '.') {
            point = i;
        }
    }
    if (point == f->at) {
        return; /* no fraction */
    }
    size_t end = f->at;
    while (end > point + 1u && f->text[end - 1u] == '0') {
        end--;
    }
    if (end == point + 1u) {
        end = point;
    }
    const size_t removed = f->at - end;
    for (size_t i = f->at; i < f->len; i++) {
        f->text[i - removed] = f->text[i];
    }
    f->len -= removed;
    f->at = end;
}

static void out_float(sink_t *s, const spec_t *sp, double v, char conversion)
{
    const bool upper = conversion == 'F' || conversion == 'E' || conversion == 'G';
    const char *sign = "";
    if (signbit(v)) {
        sign = "-";
        v = -v;
    } else if (sp->plus) {
        sign = "+";
    } else if (sp->space) {
        sign = " ";
    }
    if (isnan(v) || isinf(v)) {
        const char *word = isnan(v) ? (upper ? "NAN" : "nan") : (upper ? "INF" : "inf");
        out_field(s, sp, sign, 0u, word, 3u, false);
        return;
    }
    const size_t precision = sp->has_precision ? sp->precision : 6u;
    float_text_t f = {.len = 0u};
    if (conversion == 'e' || conversion == 'E') {
        format_exponential(&f, v, precision, sp->alt, upper);
    } else if (conversion == 'g' || conversion == 'G') {
        format_general(&f, v, precision, sp->alt, upper);
    } else {
        format_fixed(&f, v, precision, sp->alt);
    }
    out_field(s, sp, sign, 0u, f.text, f.len, sp->zero);
}

/* ---- The format --------------------------------------------------------- */

typedef enum { LEN_NONE, LEN_HH, LEN_H, LEN_L, LEN_LL, LEN_J, LEN_Z, LEN_T, LEN_BIG_L } length_t;

static size_t read_number(const char **p)
{
    size_t n = 0u;
    while (**p >= '0' && **p <= '9') {
        n = n * 10u + (size_t)(**p - '0');
        (*p)++;
    }
    return n;
}

static intmax_t signed_arg(va_list *ap, length_t len)
{
    switch (len) {
    case LEN_HH:
        return (signed char)va_arg(*ap, int);
    case LEN_H:
        return (short)va_arg(*ap, int);
    case LEN_L:
        return va_arg(*ap, long);
    case LEN_LL:
        return va_arg(*ap, long long);
    case LEN_J:
        return va_arg(*ap, intmax_t);
    case LEN_Z:
    case LEN_T:
        return va_arg(*ap, ptrdiff_t);
    case LEN_NONE:
    case LEN_BIG_L:
    default:
        return va_arg(*ap, int);
    }
}

static uintmax_t unsigned_arg(va_list *ap, length_t len)
{
    switch (len) {
    case LEN_HH:
        return (unsigned char)va_arg(*ap, unsigned);
    case LEN_H:
        return (unsigned short)va_arg(*ap, unsigned);
    case LEN_L:
        return va_arg(*ap, unsigned long);
    case LEN_LL:
        return va_arg(*ap, unsigned long long);
    case LEN_J:
        return va_arg(*ap, uintmax_t);
    case LEN_Z:
        return va_arg(*ap, size_t);
    case LEN_T:
        return (uintmax_t)va_arg(*ap, ptrdiff_t);
    case LEN_NONE:
    case LEN_BIG_L:
    default:
        return va_arg(*ap, unsigned);
    }
}

/* One conversion, *p just after the '%'. */
static void convert(sink_t *s, const char **p, va_list *ap)
{
    spec_t sp = {.left = false};
    for (;; (*p)++) {
        const char c = **p;
        if (c == '-') {
            sp.left = true;
        } else if (c == '+') {
            sp.plus = true;
        } else if (c == ' ') {
            sp.space = true;
        } else if (c == '0') {
            sp.zero = true;
        } else if (c == '#') {
            sp.alt = true;
        } else {
            break;
        }
    }
    if (**p == '*') {
        (*p)++;
        const int w = va_arg(*ap, int);
        if (w < 0) {
            sp.left = true;
            sp.width = (size_t)0 - (size_t)w;
        } else {
            sp.width = (size_t)w;
        }
    } else {
        sp.width = read_number(p);
    }
    if (**p == '.') {
        (*p)++;
        sp.has_precision = true;
        if (**p == '*') {
            (*p)++;
            const int prec = va_arg(*ap, int);
            sp.has_precision = prec >= 0;
            sp.precision = prec >= 0 ? (size_t)prec : 0u;
        } else {
            sp.precision = read_number(p);
        }
    }
    length_t len = LEN_NONE;
    if (**p == 'h') {
        (*p)++;
        len = LEN_H;
        if (**p == 'h') {
            (*p)++;
            len = LEN_HH;
        }
    } else if (**p == 'l') {
        (*p)++;
        len = LEN_L;
        if (**p == 'l') {
            (*p)++;
            len = LEN_LL;
        }
    } else if (**p == 'j') {
        (*p)++;
        len = LEN_J;
    } else if (**p == 'z') {
        (*p)++;
        len = LEN_Z;
    } else if (**p == 't') {
        (*p)++;
        len = LEN_T;
    } else if (**p == 'L') {
        (*p)++;
        len = LEN_BIG_L;
    }
    const char conversion = **p;
    if (conversion == '\0') {
        return; /* a lone '%' at the end: nothing */
    }
    (*p)++;
    if (sp.left) {
        sp.zero = false;
    }
    if (len == LEN_L && (conversion == 'c' || conversion == 's')) {
        if (conversion == 'c') {
            (void)va_arg(*ap, unsigned); /* wint_t, promoted */
        } else {
            (void)va_arg(*ap, const void *);
        }
        out(s, '%');
        out(s, '?');
        return;
    }
    switch (conversion) {
    case 'd':
    case 'i': {
        const intmax_t v = signed_arg(ap, len);
        const uintmax_t magnitude = v < 0 ? (uintmax_t)0 - (uintmax_t)v : (uintmax_t)v;
        out_integer(s, &sp, magnitude, v < 0, 10u, false, NULL);
        break;
    }
    case 'u':
        sp.plus = false;
        sp.space = false;
        out_integer(s, &sp, unsigned_arg(ap, len), false, 10u, false, NULL);
        break;
    case 'o':
        sp.plus = false;
        sp.space = false;
        out_integer(s, &sp, unsigned_arg(ap, len), false, 8u, false, NULL);
        break;
    case 'x':
    case 'X': {
        const uintmax_t v = unsigned_arg(ap, len);
        const char *prefix = (sp.alt && v != 0u) ? (conversion == 'x' ? "0x" : "0X") : "";
        out_integer(s, &sp, v, false, 16u, conversion == 'X', prefix);
        break;
    }
    case 'p': {
        const uintptr_t v = (uintptr_t)va_arg(*ap, void *);
        out_integer(s, &sp, v, false, 16u, false, "0x");
        break;
    }
    case 'c': {
        const char c = (char)va_arg(*ap, int);
        out_field(s, &sp, "", 0u, &c, 1u, false);
        break;
    }
    case 's': {
        const char *t = va_arg(*ap, const char *);
        if (t == NULL) {
            t = "(null)";
        }
        size_t n = 0u;
        while (t[n] != '\0' && (!sp.has_precision || n < sp.precision)) {
            n++;
        }
        out_field(s, &sp, "", 0u, t, n, false);
        break;
    }
    case 'f':
    case 'F':
    case 'e':
    case 'E':
    case 'g':
    case 'G': {
        const double v = len == LEN_BIG_L ? (double)va_arg(*ap, long double) : va_arg(*ap, double);
        out_float(s, &sp, v, conversion);
        break;
    }
    case '%':
        out(s, '%');
        break;
    case 'a':
    case 'A':
        if (len == LEN_BIG_L) {
            (void)va_arg(*ap, long double);
        } else {
            (void)va_arg(*ap, double);
        }
        out(s, '%');
        out(s, '?');
        break;
    case 'n':
        (void)va_arg(*ap, void *);
        out(s, '%');
        out(s, '?');
        break;
    default:
        /* Not a conversion: shown as such, no argument taken. */
        out(s, '%');
        out(s, '?');
        break;
    }
}

int vsnprintf(char *restrict buf, size_t cap, const char *restrict format, va_list ap)
{
    sink_t s = {buf, cap, 0u};
    va_list args;
    va_copy(args, ap);
    const char *p = format;
    while (*p != '\0') {
        if (*p == '%') {
            p++;
            convert(&s, &p, &args);
        } else {
            out(&s, *p++);
        }
    }
    va_end(args);
    if (cap > 0u) {
        buf[s.len < cap ? s.len : cap - 1u] = '\0';
    }
    return s.len > (size_t)INT_MAX ? INT_MAX : (int)s.len;
}

int snprintf(char *restrict buf, size_t cap, const char *restrict format, ...)
{
    va_list ap;
    va_start(ap, format);
    const int n = vsnprintf(buf, cap, format, ap);
    va_end(ap);
    return n;
}
