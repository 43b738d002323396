/* ego_hist.h - angle histograms of a prepared scan and their circular
 * cross-correlation: the initial rotation between two scans (paper
 * section 4, eqs. 5-7).
 *
 * A histogram has EGO_HIST_BINS bins over 180 degrees (directions are lines,
 * modulo 180 deg): bin b covers [b, b + 1) * 180 / EGO_HIST_BINS deg. Four ways
 * to fill it, all kept because the paper compares them:
 *
 *  EGO_HIST_AH     each linked, non-occlusion segment P[i] P[i+1] votes 1 for
 *              its direction;
 *  EGO_HIST_LAH    the same, voting the segment length (mm), so near objects
 *              do not dominate by point count;
 *  EGO_HIST_HAH    Hough angle histogram: point i votes every direction alpha
 *              for which its 2n + 1 neighbours lie within t_line of the
 *              line through P[i] along alpha (eqs. 6, 7); with an
 *              angle-of-interest mask, only the masked bins are tried;
 *  EGO_HIST_HTAH   the paper's method: the same test, but started at point i's
 *              robust tangent and stepped up and down one bin at a time
 *              while it passes (the votes are contiguous), so it stops
 *              early.
 *
 * Collinearity test (eq. 7) for direction alpha: d_j = y_j cos(alpha) -
 * x_j sin(alpha) (signed distance of P[j] from the line through the origin
 * along alpha) for j = i - n .. i + n, all in i's segment; it passes when
 * every |d_j - d'| <= t_line with d' = (d[i-n] + d[i+n]) / 2. The
 * direction tested for a bin is the bin's centre.
 *
 * Correlation (eq. 5): c(j) = sum_i (hc(i) - mc)(hl(i + j) - ml) /
 * sqrt(sum (hc - mc)^2 sum (hl - ml)^2), indices modulo EGO_HIST_BINS, for
 * shifts |j| <= max_shift_bins. The rotation theta of the current scan into
 * the last one (R(theta) P + T = P') shifts a direction by +theta, so the
 * argmax j gives theta = j * bin width, refined between bins by a parabola
 * through the peak and its neighbours. Rotation is found modulo 180 deg.
 *
 * Fixed point: votes are uint32; before the correlation both histograms
 * are scaled down to at most 2^15 per bin, so every product sum fits int64
 * (see docs/fixed-point.md). Correlation values are Q2.30 in [-1, 1].
 * Bounded: AH/LAH O(N), HTAH O(N * (2n + 1) * run length), HAH
 * O(N * (2n + 1) * EGO_HIST_BINS), correlation O(EGO_HIST_BINS * (2 max_shift + 1)).
 */
#ifndef EGO_HIST_H
#define EGO_HIST_H

#include <stdbool.h>
#include <stdint.h>

#include "ego_scan.h"
#include "ego_fx.h"

/* Bins over 180 degrees: 900 gives the paper's 0.2 deg. */
#ifndef EGO_HIST_BINS
#define EGO_HIST_BINS 900u
#endif

/* Rotation candidates kept from the correlation. */
#ifndef EGO_HIST_MAX_CANDIDATES
#define EGO_HIST_MAX_CANDIDATES 3u
#endif

_Static_assert(EGO_HIST_BINS >= 36u && EGO_HIST_BINS <= 4096u, "between 5 and 0.044 deg per bin");

typedef enum {
    EGO_HIST_AH = 0,
    EGO_HIST_LAH = 1,
    EGO_HIST_HAH = 2,
    EGO_HIST_HTAH = 3
} ego_hist_kind_t;

typedef struct {
    ego_hist_kind_t kind;
    uint8_t half_window;     /* n of the collinearity test; default 3 */
    fx_q16_16_t t_line;      /* half-width of the band, m; default 0.05 */
    const uint8_t *aoi;      /* HAH only: EGO_HIST_BINS flags (nonzero = try this
                                bin), or NULL for every bin */
} ego_hist_params_t;

void ego_hist_defaults(ego_hist_params_t *params);

typedef struct {
    uint32_t bin[EGO_HIST_BINS];
} ego_hist_t;

/* Fills h from scan (HTAH needs tfit's tangents). Returns the number of
 * votes cast (for LAH, the number of segments). */
uint32_t ego_hist_build(const ego_scan_t *scan, const ego_hist_params_t *params, ego_hist_t *h);

/* Adds the votes of points first .. end - 1 to h (ego_hist_build is a
 * cleared h and every point): the work of a few points at a time, for a
 * caller that spreads a histogram over a budget (ego.c). Returns the
 * votes cast. */
uint32_t ego_hist_vote(const ego_scan_t *scan, const ego_hist_params_t *params, uint16_t first,
                       uint16_t end, ego_hist_t *h);

/* Angle-of-interest mask from a histogram: bins whose count is at least
 * threshold, widened by `widen` bins on each side (circularly). */
void ego_hist_aoi_mask(const ego_hist_t *h, uint32_t threshold, uint16_t widen, uint8_t *mask);

/* Direction of the centre of bin b (mod 180 deg, bit 31 clear). */
fx_bam32_t ego_hist_bin_centre(uint16_t b);

/* Bin of a direction (taken mod 180 deg). */
uint16_t ego_hist_bin_of(fx_bam32_t direction);

/* The main direction of a scan: the centre of its largest bin. */
fx_bam32_t ego_hist_main_direction(const ego_hist_t *h);

typedef struct {
    fx_bam32_t rotation;       /* theta, current -> last, within 90 deg of the
                                  centre asked for, as a binary angle */
    fx_q2_30_t correlation;    /* c at the peak, Q2.30 in [-1, 1] */
} ego_hist_candidate_t;

typedef struct {
    uint8_t count;             /* candidates found (0 when a histogram is flat) */
    ego_hist_candidate_t candidate[EGO_HIST_MAX_CANDIDATES]; /* best first */
} ego_hist_match_t;

/* Correlates current against last for shifts within max_shift_bins (at
 * most EGO_HIST_BINS / 2) of centre (an expected rotation: a prior's, or 0) and
 * returns up to EGO_HIST_MAX_CANDIDATES local maxima, best first, peaks closer
 * than merge_bins to a better one dropped. Line directions repeat every
 * 180 deg, so a candidate is the rotation nearest the centre among its
 * 180-deg alternatives. */
void ego_hist_correlate(const ego_hist_t *current, const ego_hist_t *last, fx_bam32_t centre,
                    uint16_t max_shift_bins, uint16_t merge_bins, ego_hist_match_t *match);

/* The same correlation in steps, for a caller with a work budget: start,
 * then steps of at most `shifts` shifts each until one returns true, then
 * the result (ego_hist_correlate is all three at once). A step costs a
 * setup of a few passes over the bins plus, per shift, the products of
 * ego_hist_correlation_products. The histograms must not
 * change between steps. */
#define EGO_HIST_PEAKS_MAX 16u

typedef struct {
    int32_t shift;
    int64_t value;
    int64_t left;
    int64_t right;
} ego_hist_peak_t;

typedef struct {
    /* Private. */
    uint16_t merge_bins;
    bool started;
    bool done;
    int32_t mid;
    int32_t limit;
    int32_t next;
    int64_t before;
    int64_t here;
    int64_t den;
    uint8_t npeaks;
    ego_hist_peak_t peaks[EGO_HIST_PEAKS_MAX];
} ego_hist_correlation_t;

void ego_hist_correlation_start(ego_hist_correlation_t *c, fx_bam32_t centre,
                                uint16_t max_shift_bins, uint16_t merge_bins);
bool ego_hist_correlation_step(ego_hist_correlation_t *c, const ego_hist_t *current,
                               const ego_hist_t *last, uint32_t shifts);
void ego_hist_correlation_result(const ego_hist_correlation_t *c, ego_hist_match_t *match);
/* The work of one shift of a correlation against `current`, in products
 * (EGO_COST_CORRELATE_PRODUCT each): the bins the correlation multiplies,
 * which depend on how the histogram's filled bins lie, plus their runs'
 * own work. */
uint32_t ego_hist_correlation_products(const ego_hist_t *current);
/* A quick guess of the turn between two scans for tracking's retry: the
 * shift within +-max_shift_coarse degrees of centre that best aligns the
 * current histogram with the last one (current bin i with last bin i +
 * shift, as the correlation), on 1-deg bins, the peak refined by a
 * parabola. The uncentred dot product: for circular shifts its maximum is
 * the correlation's. Its work: four passes over the fine bins, then
 * EGO_COST_COARSE_SHIFT per shift (1 deg) tried, 2 max_shift_coarse + 3
 * shifts. False when a histogram is empty or no shift inside the range is
 * a maximum. */
bool ego_hist_turn_guess(const ego_hist_t *current, const ego_hist_t *last, fx_bam32_t centre,
                         uint16_t max_shift_coarse, fx_bam32_t *turn);
/* The same 1-deg correlation as rotation candidates, as ego_hist_correlate
 * gives them (up to EGO_HIST_MAX_CANDIDATES, best first, merge_bins in fine
 * bins; the correlation normalised by the 1-deg histograms' norms), for a
 * fifth of the resolution and a few percent of the work (the light search:
 * ego.c). */
void ego_hist_coarse_match(const ego_hist_t *current, const ego_hist_t *last, fx_bam32_t centre,
                           uint16_t max_shift_coarse, uint16_t merge_bins, ego_hist_match_t *match);
/* Shifts in all (2 max_shift_bins + 1, capped). */
uint32_t ego_hist_correlation_shifts(const ego_hist_correlation_t *c);

#endif /* EGO_HIST_H */
