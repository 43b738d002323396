/* ego_work.h - the estimator's work meter: a hard, counted budget per scan.
 *
 * Every stage of the estimator charges the work it does in units, before
 * doing it, and a stage that could overrun the limit does not start (it
 * waits for the next scan's budget, ego.h). The units are counted, not
 * timed: the same input gives the same count on the host and the target,
 * so the output stays bit-identical. One unit stands for about one
 * Cortex-M3 instruction: each cost below bounds what the step measured
 * under QEMU on Cortex-M3 and M4F with about 8 % to spare (docs/estimator.md,
 * "The work budget"; ctest target_budget_<stream> checks it), so a scan
 * never takes more instructions than the units it was allowed.
 */
#ifndef EGO_WORK_H
#define EGO_WORK_H

#include <stdbool.h>
#include <stdint.h>

/* No limit: the offline mode (`lmsego replay --budget none`). */
#define EGO_WORK_UNLIMITED UINT64_MAX

typedef struct {
    uint64_t used;  /* units spent this scan */
    uint64_t limit; /* units allowed this scan */
} ego_work_t;

/* Costs in units (about Cortex-M3 instructions), upper bounds per step. */
#define EGO_COST_PREP_BEAM 360u          /* ego_scan_prepare, per beam kept ... */
#define EGO_COST_BEAM_SKIPPED 20u        /* ... and per beam passed over */
#define EGO_COST_DESKEW_POINT 440u       /* de-skewing a kept beam (a sincos, six
                                            products and divisions, its bearing's
                                            arctangent, up to 8 moves back into
                                            bearing order, its links again: a root
                                            and the link tests; the hardest scan of
                                            target_budget_highway_361_cm_mirror
                                            took 274 instructions a point more than
                                            120 units paid) */
#define EGO_COST_TFIT_PLAIN 1600u        /* one plain tangent fit (one point) */
#define EGO_COST_TFIT_CHORD 300u         /* one chord tangent (one point: a chord of 0.2 m
                                            over up to 4 neighbours a side) */
#define EGO_COST_TFIT_ROBUST 6500u       /* one robust tangent fit (plain + 2 passes) */
#define EGO_COST_AH_POINT 185u           /* the AH histogram, per point */
#define EGO_COST_HTAH_POINT 1800u        /* HTAH, per point with a window ... */
#define EGO_COST_HTAH_VOTE 70u           /* ... plus per vote cast */
#define EGO_COST_HIST_MAIN 12000u       /* a histogram's fullest bin: a pass over its
                                            1 800 bins */
#define EGO_COST_CORRELATE_PRODUCT 16u   /* histogram correlation, per bin product */
#define EGO_COST_COARSE_SHIFT 4200u      /* a 1-deg correlation shift: 180 products (the
                                            turn guess measured 3.7 k instructions a
                                            shift with a wrap test per product) */
#define EGO_COST_MATCH_POINT 720u        /* ITCP / coarse probe: one point located */
#define EGO_COST_MATCH_STEP 31u          /* ... plus per scan point walked past */
#define EGO_COST_MATCH_SEGMENT 460u      /* ... plus per segment distance computed */
#define EGO_COST_TRACK_POINT 440u        /* tracking (ego_track.c): one point matched ... */
#define EGO_COST_TRACK_FIT 90u          /* ... plus per segment tried ... */
#define EGO_COST_TRACK_NORMAL 300u       /* ... plus per square root taken (a segment's normal,
                                            once a run; a free-space test) */
#define EGO_COST_TRACK_PROBE 220u        /* a coarse probe along the bearing, beyond its walk,
                                            segments and roots (ego_track_probe) */
#define EGO_COST_PROJECT_POINT 70u      /* ego_project.c, per point and direction ... */
#define EGO_COST_PROJECT_BIN 8u          /* ... per histogram bin and direction ... */
#define EGO_COST_PROJECT_PRODUCT 14u     /* ... per filled bin and shift ... */
#define EGO_COST_PROJECT_CELL 280u       /* ... and per window cell ranked */
#define EGO_COST_SOLVE 2400u             /* one closed-form solution (eq. 12) */
#define EGO_COST_COVARIANCE 6000u        /* a finished registration's covariance
                                            (ego_cov.h: four 3x3 products, nine
                                            64-bit divisions) */
#define EGO_COST_SCAN 30000u             /* per scan: bookkeeping, choosing, the output */

/* The most one located point can cost: its walk on both sides. */
#define EGO_COST_MATCH_POINT_MAX(walk) \
    (EGO_COST_MATCH_POINT + 2u * (uint32_t)(walk) * (EGO_COST_MATCH_STEP + EGO_COST_MATCH_SEGMENT))

static inline void ego_work_start(ego_work_t *w, uint64_t limit)
{
    w->used = 0u;
    w->limit = limit;
}

static inline uint64_t ego_work_left(const ego_work_t *w)
{
    return w->limit - w->used;
}

/* Is there room for `units` more (without spending them). */
static inline bool ego_work_allows(const ego_work_t *w, uint32_t units)
{
    return units <= w->limit - w->used;
}

/* Spends `units`; the caller checked ego_work_allows for at least as many
 * before the step. Saturates at the limit (an unlimited meter never
 * reaches it: 2^64 units). */
static inline void ego_work_spend(ego_work_t *w, uint32_t units)
{
    const uint64_t left = w->limit - w->used;
    w->used += (units < left) ? units : left;
}

#endif /* EGO_WORK_H */
