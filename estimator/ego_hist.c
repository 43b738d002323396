/* ego_hist.c - see ego_hist.h. */
#include "ego_hist.h"

#include <stddef.h>
#include <string.h>

#include "ego_fx_math.h"

/* Local maxima of the correlation kept before choosing candidates. */
#define PEAKS_MAX EGO_HIST_PEAKS_MAX
/* Bins are scaled to at most this before correlating (see ego_hist.h). */
#define SCALED_MAX 0x8000u

void ego_hist_defaults(ego_hist_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->kind = EGO_HIST_HTAH;
    params->half_window = 3u;
    params->t_line = FX_Q16_16_C(0.05);
    params->aoi = NULL;
}

uint16_t ego_hist_bin_of(fx_bam32_t direction)
{
    const uint32_t half = direction & (FX_BAM32_HALF - 1u); /* mod 180 deg */
    return (uint16_t)(((uint64_t)half * EGO_HIST_BINS) >> 31);
}

fx_bam32_t ego_hist_bin_centre(uint16_t b)
{
    /* (b + 1/2) * 2^31 / EGO_HIST_BINS, rounded. */
    const uint64_t twice = (uint64_t)(2u * b + 1u) << 30;
    return (fx_bam32_t)((twice + EGO_HIST_BINS / 2u) / EGO_HIST_BINS);
}

/* Direction of the segment from point i to i + 1, mod 180 deg. */
static fx_bam32_t segment_direction(const ego_scan_t *scan, uint16_t i)
{
    const int64_t dx = (int64_t)scan->x[i + 1u] - scan->x[i];
    const int64_t dy = (int64_t)scan->y[i + 1u] - scan->y[i];
    return fx_atan2(dy, dx) & (FX_BAM32_HALF - 1u);
}

static uint32_t segment_length_mm(const ego_scan_t *scan, uint16_t i)
{
    const int64_t dx = (int64_t)scan->x[i + 1u] - scan->x[i];
    const int64_t dy = (int64_t)scan->y[i + 1u] - scan->y[i];
    const uint64_t len = fx_sqrt_u64((uint64_t)(dx * dx + dy * dy)); /* Q16.16 m */
    return (uint32_t)((len * 1000u + 0x8000u) >> 16);
}

/* Is the segment from i to i + 1 a surface (linked, not an occlusion)? */
static bool is_surface(const ego_scan_t *scan, uint16_t i)
{
    return (scan->flags[i] & (EGO_LINK_BREAK | EGO_LINK_OCCLUSION)) == 0u;
}

/* Are points i - n .. i + n all in one segment? */
static bool has_full_window(const ego_scan_t *scan, uint16_t i, uint8_t n)
{
    if (i < n || (uint32_t)i + n >= scan->count) {
        return false;
    }
    for (uint16_t j = (uint16_t)(i - n); j < i + n; j++) {
        if (!ego_scan_linked(scan, j)) {
            return false;
        }
    }
    return true;
}

/* The window of eq. 7 around P[i]: P[i - n] .. P[i + n] relative to P[i],
 * computed once per point for all the directions tested. */
typedef struct {
    uint16_t count; /* 2 n + 1 */
    fx_q16_16_t rx[2u * EGO_TFIT_MAX_HALF_WINDOW + 1u];
    fx_q16_16_t ry[2u * EGO_TFIT_MAX_HALF_WINDOW + 1u];
    uint32_t drift_per_bin; /* most any deviation 2 d_k - (d_first + d_last) can
                               change from one bin centre to the next, Q16.16;
                               UINT32_MAX: no bins are skipped (see band_test) */
} window_t;

/* Skipping bins in the HTAH walk (band_test). The deviation of window point
 * k from the band's middle at direction phi, in real numbers, is
 *   D_k(phi) = A_k cos(phi) - B_k sin(phi),
 *   A_k = 2 ry_k - ry_first - ry_last,  B_k = 2 rx_k - rx_first - rx_last,
 * so it changes by at most (|A_k| + |B_k|) |dphi|. Neighbouring bin
 * centres are at most 2386093 binary-angle units apart (2^31 / EGO_HIST_BINS,
 * rounded up), 0.0034907 rad: bounded by BIN_STEP_PPM micro-radians. The
 * fixed-point deviation that band_test computes is within 4.2 LSB of D_k
 * (each product rounds by 0.5 LSB, the sine and cosine are within 0.76
 * LSB of Q2.30, coordinates below 2^24: 1.03 LSB per offset, four offsets
 * per deviation), so a bin whose largest deviation leaves slack below the
 * band's half-width guarantees that the next slack / drift_per_bin bins on
 * either side pass too, with DEVIATION_ERROR (twice 4.2, rounded up) kept
 * aside: they are counted without being computed, and the votes are
 * exactly those of testing every bin. */
#define BIN_STEP_PPM 3492u
#define DEVIATION_ERROR 10
#define SKIP_COORD_LIMIT ((int32_t)1 << 24)

/* False when n is 0 or above EGO_TFIT_MAX_HALF_WINDOW (no window). */
static bool window_of(const ego_scan_t *scan, uint16_t i, uint8_t n, window_t *w)
{
    if (n == 0u || n > EGO_TFIT_MAX_HALF_WINDOW) {
        return false;
    }
    memset(w, 0, sizeof *w); /* once per point; the slots past count stay 0 */
    w->count = (uint16_t)(2u * n + 1u);
    bool small = true;
    for (uint16_t k = 0u; k < w->count; k++) {
        const uint16_t j = (uint16_t)(i - n + k);
        w->rx[k] = fx_sub_q16(scan->x[j], scan->x[i]);
        w->ry[k] = fx_sub_q16(scan->y[j], scan->y[i]);
        small = small && w->rx[k] > -SKIP_COORD_LIMIT && w->rx[k] < SKIP_COORD_LIMIT &&
                w->ry[k] > -SKIP_COORD_LIMIT && w->ry[k] < SKIP_COORD_LIMIT;
    }
    const uint16_t last = (uint16_t)(w->count - 1u);
    int64_t most = 0;
    for (uint16_t k = 0u; k < w->count; k++) {
        const int64_t a = 2 * (int64_t)w->ry[k] - w->ry[0] - w->ry[last];
        const int64_t b = 2 * (int64_t)w->rx[k] - w->rx[0] - w->rx[last];
        const int64_t change = ((a < 0) ? -a : a) + ((b < 0) ? -b : b);
        most = (change > most) ? change : most;
    }
    /* Rounded up; below 2^27 * 3492 / 10^6 for coordinates below 2^24. */
    w->drift_per_bin =
        small ? (uint32_t)((most * BIN_STEP_PPM + 999999) / 1000000) : UINT32_MAX;
    return true;
}

/* Distance of window point k from the line through P[i] with direction
 * (c, s): ry c - rx s. */
static fx_q16_16_t line_offset(const window_t *w, uint16_t k, fx_q2_30_t s, fx_q2_30_t c)
{
    return fx_sub_q16(fx_mul_q16_q30(w->ry[k], c), fx_mul_q16_q30(w->rx[k], s));
}

/* Eq. 7 for the line through P[i] along the centre of bin b: every point
 * of the window within t_line of the band's middle (the mean of the two
 * end offsets). When it holds, *skip gets how many bins on either side
 * are sure to hold as well (see BIN_STEP_PPM; 0 when none are). */
static bool band_test(const window_t *w, fx_q16_16_t t_line, uint16_t b, uint32_t *skip)
{
    *skip = 0u;
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(ego_hist_bin_centre(b), &s, &c);
    const uint16_t last = (uint16_t)(w->count - 1u);
    const fx_q16_16_t d_first = line_offset(w, 0u, s, c);
    const fx_q16_16_t d_last = line_offset(w, last, s, c);
    const int64_t mid2 = (int64_t)d_first + d_last; /* 2 d' */
    const int64_t limit = 2 * (int64_t)t_line;
    int64_t worst = 0;
    for (uint16_t k = 0u; k <= last; k++) {
        const fx_q16_16_t d = (k == 0u) ? d_first : (k == last) ? d_last : line_offset(w, k, s, c);
        const int64_t dev2 = 2 * (int64_t)d - mid2;
        const int64_t size = (dev2 < 0) ? -dev2 : dev2;
        if (size > limit) {
            return false;
        }
        worst = (size > worst) ? size : worst;
    }
    const int64_t slack = limit - worst - DEVIATION_ERROR;
    if (slack > 0 && w->drift_per_bin != UINT32_MAX) {
        *skip = (w->drift_per_bin == 0u) ? EGO_HIST_BINS : (uint32_t)(slack / w->drift_per_bin);
    }
    return true;
}

static bool band_holds(const window_t *w, fx_q16_16_t t_line, uint16_t b)
{
    uint32_t skip;
    return band_test(w, t_line, b, &skip);
}

static uint16_t bin_step(uint16_t b, int direction)
{
    if (direction > 0) {
        return (uint16_t)((b + 1u == EGO_HIST_BINS) ? 0u : b + 1u);
    }
    return (uint16_t)((b == 0u) ? EGO_HIST_BINS - 1u : b - 1u);
}

/* HTAH votes of point i: the contiguous run of passing bins around its
 * tangent. At most EGO_HIST_BINS bins; the bins band_test vouches for are
 * counted without being tested. */
static uint32_t vote_htah(const ego_scan_t *scan, uint16_t i, const ego_hist_params_t *p, ego_hist_t *h)
{
    const uint16_t start = ego_hist_bin_of(scan->tangent[i]);
    window_t w;
    uint32_t start_skip = 0u;
    if (!window_of(scan, i, p->half_window, &w) || !band_test(&w, p->t_line, start, &start_skip)) {
        return 0u;
    }
    h->bin[start]++;
    uint32_t votes = 1u;
    uint16_t up = start;
    uint32_t skip = start_skip;
    for (;;) { /* upwards */
        const uint16_t next = bin_step(up, +1);
        if (next == start) {
            break;
        }
        if (skip > 0u) {
            skip--;
        } else if (!band_test(&w, p->t_line, next, &skip)) {
            break;
        }
        h->bin[next]++;
        votes++;
        up = next;
    }
    uint16_t down = start;
    skip = start_skip;
    for (;;) { /* downwards, not into the upward run */
        const uint16_t next = bin_step(down, -1);
        if (next == up) {
            break;
        }
        if (skip > 0u) {
            skip--;
        } else if (!band_test(&w, p->t_line, next, &skip)) {
            break;
        }
        h->bin[next]++;
        votes++;
        down = next;
    }
    return votes;
}

uint32_t ego_hist_vote(const ego_scan_t *scan, const ego_hist_params_t *params, uint16_t first,
                       uint16_t end, ego_hist_t *h)
{
    uint32_t votes = 0u;
    uint8_t n = params->half_window;
    n = (n < 1u) ? 1u : (n > EGO_TFIT_MAX_HALF_WINDOW ? EGO_TFIT_MAX_HALF_WINDOW : n);
    end = (end > scan->count) ? scan->count : end;

    switch (params->kind) {
    case EGO_HIST_AH:
    case EGO_HIST_LAH:
        for (uint16_t i = first; i < end && i + 1u < scan->count; i++) {
            if (!is_surface(scan, i)) {
                continue;
            }
            const uint16_t b = ego_hist_bin_of(segment_direction(scan, i));
            h->bin[b] += (params->kind == EGO_HIST_AH) ? 1u : segment_length_mm(scan, i);
            votes++;
        }
        break;
    case EGO_HIST_HAH:
        for (uint16_t i = first; i < end; i++) {
            window_t w;
            if (!has_full_window(scan, i, n) || !window_of(scan, i, n, &w)) {
                continue;
            }
            for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
                if ((params->aoi == NULL || params->aoi[b] != 0u) &&
                    band_holds(&w, params->t_line, b)) {
                    h->bin[b]++;
                    votes++;
                }
            }
        }
        break;
    case EGO_HIST_HTAH:
        for (uint16_t i = first; i < end; i++) {
            if ((scan->flags[i] & EGO_POINT_HAS_TANGENT) != 0u && has_full_window(scan, i, n)) {
                votes += vote_htah(scan, i, params, h);
            }
        }
        break;
    }
    return votes;
}

uint32_t ego_hist_build(const ego_scan_t *scan, const ego_hist_params_t *params, ego_hist_t *h)
{
    memset(h, 0, sizeof *h);
    return ego_hist_vote(scan, params, 0u, scan->count, h);
}

void ego_hist_aoi_mask(const ego_hist_t *h, uint32_t threshold, uint16_t widen, uint8_t *mask)
{
    memset(mask, 0, EGO_HIST_BINS);
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        if (h->bin[b] < threshold || h->bin[b] == 0u) {
            continue;
        }
        for (int32_t k = -(int32_t)widen; k <= (int32_t)widen; k++) {
            const int32_t m = ((int32_t)b + k + (int32_t)EGO_HIST_BINS * 2) % (int32_t)EGO_HIST_BINS;
            mask[m] = 1u;
        }
    }
}

fx_bam32_t ego_hist_main_direction(const ego_hist_t *h)
{
    uint16_t best = 0u;
    for (uint16_t b = 1u; b < EGO_HIST_BINS; b++) {
        if (h->bin[b] > h->bin[best]) {
            best = b;
        }
    }
    return ego_hist_bin_centre(best);
}

/* A histogram scaled down: s[i] = bin[i] >> shift, with shift chosen so
 * that no s[i] exceeds SCALED_MAX, and sum = sum of s[i]. The correlation
 * of eq. 5 needs the centred values a[i] = EGO_HIST_BINS s[i] - sum; because
 * sum(a) = 0 the centring comes out of the sums:
 *   sum_i a[i] b[i + j] = M (M sum_i s[i] t[i + j] - S T)
 *   sum_i a[i]^2        = M (M sum_i s[i]^2 - S^2)
 * (M = EGO_HIST_BINS), so each shift costs one plain dot product of the scaled
 * bins: products < 2^30, sums < 2^40, M times them < 2^50. */
typedef struct {
    const uint32_t *bin;
    unsigned shift;
    int64_t sum;
} scaled_t;

static scaled_t scale(const ego_hist_t *h)
{
    uint32_t max = 0u;
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        max = (h->bin[b] > max) ? h->bin[b] : max;
    }
    scaled_t c = {h->bin, 0u, 0};
    while ((max >> c.shift) > SCALED_MAX) {
        c.shift++;
    }
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        c.sum += (int64_t)(h->bin[b] >> c.shift);
    }
    return c;
}

/* sum of (a[i] >> sa) (b[k + i] >> sb) for i < n: the inner loop, with no
 * wrap-around inside it. */
static uint64_t dot_run(const uint32_t *a, unsigned sa, const uint32_t *b, unsigned sb, uint32_t n)
{
    uint64_t dot = 0u;
    for (uint32_t i = 0u; i < n; i++) {
        dot += (uint64_t)(a[i] >> sa) * (b[i] >> sb);
    }
    return dot;
}

/* The runs of bins of a scaled histogram that are not zero: a tangent
 * histogram has most of its bins empty, and every shift's dot product
 * needs only these. Too many runs: `dense`, use every bin. */
#define EGO_HIST_MAX_RUNS 16u /* seen: at most 4 on every stream */

typedef struct {
    uint16_t start;
    uint16_t length;
} run_t;

/* More runs than that, but at most EGO_HIST_MAX_SCATTERED bins that are not
 * zero (a plain angle histogram of a short scan: single votes spread
 * over many directions): the list of those bins. */
#define EGO_HIST_MAX_SCATTERED 128u

typedef struct {
    bool dense;
    uint8_t count;
    run_t run[EGO_HIST_MAX_RUNS];
    uint16_t scattered;               /* bins in bin[] (valid when dense) */
    uint16_t bin[EGO_HIST_MAX_SCATTERED]; /* ... or 0 when there are more */
} runs_t;

static void find_scattered(const scaled_t *a, runs_t *r)
{
    r->scattered = 0u;
    for (uint16_t b = 0u; b < EGO_HIST_BINS; b++) {
        if ((a->bin[b] >> a->shift) == 0u) {
            continue;
        }
        if (r->scattered == EGO_HIST_MAX_SCATTERED) {
            r->scattered = 0u;
            return;
        }
        r->bin[r->scattered++] = b;
    }
}

static void find_runs(const scaled_t *a, runs_t *r)
{
    r->dense = false;
    r->count = 0u;
    r->scattered = 0u;
    uint16_t b = 0u;
    while (b < EGO_HIST_BINS) { /* each bin is passed once */
        if ((a->bin[b] >> a->shift) == 0u) {
            b++;
            continue;
        }
        if (r->count == EGO_HIST_MAX_RUNS) {
            r->dense = true;
            find_scattered(a, r);
            return;
        }
        const uint16_t start = b;
        while (b < EGO_HIST_BINS && (a->bin[b] >> a->shift) != 0u) {
            b++;
        }
        r->run[r->count].start = start;
        r->run[r->count].length = (uint16_t)(b - start);
        r->count++;
    }
}

/* A run's own work in a shift (its place modulo M, two pieces), counted as
 * this many products; a scattered bin's indexing as one more. */
#define RUN_OVERHEAD_PRODUCTS 6u

/* M sum_i s[i] t[i + shift] - S T (indices modulo M): the centred dot
 * product over M, over a's runs (the zero bins add nothing), each as at
 * most two straight pieces, or over its scattered bins; runs NULL: over
 * every bin. */
static int64_t dot_shifted(const scaled_t *a, const runs_t *runs, const scaled_t *b,
                           int32_t shift)
{
    const uint32_t k =
        (uint32_t)((shift % (int32_t)EGO_HIST_BINS + (int32_t)EGO_HIST_BINS) % (int32_t)EGO_HIST_BINS);
    uint64_t dot = 0u;
    if (runs != NULL && runs->dense && runs->scattered > 0u) {
        for (uint16_t e = 0u; e < runs->scattered; e++) {
            const uint32_t i = runs->bin[e];
            const uint32_t at = (i + k < EGO_HIST_BINS) ? i + k : i + k - EGO_HIST_BINS;
            dot += (uint64_t)(a->bin[i] >> a->shift) * (b->bin[at] >> b->shift);
        }
    } else if (runs == NULL || runs->dense) {
        const uint32_t first = EGO_HIST_BINS - k; /* i = 0 .. first - 1 meet b[k .. M - 1] */
        dot = dot_run(a->bin, a->shift, &b->bin[k], b->shift, first) +
              dot_run(&a->bin[first], a->shift, b->bin, b->shift, k);
    } else {
        for (uint8_t r = 0u; r < runs->count; r++) {
            const uint32_t start = runs->run[r].start;
            const uint32_t length = runs->run[r].length;
            const uint32_t at = (start + k) % EGO_HIST_BINS; /* b's index of a[start] */
            const uint32_t straight = (EGO_HIST_BINS - at < length) ? EGO_HIST_BINS - at : length;
            dot += dot_run(&a->bin[start], a->shift, &b->bin[at], b->shift, straight);
            dot += dot_run(&a->bin[start + straight], a->shift, b->bin, b->shift,
                           length - straight);
        }
    }
    return (int64_t)EGO_HIST_BINS * (int64_t)dot - a->sum * b->sum;
}

/* num / den as Q2.30, |num| <= den (Cauchy-Schwarz), den > 0. */
static fx_q2_30_t ratio_q30(int64_t num, int64_t den)
{
    while (den >= ((int64_t)1 << 31)) {
        num /= 2;
        den /= 2;
    }
    if (den == 0) {
        return 0;
    }
    return (fx_q2_30_t)((num * ((int64_t)1 << 30)) / den);
}

typedef ego_hist_peak_t peak_t;

/* Keeps the PEAKS_MAX largest local maxima, sorted, largest first. */
static void keep_peak(peak_t *peaks, uint8_t *count, const peak_t *p)
{
    uint8_t at = *count;
    while (at > 0u && peaks[at - 1u].value < p->value) {
        at--;
    }
    if (at >= PEAKS_MAX) {
        return;
    }
    const uint8_t last = (*count < PEAKS_MAX) ? *count : (uint8_t)(PEAKS_MAX - 1u);
    for (uint8_t k = last; k > at; k--) {
        peaks[k] = peaks[k - 1u];
    }
    peaks[at] = *p;
    if (*count < PEAKS_MAX) {
        (*count)++;
    }
}

/* Rotation of a peak, refined by the parabola through its neighbours. */
static fx_bam32_t peak_rotation(const peak_t *p)
{
    const int64_t curv = p->left - 2 * p->value + p->right; /* < 0 at a maximum */
    int64_t offset_q16 = 0;
    if (curv < 0) {
        /* (left - right) / (2 curv) in bins, Q16; within (-1/2, 1/2]. */
        int64_t num = p->left - p->right;
        int64_t den = 2 * curv;
        while (num > ((int64_t)1 << 46) || num < -((int64_t)1 << 46)) {
            num /= 2;
            den /= 2;
        }
        if (den != 0) {
            offset_q16 = (num * 65536) / den;
        }
        offset_q16 = (offset_q16 > 32768) ? 32768 : (offset_q16 < -32768 ? -32768 : offset_q16);
    }
    /* (shift + offset) bins * 2^31 / EGO_HIST_BINS; wraps modulo a turn. */
    const int64_t bins_q16 = (int64_t)p->shift * 65536 + offset_q16;
    const int64_t bam = (bins_q16 * ((int64_t)1 << 15)) / (int64_t)EGO_HIST_BINS;
    return (fx_bam32_t)(uint64_t)bam;
}

/* A rotation in bins (0.2 deg), rounded: |result| <= EGO_HIST_BINS. */
static int32_t bins_of(fx_bam32_t rotation)
{
    const int64_t q = (int64_t)fx_bam32_diff(rotation, 0u) * (int64_t)EGO_HIST_BINS;
    return (int32_t)((q + (q >= 0 ? 1 : -1) * ((int64_t)1 << 30)) / ((int64_t)1 << 31));
}

void ego_hist_correlation_start(ego_hist_correlation_t *c, fx_bam32_t centre,
                                uint16_t max_shift_bins, uint16_t merge_bins)
{
    memset(c, 0, sizeof *c);
    c->merge_bins = merge_bins;
    c->limit =
        (int32_t)((max_shift_bins < EGO_HIST_BINS / 2u) ? max_shift_bins : EGO_HIST_BINS / 2u - 1u);
    c->mid = bins_of(centre);
    c->next = c->mid - c->limit;
}

bool ego_hist_correlation_step(ego_hist_correlation_t *c, const ego_hist_t *current,
                               const ego_hist_t *last, uint32_t shifts)
{
    if (c->done) {
        return true;
    }
    const scaled_t a = scale(current);
    const scaled_t b = scale(last);
    runs_t a_runs;
    find_runs(&a, &a_runs);
    if (!c->started) {
        const int64_t na = dot_shifted(&a, &a_runs, &a, 0);
        const int64_t nb = dot_shifted(&b, NULL, &b, 0);
        if (na == 0 || nb == 0) {
            c->done = true; /* a flat histogram has no direction */
            return true;
        }
        c->den = (int64_t)fx_sqrt_u64((uint64_t)na) * (int64_t)fx_sqrt_u64((uint64_t)nb);
        c->before = dot_shifted(&a, &a_runs, &b, c->mid - c->limit - 1);
        c->here = dot_shifted(&a, &a_runs, &b, c->mid - c->limit);
        c->started = true;
    }
    for (uint32_t n = 0u; n < shifts && c->next <= c->mid + c->limit; n++) {
        const int32_t j = c->next;
        const int64_t after = dot_shifted(&a, &a_runs, &b, j + 1);
        if (c->here > c->before && c->here >= after) {
            const peak_t p = {j, c->here, c->before, after};
            keep_peak(c->peaks, &c->npeaks, &p);
        }
        c->before = c->here;
        c->here = after;
        c->next++;
    }
    c->done = c->next > c->mid + c->limit;
    return c->done;
}

uint32_t ego_hist_correlation_products(const ego_hist_t *current)
{
    const scaled_t a = scale(current);
    runs_t r;
    find_runs(&a, &r);
    if (r.dense) {
        return (r.scattered > 0u) ? 2u * r.scattered : EGO_HIST_BINS;
    }
    uint32_t products = 0u;
    for (uint8_t k = 0u; k < r.count; k++) {
        products += r.run[k].length + RUN_OVERHEAD_PRODUCTS;
    }
    return products;
}

/* Fine bins per coarse bin of the turn guess (1 deg). */
#define GUESS_GROUP 5u
#define GUESS_BINS (EGO_HIST_BINS / GUESS_GROUP)
_Static_assert(EGO_HIST_BINS % GUESS_GROUP == 0u, "whole coarse bins");

/* A coarse peak's rotation: the parabola's offset is in coarse bins,
 * scaled to fine ones. */
static fx_bam32_t coarse_rotation(const peak_t *p)
{
    const int64_t shift_bam = ((int64_t)p->shift * ((int64_t)1 << 31)) / (int64_t)EGO_HIST_BINS;
    const int64_t coarse_offset = fx_bam32_diff(peak_rotation(p), 0u) - shift_bam;
    return (fx_bam32_t)(uint64_t)(shift_bam + coarse_offset * (int64_t)GUESS_GROUP);
}

/* The candidates of sorted peaks: best first, a peak within merge_bins of
 * a better one kept dropped; coarse: 1-deg peaks (coarse_rotation). */
static void take_candidates(const peak_t *peaks, uint8_t count, int64_t den, uint16_t merge_bins,
                            bool coarse, ego_hist_match_t *match)
{
    int32_t kept[EGO_HIST_MAX_CANDIDATES] = {0};
    for (uint8_t k = 0u; k < count && match->count < EGO_HIST_MAX_CANDIDATES; k++) {
        bool near = false;
        for (uint8_t m = 0u; m < match->count; m++) {
            const int32_t gap = peaks[k].shift - kept[m];
            near = near || (gap <= (int32_t)merge_bins && gap >= -(int32_t)merge_bins);
        }
        if (near) {
            continue;
        }
        kept[match->count] = peaks[k].shift;
        ego_hist_candidate_t *cand = &match->candidate[match->count++];
        cand->rotation = coarse ? coarse_rotation(&peaks[k]) : peak_rotation(&peaks[k]);
        cand->correlation = ratio_q30(peaks[k].value, den);
    }
}

void ego_hist_correlation_result(const ego_hist_correlation_t *c, ego_hist_match_t *match)
{
    memset(match, 0, sizeof *match);
    if (!c->started) {
        return;
    }
    take_candidates(c->peaks, c->npeaks, c->den, c->merge_bins, false, match);
}

uint32_t ego_hist_correlation_shifts(const ego_hist_correlation_t *c)
{
    return (uint32_t)(2 * c->limit + 1);
}

void ego_hist_correlate(const ego_hist_t *current, const ego_hist_t *last, fx_bam32_t centre,
                    uint16_t max_shift_bins, uint16_t merge_bins, ego_hist_match_t *match)
{
    ego_hist_correlation_t c;
    ego_hist_correlation_start(&c, centre, max_shift_bins, merge_bins);
    (void)ego_hist_correlation_step(&c, current, last, UINT32_MAX);
    ego_hist_correlation_result(&c, match);
}


/* A histogram in 1-deg bins from fine bin `from` on (wrapping), scaled
 * right by `shift` and left by `up`; the largest sum before scaling. */
static uint64_t coarse_bins(const ego_hist_t *h, uint32_t from, unsigned shift, unsigned up,
                            uint16_t *out)
{
    uint64_t top = 0u;
    uint32_t j = from;
    for (uint16_t c = 0u; c < GUESS_BINS; c++) {
        uint64_t sum = 0u;
        for (uint16_t k = 0u; k < GUESS_GROUP; k++) {
            sum += h->bin[j];
            j = (j + 1u < EGO_HIST_BINS) ? j + 1u : 0u;
        }
        top = (sum > top) ? sum : top;
        if (out != NULL) {
            const uint64_t v = (sum >> shift) << up;
            out[c] = (uint16_t)((v > 0xFFFFu) ? 0xFFFFu : v);
        }
    }
    return top;
}

/* A histogram in 1-deg bins from fine bin `from` on (coarse_bins), in 16
 * bits: scaled down to fit, and small counts scaled up too (the norms'
 * square roots round); its squared norm. False when it is empty. */
static bool coarse_scaled(const ego_hist_t *h, uint32_t from, uint16_t *out, uint64_t *norm_sq)
{
    const uint64_t top = coarse_bins(h, from, 0u, 0u, NULL);
    if (top == 0u) {
        return false;
    }
    unsigned down = 0u;
    while ((top >> down) > 0xFFFFu) {
        down++;
    }
    unsigned up = 0u;
    while ((top << (up + 1u)) <= 0xFFFFu) {
        up++;
    }
    (void)coarse_bins(h, from, down, up, out);
    *norm_sq = 0u;
    for (uint16_t c = 0u; c < GUESS_BINS; c++) {
        *norm_sq += (uint32_t)out[c] * out[c];
    }
    return true;
}

/* The coarse correlation's local maxima within +-max_shift_coarse degrees
 * of centre, largest first (at most PEAKS_MAX): each peak's shift in fine
 * bins, its dot product and its neighbours' (a maximum: at least its left
 * neighbour, above its right one), and den, the product of the two
 * histograms' coarse norms; 0 peaks when a histogram is empty. */
static uint8_t coarse_peaks(const ego_hist_t *current, const ego_hist_t *last, fx_bam32_t centre,
                            uint16_t max_shift_coarse, peak_t *peaks, int64_t *den)
{
    const int32_t mid = bins_of(centre);
    /* Both histograms in 1-deg bins, 16 bits: the current one from bin 0,
     * the last one from the centre's place within a coarse bin, so that
     * every shift tried (mid + s GUESS_GROUP) is a whole number of coarse
     * bins. */
    const uint32_t phase = (uint32_t)(((mid % (int32_t)GUESS_GROUP) + (int32_t)GUESS_GROUP) %
                                      (int32_t)GUESS_GROUP);
    uint16_t a[GUESS_BINS];
    uint16_t b[GUESS_BINS];
    uint64_t na = 0u;
    uint64_t nb = 0u;
    if (!coarse_scaled(current, 0u, a, &na) || !coarse_scaled(last, phase, b, &nb)) {
        return 0u;
    }
    *den = (int64_t)fx_sqrt_u64(na) * (int64_t)fx_sqrt_u64(nb);
    const int32_t base = (mid - (int32_t)phase) / (int32_t)GUESS_GROUP; /* exact */
    const int32_t limit = (max_shift_coarse < GUESS_BINS / 2u) ? (int32_t)max_shift_coarse
                                                                : (int32_t)(GUESS_BINS / 2u - 1u);
    /* dot(s) = sum_c a[c] b[c + base + s]: current bin i meets last bin
     * i + shift, the correlation's convention. */
    uint8_t count = 0u;
    uint64_t prev = 0u;
    uint64_t here = 0u;
    for (int32_t s = -limit - 1; s <= limit + 1; s++) {
        const int32_t start = base + s;
        const uint32_t j = (uint32_t)(((start % (int32_t)GUESS_BINS) + (int32_t)GUESS_BINS) %
                                      (int32_t)GUESS_BINS);
        /* In two runs, so that no product tests for the wrap. */
        uint64_t dot = 0u;
        const uint32_t split = GUESS_BINS - j;
        for (uint32_t c = 0u; c < split; c++) {
            dot += (uint32_t)a[c] * b[j + c];
        }
        for (uint32_t c = split; c < GUESS_BINS; c++) {
            dot += (uint32_t)a[c] * b[c - split];
        }
        /* s - 1 is a maximum within the range. */
        if (s - 1 >= -limit && s - 1 <= limit && here >= prev && here > dot) {
            const peak_t p = {mid + (s - 1) * (int32_t)GUESS_GROUP, (int64_t)here, (int64_t)prev,
                              (int64_t)dot};
            keep_peak(peaks, &count, &p);
        }
        prev = here;
        here = dot;
    }
    return count;
}

bool ego_hist_turn_guess(const ego_hist_t *current, const ego_hist_t *last, fx_bam32_t centre,
                         uint16_t max_shift_coarse, fx_bam32_t *turn)
{
    peak_t peaks[PEAKS_MAX];
    int64_t den = 0;
    if (coarse_peaks(current, last, centre, max_shift_coarse, peaks, &den) == 0u) {
        return false;
    }
    *turn = coarse_rotation(&peaks[0]);
    return true;
}

void ego_hist_coarse_match(const ego_hist_t *current, const ego_hist_t *last, fx_bam32_t centre,
                           uint16_t max_shift_coarse, uint16_t merge_bins, ego_hist_match_t *match)
{
    memset(match, 0, sizeof *match);
    peak_t peaks[PEAKS_MAX];
    int64_t den = 0;
    const uint8_t count = coarse_peaks(current, last, centre, max_shift_coarse, peaks, &den);
    take_candidates(peaks, count, den, merge_bins, true, match);
}
