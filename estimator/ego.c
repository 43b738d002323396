/* ego.c - see ego.h. */
#include "ego.h"

#include <stddef.h>
#include <string.h>

#if defined(EGO_PROFILE)
#define STAGE(s) ego_profile_stage((s), state->work.used)
#else
#define STAGE(s) ((void)0)
#endif

/* round(2 pi * 2^16): radians in Q16.16 per 2^32 binary angle units. */
#define RAD_Q16_PER_TURN 411775
#define US_PER_S 1000000

void ego_defaults(ego_params_t *params)
{
    memset(params, 0, sizeof *params);
    ego_prep_defaults(&params->prep);
    ego_tfit_defaults(&params->tfit);
    ego_hist_defaults(&params->hist);
    ego_track_defaults(&params->track);
    ego_coarse_defaults(&params->coarse);
    params->coarse_window_first = FX_Q16_16_C(4.0);
    params->coarse_window_wide = FX_Q16_16_C(1.6);
    params->accept_fraction = (fx_q2_30_t)(FX_Q2_30_ONE / 10 * 6);
    params->stop_fraction = (fx_q2_30_t)(FX_Q2_30_ONE / 10 * 8);
    params->max_rotation_bins = (uint16_t)(EGO_HIST_BINS / 4u); /* 45 deg */
    params->merge_bins = (uint16_t)(EGO_HIST_BINS / 60u);       /* 3 deg */
    params->min_correlation = (fx_q2_30_t)(FX_Q2_30_ONE / 10 * 3);
    params->min_points = 20u;
    params->trust_translation = FX_Q16_16_C(0.10);
    params->trust_rotation = FX_BAM32_DEG_C(3.0);
    params->prior_margin = (fx_q2_30_t)(FX_Q2_30_ONE / 10);
    params->sweep_steps = 7u;
    params->sweep_step = FX_BAM32_DEG_C(6.0);
    /* Unbounded until the budgeted path keeps the accuracy (issue 15,
     * docs/estimator.md "The work budget"): ego_budget_defaults sets it. */
    params->work_per_s = 0u;
    params->work_min = EGO_DEFAULT_WORK_MIN;
    params->max_search_scans = 30u;
}

void ego_budget_defaults(ego_params_t *params)
{
    params->work_per_s = EGO_DEFAULT_WORK_PER_S;
    params->work_min = EGO_DEFAULT_WORK_MIN;
}

/* All of it: a field left over (the objects test's hysteresis, the tight
 * scans, the weak direction, the dynamics check's reference) changed the
 * lines after a reset (fuzz finding E5). 23.9 KB on the Cortex-M builds,
 * written only on a reset. */
void ego_reset(ego_state_t *state)
{
    memset(state, 0, sizeof *state);
}

/* Does the last motion say anything about an interval of dt_us: it is
 * known and dt_us is at most MAX_PREDICTION_RATIO times its own interval
 * (beyond that, constant velocity is a guess: the vehicle may have
 * stopped, and a scaled-up motion would centre every search far off). */
#define MAX_PREDICTION_RATIO 32u

static bool motion_known(const ego_state_t *state, uint32_t dt_us)
{
    return state->motion_dt_us != 0u &&
           (uint64_t)dt_us <= (uint64_t)MAX_PREDICTION_RATIO * state->motion_dt_us;
}

/* A motion over dt_us scaled to an interval of to_us (dt_us > 0). */
static ego_pose_t scale_motion(const ego_pose_t *motion, uint32_t dt_us, uint32_t to_us)
{
    ego_pose_t p = {0u, 0, 0};
    const int64_t num = to_us;
    const int64_t den = (dt_us > 0u) ? dt_us : 1;
    p.x = fx_sat_s32((int64_t)motion->x * num / den);
    p.y = fx_sat_s32((int64_t)motion->y * num / den);
    p.theta = (fx_bam32_t)(uint32_t)fx_sat_s32(
        (int64_t)fx_bam32_diff(motion->theta, 0u) * num / den);
    return p;
}

/* The last motion scaled to a scan interval of dt_us (no motion when it
 * says nothing about it). */
static ego_pose_t predict(const ego_state_t *state, uint32_t dt_us)
{
    if (!motion_known(state, dt_us)) {
        const ego_pose_t none = {0u, 0, 0};
        return none;
    }
    return scale_motion(&state->motion, state->motion_dt_us, dt_us);
}

/* |a - b| of two headings, binary angle (at most half a turn). */
static int64_t turn_between(fx_bam32_t a, fx_bam32_t b)
{
    const int64_t d = fx_bam32_diff(a, b);
    return (d < 0) ? -d : d;
}

/* |a - b| of two Q16.16 coordinates: up to 2^32 - 1. */
static uint64_t gap_between(fx_q16_16_t a, fx_q16_16_t b)
{
    const int64_t d = (int64_t)a - b;
    return (uint64_t)((d < 0) ? -d : d);
}

/* Is the estimate within trust of the prediction over `horizon` of the
 * prediction's own intervals: the trust distance times the horizon (a
 * speed that changes goes on changing over each), the trust turn. The
 * distance is capped at 2^31 (32 768 m) and each axis tested alone first,
 * so that the squares fit: poses saturate at the ends of Q16.16, and two
 * such gaps squared overflowed int64 (E7 in docs/robustness.md). */
#define TRUST_DISTANCE_CAP ((uint64_t)1u << 31)

static bool close_over(const ego_pose_t *estimate, const ego_pose_t *predicted,
                       const ego_params_t *params, uint32_t horizon)
{
    const uint64_t dx = gap_between(estimate->x, predicted->x);
    const uint64_t dy = gap_between(estimate->y, predicted->y);
    const int64_t trust = params->trust_translation;
    uint64_t r = (uint64_t)((trust < 0) ? -trust : trust) * horizon;
    r = (r > TRUST_DISTANCE_CAP) ? TRUST_DISTANCE_CAP : r;
    return dx <= r && dy <= r && dx * dx + dy * dy <= r * r &&
           turn_between(estimate->theta, predicted->theta) <= (int64_t)params->trust_rotation;
}

/* Is the estimate within the prediction's trust of it (one interval). */
static bool close_to(const ego_pose_t *estimate, const ego_pose_t *predicted,
                     const ego_params_t *params)
{
    return close_over(estimate, predicted, params, 1u);
}

/* How many of the last motion's intervals a prediction over dt_us spans,
 * rounded, 1 to MAX_HORIZON (a bridge after a search spans several; a
 * confirmation is over CONFIRM_INTERVAL_US at most anyway). */
#define MAX_HORIZON 4u

static uint32_t horizon_of(const ego_state_t *state, uint32_t dt_us)
{
    const uint64_t own = state->motion_dt_us;
    if (own == 0u) {
        return 1u;
    }
    const uint64_t k = ((uint64_t)dt_us + own / 2u) / own;
    return (k < 1u) ? 1u : (k > MAX_HORIZON) ? MAX_HORIZON : (uint32_t)k;
}

/* out->dt_us > 0: a scan with no interval to the last one starts over
 * (ego_process_with_prior; E6, docs/robustness.md). */
static void set_velocities(ego_output_t *out)
{
    const int64_t dt = out->dt_us;
    out->vx = fx_sat_s32((int64_t)out->pose.x * US_PER_S / dt);
    out->vy = fx_sat_s32((int64_t)out->pose.y * US_PER_S / dt);
    /* theta (2^32 a turn) -> rad/s in Q16.16, in two steps to stay in
     * int64: |theta| * 411775 < 2^50, then * 10^6 / 2^32. */
    const int64_t per_us = (int64_t)fx_bam32_diff(out->pose.theta, 0u) * RAD_Q16_PER_TURN / dt;
    /* Over an interval of microseconds a turn is beyond any rate: saturated
     * before the product leaves int64 (fuzz finding E1, docs/robustness.md). */
    const int64_t limit = INT64_MAX / US_PER_S;
    out->omega = (per_us > limit)    ? INT32_MAX
                 : (per_us < -limit) ? -INT32_MAX
                                     : fx_sat_s32(per_us * US_PER_S / 4294967296LL);
}

/* pose += ((predicted - pose) . d) d, d the unit vector of direction. */
static void keep_prediction_along(ego_pose_t *pose, const ego_pose_t *predicted,
                                  fx_bam32_t direction)
{
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(direction, &s, &c);
    const fx_q16_16_t ex = fx_sub_q16(predicted->x, pose->x);
    const fx_q16_16_t ey = fx_sub_q16(predicted->y, pose->y);
    const fx_q16_16_t along = fx_add_q16(fx_mul_q16_q30(ex, c), fx_mul_q16_q30(ey, s));
    pose->x = fx_add_q16(pose->x, fx_mul_q16_q30(along, c));
    pose->y = fx_add_q16(pose->y, fx_mul_q16_q30(along, s));
}

/* The pose keeps its part across the weak direction and takes the
 * prediction's along it, in the metric of ego_cov_weakest (the turn times
 * the lever). */
static void keep_prediction_on(ego_pose_t *pose, const ego_pose_t *predicted,
                               const ego_weak_t *weak, fx_q16_16_t lever)
{
    const int64_t l = ego_cov_lever(lever);
    const int64_t d[3] = {(int64_t)fx_sub_q16(predicted->x, pose->x),
                          (int64_t)fx_sub_q16(predicted->y, pose->y),
                          fx_rad_q16_of_turn((int32_t)(predicted->theta - pose->theta)) * l / 65536};
    const int64_t along = (d[0] * weak->dir[0] + d[1] * weak->dir[1] + d[2] * weak->dir[2]) / 128;
    pose->x = fx_sat_s32((int64_t)pose->x + along * weak->dir[0] / 128);
    pose->y = fx_sat_s32((int64_t)pose->y + along * weak->dir[1] / 128);
    const int64_t turn_q16 = (along * weak->dir[2] / 128) * 65536 / l;
    pose->theta += (fx_bam32_t)(uint32_t)fx_sat_s32(turn_q16 * FX_BAM_PER_RAD_Q16_X128 / 128);
}

/* Is one group too small to be judged on its own: under a fifth of the
 * points (a few points' fit is noise, not evidence). */
static bool groups_lopsided(const ego_itcp_result_t *r)
{
    const uint32_t p0 = r->group_points[0];
    const uint32_t p1 = r->group_points[1];
    const uint32_t smaller = (p0 < p1) ? p0 : p1;
    return 5u * smaller < p0 + p1;
}

/* The share over all points together. */
static fx_q2_30_t pooled_share(const ego_itcp_result_t *r)
{
    const int64_t p0 = r->group_points[0];
    const int64_t p1 = r->group_points[1];
    if (p0 + p1 == 0) {
        return 0;
    }
    return (fx_q2_30_t)(((int64_t)r->group_fit[0] * p0 + (int64_t)r->group_fit[1] * p1) /
                        (p0 + p1));
}

/* The smaller inlier share of the two groups (main direction, others).
 * Judged per group because in a corridor the walls fit at any position
 * along it: a pose that fits the walls but not the few door frames and end
 * walls is wrong, however many inliers it has. */
static fx_q2_30_t worst_share(const ego_itcp_result_t *r)
{
    if (groups_lopsided(r)) {
        return pooled_share(r);
    }
    const fx_q2_30_t a = r->group_fit[0];
    const fx_q2_30_t b = r->group_fit[1];
    return (a < b) ? a : b;
}

/* Mean inlier share of the two groups: equal weight per group, as in
 * eq. 10. */
static fx_q2_30_t balanced_share(const ego_itcp_result_t *r)
{
    if (groups_lopsided(r)) {
        return pooled_share(r);
    }
    return (fx_q2_30_t)(((int64_t)r->group_fit[0] + r->group_fit[1]) / 2);
}

/* Is a registration good enough to stop looking: converged with at least
 * accept (or, for skipping the other rotation candidates, stop) of each
 * group's points as inliers. */
static bool good_enough(const ego_params_t *params, ego_itcp_status_t st, const ego_itcp_result_t *r,
                        bool to_stop)
{
    const fx_q2_30_t fraction = to_stop ? params->stop_fraction : params->accept_fraction;
    return st == EGO_ITCP_OK && r->converged && worst_share(r) >= fraction;
}

/* Does a registration fit loosely: half the accept share over both groups
 * together. Enough where other evidence backs it (a trusted prediction it
 * confirms), or where the answer is due (the end of a light search, of a
 * full search's budget). */
static bool half_accepted(const ego_params_t *params, const ego_itcp_result_t *r)
{
    return balanced_share(r) >= params->accept_fraction / 2;
}

/* Does a registration's translation rest on objects (ego_cov_on_objects)? */
static bool rests_on_objects(const ego_itcp_result_t *r)
{
    return r->weak.kind == EGO_WEAK_OBJECTS;
}

/* Does the static structure alone measure the motion: a registration of
 * the points not on objects, converged with the accept share, no weak
 * direction. Then it is no corridor either, however few of its matches lie
 * across the main direction (behind a platoon, a side street's corners:
 * the information test says they measure the motion along the street). */
static bool statically_measured(const ego_params_t *params, ego_itcp_status_t st,
                                const ego_itcp_result_t *r)
{
    return good_enough(params, st, r, false) && r->weak.kind == EGO_WEAK_NONE;
}

/* Is a better than b: registered, a balanced inlier share larger by more
 * than margin, then (equal shares, no margin) a smaller residual. */
static bool better(ego_itcp_status_t sa, const ego_itcp_result_t *a, ego_itcp_status_t sb,
                   const ego_itcp_result_t *b, fx_q2_30_t margin)
{
    if (sa != EGO_ITCP_OK) {
        return false;
    }
    if (sb != EGO_ITCP_OK) {
        return true;
    }
    const fx_q2_30_t qa = balanced_share(a);
    const fx_q2_30_t qb = balanced_share(b);
    if (margin > 0 || qa != qb) {
        return (int64_t)qa > (int64_t)qb + margin;
    }
    return a->residual < b->residual;
}

/* Does a tracking result stand: good enough on its own, or, over a short
 * interval, converged where a trusted prediction said with half the
 * inlier share (moving objects and thinned beams leave points unmatched
 * that a wrong pose would not explain either). Over a short interval only:
 * a prediction's error grows with the square of the interval (5 m/s^2 for
 * 0.1 s is 2.5 cm; for the 3 s of a keyframe log, metres). */
#define CONFIRM_INTERVAL_US 100000u

/* The longest interval tracking is tried over: 0.2 s (at 5 m/s^2 a
 * prediction is then still within 10 cm, inside tracking's 0.3 m reach). */
#define TRACK_INTERVAL_US 200000u

static bool tracking_stands(const ego_params_t *params, ego_itcp_status_t st,
                            const ego_itcp_result_t *r, const ego_pose_t *predicted,
                            bool have_prediction, uint32_t dt_us, uint32_t horizon,
                            fx_bam32_t main_direction)
{
    /* Ended by the budget before its iterations did: unconverged, but a
     * pose that moved by millimetres in the last pass. */
    const bool cut = !r->converged && r->iterations < params->track.max_iterations;
    /* Along a corridor the registration cannot tell how far it went (and a
     * car ahead pulls it towards standing still): judged, like its output
     * (output_match), with the prediction's motion along the corridor. */
    ego_pose_t pose = r->pose;
    if (r->aperture) {
        keep_prediction_along(&pose, predicted, main_direction);
    }
    const bool confirmed = have_prediction && dt_us <= CONFIRM_INTERVAL_US &&
                           st == EGO_ITCP_OK && (r->converged || cut) &&
                           close_over(&pose, predicted, params, horizon) &&
                           half_accepted(params, r);
    /* Cut by the budget after its steps brought each group's share to the
     * accept share: as good as converged, whatever the prediction said (a
     * turn's onset tracked from the turned start; flagged not converged). */
    const bool fits_cut = cut && st == EGO_ITCP_OK && worst_share(r) >= params->accept_fraction;
    return confirmed || fits_cut || good_enough(params, st, r, false);
}

/* ---- The search (ego.h step 3), in steps within the meter. ---- */

enum {
    SEARCH_TRACKING = 0, /* the tracking the last budget did not finish */
    SEARCH_REFINE,     /* robust tangents and the search's histogram of both scans */
    SEARCH_CORRELATE,  /* the rotation candidates */
    SEARCH_CANDIDATES, /* each candidate: from the prediction, then coarse passes */
    SEARCH_SWEEP,      /* no candidate fits: the rotation sweep */
    SEARCH_STATIC,     /* a best on objects: the static structure's registration */
    SEARCH_DONE
};

/* The light search's levels (se->pass, light_next). */
enum {
    LIGHT_LEVEL_TRACK = 0, /* every rotation candidate tracked from the prediction */
    LIGHT_LEVEL_AROUND,    /* the coarse search around the prediction */
    LIGHT_LEVEL_WIDE       /* the coarse search over the wide window */
};

enum {
    ATTEMPT_COARSE = 0, /* the coarse search from start */
    ATTEMPT_TRACK,      /* the tracking registration */
    ATTEMPT_DONE
};

/* Work of the correlation: per shift, the products of the current
 * histogram's filled bins (an upper bound of ego_hist_correlate's), and
 * the peaks. */
#define COST_CORRELATE_BIN 90u

/* Under a budget the coarse search scores this many points per pose. */
#define LIGHT_SAMPLE_POINTS 24u

static uint8_t other_slot(uint8_t slot)
{
    return (uint8_t)(1u - slot);
}

/* An attempt: [the coarse search from start, then] the tracking
 * registration from its best. The coarse search scores along the bearing
 * with the tracking run's cached normals; the run is free until the coarse
 * search ends. */
static void attempt_begin(ego_state_t *state, const ego_params_t *params,
                          const ego_pose_t *start, bool with_coarse, const ego_coarse_params_t *cp)
{
    ego_search_t *se = &state->search;
    const ego_scan_t *last = &state->slot[state->last];
    const ego_scan_t *cur = &state->slot[other_slot(state->last)];
    se->start = *start;
    se->with_coarse = with_coarse;
    se->static_only = false;
    if (with_coarse) {
        se->cp = *cp;
        ego_coarse_start(&se->coarse, last, cur, se->main_direction, start, &se->cp);
        ego_coarse_along_bearing(&se->coarse, &state->tracking, &params->track);
        if (!se->light || se->pass == LIGHT_LEVEL_WIDE) {
            /* Windows ranked by projections first (ego_project.h): the
             * light search's too, over its wide window (a 2.4 m jump is
             * found in 6 scans instead of 12: its 289 cells scored in
             * full took 4 M units), a direction a step. */
            ego_coarse_projected(&se->coarse, &state->projection);
        }
        se->step = ATTEMPT_COARSE;
    } else {
        se->step = ATTEMPT_TRACK;
    }
    se->cursor = 0u; /* the registration is not started yet */
}

static bool attempt_run(ego_state_t *state, const ego_params_t *params)
{
    ego_search_t *se = &state->search;
    const ego_scan_t *last = &state->slot[state->last];
    const ego_scan_t *cur = &state->slot[other_slot(state->last)];
    if (se->step == ATTEMPT_COARSE) {
        STAGE(EGO_STAGE_COARSE);
        if (!ego_coarse_step(&se->coarse, &state->work)) {
            return false;
        }
        uint64_t score = 0u;
        ego_coarse_result(&se->coarse, &se->start, &score);
        se->step = ATTEMPT_TRACK;
    }
    if (se->step == ATTEMPT_TRACK) {
        STAGE(EGO_STAGE_REGISTER);
        if (se->cursor == 0u) {
            ego_track_start(&state->tracking, last, cur, se->main_direction, &se->start, false,
                            &params->track);
            if (se->static_only) {
                ego_track_static_only(&state->tracking);
            }
            se->cursor = 1u;
        }
        if (!ego_track_step(&state->tracking, &state->work)) {
            return false;
        }
        se->attempt_status = ego_track_result(&state->tracking, &se->attempt);
        se->step = ATTEMPT_DONE;
        STAGE(EGO_STAGE_OTHER);
    }
    return true;
}

/* Robust tangents and the search's histogram for one slot, a point at a
 * time; true when done. */
static bool refine_slot(ego_state_t *state, const ego_params_t *params, uint8_t slot)
{
    ego_search_t *se = &state->search;
    ego_scan_t *scan = &state->slot[slot];
    if (state->refined[slot] || se->light) {
        return true; /* under a budget: the chord tangents and AH of the scan */
    }
    const uint16_t n = scan->count;
    const bool rebuild = params->hist.kind != EGO_HIST_AH;
    STAGE(EGO_STAGE_TANGENTS);
    while (se->cursor < n) {
        if (!ego_work_allows(&state->work, EGO_COST_TFIT_ROBUST)) {
            return false;
        }
        ego_work_spend(&state->work, EGO_COST_TFIT_ROBUST);
        ego_tfit_fit_point(scan, &params->tfit, se->cursor);
        se->cursor++;
    }
    STAGE(EGO_STAGE_HISTOGRAM);
    if (rebuild && se->cursor == n) {
        memset(&state->hist[slot], 0, sizeof state->hist[slot]);
    }
    /* A point casts at most one vote per bin. */
    const uint32_t most = EGO_COST_HTAH_POINT + EGO_HIST_BINS * EGO_COST_HTAH_VOTE;
    while (rebuild && se->cursor < 2u * n) {
        if (!ego_work_allows(&state->work, most)) {
            return false;
        }
        const uint16_t i = (uint16_t)(se->cursor - n);
        const uint32_t votes = ego_hist_vote(scan, &params->hist, i, (uint16_t)(i + 1u),
                                             &state->hist[slot]);
        ego_work_spend(&state->work, EGO_COST_HTAH_POINT + votes * EGO_COST_HTAH_VOTE);
        se->cursor++;
    }
    if (rebuild) {
        if (!ego_work_allows(&state->work, EGO_COST_HIST_MAIN)) {
            return false;
        }
        ego_work_spend(&state->work, EGO_COST_HIST_MAIN);
        state->main_direction[slot] = ego_hist_main_direction(&state->hist[slot]);
    }
    STAGE(EGO_STAGE_OTHER);
    state->refined[slot] = true;
    se->cursor = 0u;
    return true;
}

/* The candidates from the correlation's peaks hm: the prior's rotation
 * first; under a budget a trusted prediction's too (the histogram of a
 * thinned scan is coarse); the predicted rotation when the histogram is
 * not trustworthy. */
static void take_rotations(ego_search_t *se, const ego_params_t *params, const ego_hist_match_t *hm)
{
    uint8_t n = 0u;
    const bool prediction_first = se->have_prior || (se->light && se->have_prediction);
    if (prediction_first) {
        se->rotation[n] = se->predicted.theta;
        se->correlation[n] = (hm->count > 0u) ? hm->candidate[0].correlation : 0;
        n++;
    }
    for (uint8_t k = 0u; k < hm->count; k++) {
        se->rotation[n] = hm->candidate[k].rotation;
        se->correlation[n] = hm->candidate[k].correlation;
        n++;
    }
    if (hm->count == 0u || hm->candidate[0].correlation < params->min_correlation) {
        se->flags |= EGO_FLAG_LOW_CORRELATION;
        if (!prediction_first) {
            se->rotation[n] = se->predicted.theta;
            se->correlation[n] = (hm->count > 0u) ? hm->candidate[0].correlation : 0;
            n++;
        }
    }
    se->n = n;
}

/* The work of a 1-deg correlation over +-degrees (ego_hist.h): four
 * passes over the fine bins, then its shifts. */
static uint32_t coarse_match_cost(uint32_t degrees)
{
    return EGO_HIST_BINS * COST_CORRELATE_BIN / 2u + (2u * degrees + 3u) * EGO_COST_COARSE_SHIFT;
}

/* Fine bins each side of a 1-deg peak that refine it (1 deg). */
#define REFINE_BINS 5u

/* Under a budget: the AH histograms correlated at 1 deg over the whole
 * range (ego_hist_coarse_match), then each peak at 0.2 deg within 1 deg of
 * it (ego_hist_correlate), one peak a step; cursor: the next candidate. A
 * few percent of the work of the 0.2-deg correlation over the range (on a
 * 361-value scan up to six sensor-rate budgets: its products), for the
 * same peaks where they are a degree or more apart. */
static bool correlate_light(ego_state_t *state, const ego_params_t *params)
{
    ego_search_t *se = &state->search;
    const ego_hist_t *current = &state->hist[other_slot(state->last)];
    const ego_hist_t *last = &state->hist[state->last];
    if (se->cursor == 0u) {
        const uint32_t degrees = (uint32_t)params->max_rotation_bins * 180u / EGO_HIST_BINS;
        const uint32_t cost = coarse_match_cost(degrees);
        if (!ego_work_allows(&state->work, cost)) {
            return false;
        }
        STAGE(EGO_STAGE_CORRELATE);
        ego_work_spend(&state->work, cost);
        ego_hist_match_t hm;
        ego_hist_coarse_match(current, last, se->have_prior ? se->predicted.theta : 0u,
                              (uint16_t)degrees, params->merge_bins, &hm);
        STAGE(EGO_STAGE_OTHER);
        take_rotations(se, params, &hm);
        se->cursor = 1u;
    }
    const uint32_t per_shift =
        (ego_hist_correlation_products(current) + 8u) * EGO_COST_CORRELATE_PRODUCT;
    /* Its setup, its shifts, and the four dots that start it (two norms,
     * the two shifts before the first). */
    const uint32_t refine =
        EGO_HIST_BINS * COST_CORRELATE_BIN + (2u * REFINE_BINS + 1u + 4u) * per_shift;
    for (; se->cursor <= se->n; se->cursor++) {
        const uint8_t k = (uint8_t)(se->cursor - 1u);
        if (se->rotation[k] == se->predicted.theta) {
            continue; /* the prediction's own candidate is no peak */
        }
        if (!ego_work_allows(&state->work, refine)) {
            return false;
        }
        STAGE(EGO_STAGE_CORRELATE);
        ego_work_spend(&state->work, refine);
        ego_hist_match_t fine;
        ego_hist_correlate(current, last, se->rotation[k], REFINE_BINS, params->merge_bins, &fine);
        STAGE(EGO_STAGE_OTHER);
        if (fine.count > 0u) {
            se->rotation[k] = fine.candidate[0].rotation;
            se->correlation[k] = fine.candidate[0].correlation;
        }
    }
    se->cursor = 0u;
    se->main_direction = state->main_direction[state->last];
    return true;
}

/* The rotation candidates: the prior's rotation, the histogram's peaks,
 * and the predicted rotation when the histogram is not trustworthy. The
 * full search correlates the HTAH histograms at 0.2 deg, a chunk of shifts
 * at a time; the light one the AH histograms at 1 deg, at once (a fifth of
 * a sensor-rate budget instead of up to six budgets on a 361-value scan:
 * its registrations refine the rotation anyway). */
static bool correlate(ego_state_t *state, const ego_params_t *params)
{
    ego_search_t *se = &state->search;
    const uint8_t cur = other_slot(state->last);
    if (se->light) {
        return correlate_light(state, params);
    }
    const fx_bam32_t expected = se->have_prior ? se->predicted.theta : 0u;
    ego_hist_match_t hm;
    if (se->cursor == 0u) {
        ego_hist_correlation_start(&se->correlation_run, expected, params->max_rotation_bins,
                                   params->merge_bins);
        se->cursor = 1u;
    }
    /* Per shift: its products, and the shift's own work. */
    const uint32_t per_shift =
        (ego_hist_correlation_products(&state->hist[cur]) + 8u) * EGO_COST_CORRELATE_PRODUCT;
    const uint32_t setup = EGO_HIST_BINS * COST_CORRELATE_BIN;
    STAGE(EGO_STAGE_CORRELATE);
    for (;;) {
        if (!ego_work_allows(&state->work, setup + per_shift)) {
            STAGE(EGO_STAGE_OTHER);
            return false;
        }
        const uint64_t left = ego_work_left(&state->work) - setup;
        const uint32_t shifts = (left / per_shift > UINT32_MAX) ? UINT32_MAX
                                                                : (uint32_t)(left / per_shift);
        const uint32_t all = ego_hist_correlation_shifts(&se->correlation_run);
        const uint32_t now = (shifts < all) ? shifts : all;
        ego_work_spend(&state->work, setup + now * per_shift);
        if (ego_hist_correlation_step(&se->correlation_run, &state->hist[cur],
                                      &state->hist[state->last], now)) {
            break;
        }
    }
    STAGE(EGO_STAGE_OTHER);
    se->cursor = 0u;
    ego_hist_correlation_result(&se->correlation_run, &hm);
    take_rotations(se, params, &hm);
    se->main_direction = state->main_direction[state->last];
    return true;
}

/* The coarse search of pass 0 (around the prediction) or 1 (the wide
 * window, or the first window when no motion is known). */
static ego_coarse_params_t coarse_pass(const ego_search_t *se, const ego_params_t *params,
                                       uint8_t pass)
{
    ego_coarse_params_t cp = params->coarse;
    const bool first = pass == 1u && !se->known_motion;
    if (pass == 1u) {
        cp.window = first ? params->coarse_window_first : params->coarse_window_wide;
    }
    if (se->light) {
        /* Under a budget: the candidate's rotation only, a lean sample,
         * steps twice as coarse (the tracking registration after it
         * converges from 0.3 m), four times over the first window. */
        cp.rotation_steps = 0u;
        cp.sample_points = LIGHT_SAMPLE_POINTS;
        cp.step = (first ? 4 : 2) * cp.step;
        cp.fine_step = 2 * cp.fine_step;
    } else if (first) {
        cp.step = 2 * cp.step; /* 4 m in EGO_PROJECT_MAX_SIDE steps */
    }
    return cp;
}

static void candidate_begin(ego_state_t *state, const ego_params_t *params)
{
    ego_search_t *se = &state->search;
    const ego_pose_t start = {se->rotation[se->k], se->predicted.x, se->predicted.y};
    attempt_begin(state, params, &start, false, NULL);
}

/* Under a budget: does a registration after a coarse pass confirm a
 * trusted prediction (converged within its trust distance)? The coarse
 * search around the prediction found nothing better nearby, and the
 * prediction is itself evidence: the answer, even when a group's share is
 * low (part of the scene changed). */
static bool confirms_prediction(const ego_params_t *params, const ego_search_t *se,
                                const ego_itcp_result_t *r)
{
    return se->have_prediction && r->converged && close_to(&r->pose, &se->predicted, params);
}

/* After a candidate's attempt: the next coarse pass (around the
 * prediction, then over the wide window), or the verdict on it. */
static void candidate_next(ego_state_t *state, const ego_params_t *params)
{
    ego_search_t *se = &state->search;
    if (!se->with_coarse) {
        se->candidate = se->attempt;
        se->candidate_status = se->attempt_status;
        /* Around a prior only its small window (pass 0); otherwise the
         * wide (or first) window at once: ranked by projections, it holds
         * the small one for little more work (the real logs' answers are
         * the same without the small pass, for a sixth less work). */
        se->pass = (uint8_t)(se->have_prior ? 0u : 1u);
        se->pass_end = (uint8_t)(se->have_prior ? 1u : 2u);
    } else {
        if (better(se->attempt_status, &se->attempt, se->candidate_status, &se->candidate, 0)) {
            se->candidate = se->attempt;
            se->candidate_status = se->attempt_status;
        }
        se->pass++;
    }
    if (se->pass < se->pass_end &&
        !good_enough(params, se->candidate_status, &se->candidate, false)) {
        const ego_pose_t start = {se->rotation[se->k], se->predicted.x, se->predicted.y};
        const ego_coarse_params_t cp = coarse_pass(se, params, se->pass);
        attempt_begin(state, params, &start, true, &cp);
        return;
    }
    se->tried++;
    /* Another rotation replaces the prior's only if clearly better. */
    const bool against_prior = se->have_prior && se->best_k == 0u && se->best_status == EGO_ITCP_OK;
    if (better(se->candidate_status, &se->candidate, se->best_status, &se->best,
               against_prior ? params->prior_margin : 0)) {
        se->best = se->candidate;
        se->best_status = se->candidate_status;
        se->best_k = se->k;
    }
    se->k++;
    if (se->k < se->n && !good_enough(params, se->best_status, &se->best, true)) {
        candidate_begin(state, params);
        return;
    }
    se->stage = SEARCH_SWEEP;
    se->step = ATTEMPT_DONE;
}

/* Under a budget the answer is due: the attempts go breadth first,
 * cheapest first, and the first good enough (or, after a coarse pass,
 * confirming a trusted prediction) ends the search. Level 0: every
 * rotation candidate tracked from the predicted translation; level 1 (with
 * a prediction): the coarse search around it, for the first candidate;
 * level 2: the wide window, for the first LIGHT_WIDE candidates. A coarse
 * pass that lands back on the best so far also ends it. */
#define LIGHT_WIDE 2u

static uint8_t light_width(const ego_search_t *se)
{
    if (se->pass == LIGHT_LEVEL_TRACK) {
        return se->n;
    }
    const uint8_t wide = (se->pass == LIGHT_LEVEL_AROUND) ? 1u : (uint8_t)LIGHT_WIDE;
    return (se->n < wide) ? se->n : wide;
}

/* The rotation candidate of attempt k of the level: in the wide window the
 * histogram's best first (a jump the prediction missed is what it is
 * for), then the prediction's. */
static uint8_t light_candidate(const ego_search_t *se)
{
    const bool swap = se->pass == LIGHT_LEVEL_WIDE && se->n > 1u && se->k < 2u &&
                      (se->have_prior || se->have_prediction);
    return swap ? (uint8_t)(1u - se->k) : se->k;
}

static void light_next(ego_state_t *state, const ego_params_t *params)
{
    ego_search_t *se = &state->search;
    se->tried++;
    /* A coarse pass that lands back on the best registration so far (both
     * converged, within the prediction's trust distance of each other):
     * two independent starts agree. Not along a corridor, where every
     * start stays where it began along it. */
    const bool agrees = se->with_coarse && se->best_status == EGO_ITCP_OK &&
                        se->attempt_status == EGO_ITCP_OK && !se->attempt.aperture &&
                        se->best.converged &&
                        se->attempt.converged && close_to(&se->attempt.pose, &se->best.pose, params);
    if (better(se->attempt_status, &se->attempt, se->best_status, &se->best, 0)) {
        se->best = se->attempt;
        se->best_status = se->attempt_status;
        se->best_k = light_candidate(se);
    }
    /* After a coarse pass, a best with the accept share over both groups
     * is enough: more candidates cost scans. Not a best that rests on
     * objects: behind a platoon at our speed the trucks' "standing still"
     * fits well, and the street's motion is among the next candidates. */
    const bool done = !rests_on_objects(&se->best) &&
                      (good_enough(params, se->best_status, &se->best, false) || agrees ||
                       (se->with_coarse && (confirms_prediction(params, se, &se->best) ||
                                            balanced_share(&se->best) >= params->accept_fraction)));
    se->k++;
    if (!done && se->k >= light_width(se)) {
        se->k = 0u;
        se->pass++;
        if (se->pass == LIGHT_LEVEL_AROUND && !se->have_prediction) {
            se->pass++; /* nothing to search around */
        }
    }
    if (done || se->pass > LIGHT_LEVEL_WIDE || se->k >= se->n) {
        se->stage = SEARCH_SWEEP;
        se->step = ATTEMPT_DONE;
        return;
    }
    if (se->pass == LIGHT_LEVEL_TRACK) {
        candidate_begin(state, params);
        return;
    }
    const ego_pose_t start = {se->rotation[light_candidate(se)], se->predicted.x,
                              se->predicted.y};
    const ego_coarse_params_t cp = coarse_pass(se, params, (uint8_t)(se->pass - 1u));
    attempt_begin(state, params, &start, true, &cp);
}

/* Does the best candidate fit well enough that the rotation sweep is not
 * worth its work: converged, with two thirds of the accept share over both
 * groups. The sweep is for histogram candidates that are all wrong, and a
 * wrong rotation seldom fits that well. Measured on the real logs
 * (docs/estimator.md): skipping the sweep there costs aces 4 of 439 pairs
 * and intel none, and cuts aces's median search from 85 M to 23 M units,
 * where a noisy log's candidates seldom reach the accept share. */
static bool fits_some(const ego_params_t *params, const ego_search_t *se)
{
    return se->best_status == EGO_ITCP_OK && se->best.converged &&
           balanced_share(&se->best) >= params->accept_fraction / 3 * 2;
}

/* The static structure's own registration from start (SEARCH_STATIC). */
static void static_attempt_begin(ego_state_t *state, const ego_params_t *params,
                                 const ego_pose_t *start)
{
    attempt_begin(state, params, start, false, NULL);
    state->search.static_only = true;
    state->search.stage = SEARCH_STATIC;
}

/* Works on the search until it is done (true) or the meter runs dry. */
static bool search_run(ego_state_t *state, const ego_params_t *params)
{
    ego_search_t *se = &state->search;
    for (;;) {
        switch (se->stage) {
        case SEARCH_TRACKING: {
            STAGE(EGO_STAGE_REGISTER);
            const bool done = ego_track_step(&state->tracking, &state->work);
            STAGE(EGO_STAGE_OTHER);
            if (!done) {
                return false;
            }
            ego_itcp_result_t r;
            const ego_itcp_status_t st = ego_track_result(&state->tracking, &r);
            const fx_bam32_t main_direction = state->main_direction[state->last];
            if (tracking_stands(params, st, &r, &se->track_predicted, se->have_prediction,
                                se->dt_us, horizon_of(state, se->dt_us), main_direction)) {
                se->best = r;
                se->best_status = st;
                se->stage_tracked = true;
                se->main_direction = main_direction;
                se->stage = SEARCH_DONE;
            } else if (st == EGO_ITCP_OK && rests_on_objects(&r)) {
                /* Pulled onto objects: the static structure's own
                 * registration from the prediction first (SEARCH_STATIC
                 * goes on to the search where it does not measure). */
                se->main_direction = main_direction;
                static_attempt_begin(state, params, &se->track_predicted);
            } else {
                se->stage = SEARCH_REFINE;
            }
            break;
        }
        case SEARCH_REFINE:
            if (!refine_slot(state, params, state->last) ||
                !refine_slot(state, params, other_slot(state->last))) {
                return false;
            }
            se->stage = SEARCH_CORRELATE;
            break;
        case SEARCH_CORRELATE:
            if (!correlate(state, params)) {
                return false;
            }
            se->stage = SEARCH_CANDIDATES;
            se->k = 0u;
            candidate_begin(state, params);
            break;
        case SEARCH_CANDIDATES:
            if (!attempt_run(state, params)) {
                return false;
            }
            if (se->light) {
                light_next(state, params);
            } else {
                candidate_next(state, params);
            }
            break;
        case SEARCH_SWEEP:
            /* Last resort, without a prior: no candidate fits. The
             * histogram's peaks can all be wrong where few walls are seen
             * (its correlation is broad and has one maximum); sweep the
             * rotation instead, coarse to fine: every sweep_step first,
             * then, if nothing fits yet, the rotations halfway between
             * (a budget that ends in between has the first's answer). */
            if (se->step == ATTEMPT_DONE) {
                /* The finer sweep only where the meter still holds what
                 * the coarse one took (in this scan: one that ran on
                 * cannot be repeated now). */
                const bool afford = se->sweeps == 0u ||
                                    (se->sweep_scans == se->scans &&
                                     ego_work_left(&state->work) >= state->work.used - se->sweep_mark);
                if (se->light || se->have_prior || params->sweep_steps == 0u || se->sweeps >= 2u ||
                    !afford || good_enough(params, se->best_status, &se->best, false) ||
                    fits_some(params, se)) {
                    if (se->best_status == EGO_ITCP_OK && rests_on_objects(&se->best)) {
                        static_attempt_begin(state, params, &se->best.pose);
                    } else {
                        se->stage = SEARCH_DONE;
                    }
                    break;
                }
                se->sweep_mark = state->work.used;
                se->sweep_scans = se->scans;
                ego_coarse_params_t cp = coarse_pass(se, params, 1u); /* the wide window */
                cp.rotation_steps = params->sweep_steps;
                cp.rotation_step = params->sweep_step;
                ego_pose_t centre = se->predicted;
                centre.theta += (se->sweeps == 0u) ? 0u : params->sweep_step / 2u;
                se->sweeps++;
                attempt_begin(state, params, &centre, true, &cp);
            }
            if (!attempt_run(state, params)) {
                return false;
            }
            se->tried++;
            if (better(se->attempt_status, &se->attempt, se->best_status, &se->best, 0)) {
                se->best = se->attempt;
                se->best_status = se->attempt_status;
                se->best_k = se->n; /* no histogram candidate */
                se->correlation[se->n] = 0;
            }
            break; /* the other half, or done */
        case SEARCH_STATIC:
            if (!attempt_run(state, params)) {
                return false;
            }
            if (statically_measured(params, se->attempt_status, &se->attempt)) {
                se->best = se->attempt;
                se->best_status = se->attempt_status;
                se->best.aperture = false; /* (statically_measured) */
                se->best_static = true;
            }
            /* Before any candidate (from SEARCH_TRACKING), the search
             * proper, unless the static registration answered. */
            se->stage = (se->best_static || se->tried > 0u) ? SEARCH_DONE : SEARCH_REFINE;
            se->cursor = 0u;
            break;
        default:
            return true;
        }
    }
}

static void search_begin(ego_state_t *state, uint32_t time_us, uint32_t dt,
                         const ego_pose_t *predicted, bool have_prior, bool have_prediction,
                         bool light)
{
    /* After a search that found nothing the motion may be anything: the
     * first window again (around the prediction), not the narrow one. */
    const bool known_motion = motion_known(state, dt) && !state->lost;
    ego_search_t *se = &state->search;
    memset(se, 0, sizeof *se);
    se->active = true;
    se->stage = SEARCH_REFINE;
    se->time_us = time_us;
    se->dt_us = dt;
    se->predicted = *predicted;
    se->have_prior = have_prior;
    se->have_prediction = have_prediction;
    se->known_motion = known_motion;
    se->best_status = EGO_ITCP_ERR_FEW_MATCHES;
    se->light = light;
}

/* ---- The output. ---- */

/* The output of a registration r (status st) from the prediction. */
static bool output_match(const ego_params_t *params, ego_itcp_status_t st,
                         const ego_itcp_result_t *r, bool have_prediction,
                         const ego_pose_t *predicted, fx_bam32_t main_direction,
                         fx_q16_16_t lever, ego_output_t *out)
{
    if (st != EGO_ITCP_OK) {
        return false;
    }
    out->pose = r->pose;
    out->cov = r->cov;
    out->iterations = r->iterations;
    out->matches = r->matches;
    out->n_main = r->n_main;
    out->n_non_main = r->n_non_main;
    out->inliers = r->inliers;
    out->residual = r->residual;
    if (r->aperture) {
        /* Along a corridor the scans cannot tell how far the vehicle
         * went: keep the measured motion across the main direction and
         * take the predicted one along it, if there is a prediction worth
         * the name: one the measured turn agrees with (a turn the
         * prediction missed by more than its trust says it missed the
         * rest too; else the match's own guess, flagged either way). */
        out->flags |= EGO_FLAG_APERTURE;
        if (have_prediction &&
            turn_between(r->pose.theta, predicted->theta) <= (int64_t)params->trust_rotation) {
            keep_prediction_along(&out->pose, predicted, main_direction);
        }
        /* Either way the length is not measured: its variance says so. */
        fx_q2_30_t s;
        fx_q2_30_t c;
        fx_sincos(main_direction, &s, &c);
        ego_cov_unmeasured_along(&out->cov, c, s);
    }
    out->flags |= r->converged ? 0u : EGO_FLAG_NOT_CONVERGED;
    /* A prediction over a short interval is a motion; over a keyframe's
     * seconds it is a guess that the measurement beats even where it is
     * weak (taking it cost the aces log 1.8 % more failed pairs). */
    const bool predicts = have_prediction && out->dt_us <= TRACK_INTERVAL_US;
    if (r->weak.kind == EGO_WEAK_TRANSLATION || r->weak.kind == EGO_WEAK_COUPLED) {
        /* A direction the matches barely see: the prediction's motion
         * along it, if there is one (flagged and unmeasured either way). */
        out->flags |= (r->weak.kind == EGO_WEAK_TRANSLATION) ? EGO_FLAG_WEAK_TRANSLATION
                                                             : EGO_FLAG_WEAK_COUPLED;
        if (predicts) {
            keep_prediction_on(&out->pose, predicted, &r->weak, lever);
        }
        ego_cov_unmeasured_direction(&out->cov, &r->weak, lever);
    }
    if (r->weak.kind == EGO_WEAK_OBJECTS) {
        /* Measured on what may be moving (a platoon of trucks at our speed
         * says we stand still): the motion as found, its translation's
         * trust withdrawn (both axes: ego_cov_on_objects). */
        out->flags |= EGO_FLAG_ON_OBJECTS;
        ego_cov_unmeasured_along(&out->cov, FX_Q2_30_ONE, 0);
        ego_cov_unmeasured_along(&out->cov, 0, FX_Q2_30_ONE);
    }
    if (r->weak_rotation || r->weak.kind == EGO_WEAK_ROTATION) {
        /* Every surface faces the scanner (the spacing test: the
         * prediction's turn at any interval) or the eigen test found the
         * turn weak (over a short one): the turn is the prediction's
         * (flagged and unmeasured either way). */
        out->flags |= EGO_FLAG_WEAK_ROTATION;
        if (r->weak_rotation ? have_prediction : predicts) {
            out->pose.theta = predicted->theta;
        }
        ego_cov_unmeasured_rotation(&out->cov);
    }
    return true;
}

/* The dynamics check (EGO_FLAG_SUSPECT): a constant-velocity filter of
 * the translation's velocity, fed the measured lines that pass it. Its
 * velocity drifts by DRIFT_ACCELERATION a second at one sigma (the limit
 * EGO_MAX_ACCELERATION at three); a line whose velocity is beyond the
 * gate of the filter's and its own variance is suspect, and so are the
 * next ones until one is within the gate again (which widens with the
 * time since the filter's last line). A vague line (cars in the match
 * window) moves the filter by its small weight only: a slide onto cars
 * moving with the vehicle, each line within reach of the last, shows
 * against the filter. The turn is not judged: a path's curvature may jump
 * (a synthetic world's arcs; a robot spinning up), and a turn no scan
 * supports shows in the weak-rotation test. */
#define DRIFT_ACCELERATION (EGO_MAX_ACCELERATION / 3) /* Q16 m/s^2 */
/* Innovation e beyond the gate: |e|^2 > 6.9 (P + R), the 99.9 % of
 * chi^2 with two degrees of freedom (13.8) over the two axes that share
 * the variances' sums P and R. */
#define GATE_X10 69u
/* Intervals (keyframes) and references older than this are not judged
 * by: 1.5 g over a second is already 15 m/s. */
#define DYNAMICS_MAX_DT_US 1000000u
/* Variances above this (Q16 (m/s)^2, 65536 (m/s)^2) are not measured. */
#define VAR_UNKNOWN UINT32_MAX

static uint64_t variance_of(fx_q2_30_t v)
{
    return (v > 0) ? (uint64_t)v : 0u;
}

/* The variance of the line's velocity, x and y together, Q16 (m/s)^2;
 * VAR_UNKNOWN where it saturated or the translation was not measured. */
static uint32_t velocity_variance(const ego_output_t *out)
{
    if (out->cov.xx == EGO_COV_SATURATED || out->cov.yy == EGO_COV_SATURATED) {
        return VAR_UNKNOWN;
    }
    const uint64_t dt = out->dt_us;                                    /* > 0 */
    const uint64_t var = variance_of(out->cov.xx) + variance_of(out->cov.yy); /* Q30 m^2, < 2^33 */
    const uint64_t per_s = var * US_PER_S / dt;                        /* < 2^53 */
    if (per_s >= ((uint64_t)1 << 43)) {
        return VAR_UNKNOWN;
    }
    const uint64_t q16 = (per_s * US_PER_S / dt) >> 14;
    return (q16 < VAR_UNKNOWN) ? (uint32_t)q16 : VAR_UNKNOWN;
}

/* The filter's variance grown by its drift over span_us (Q16 (m/s)^2). */
static uint64_t drifted_variance(const ego_velocity_ref_t *ref, uint32_t span_us)
{
    const uint64_t drift = (uint64_t)DRIFT_ACCELERATION * span_us / US_PER_S; /* Q16 m/s */
    return (uint64_t)ref->var + ((drift * drift) >> 16);
}

/* Judges a matched line's translation against the filter and feeds it
 * in when it passes. A line whose translation is partly the prediction's
 * (aperture, weak) says nothing either way; one that rests on objects is
 * judged, its covariance wide along them (a vague line moves the filter
 * little). */
static void judge_dynamics(ego_state_t *state, bool matched, uint32_t time_us, ego_output_t *out)
{
    const uint16_t unmeasured = EGO_FLAG_APERTURE | EGO_FLAG_WEAK_TRANSLATION | EGO_FLAG_WEAK_COUPLED;
    const uint32_t r = velocity_variance(out);
    ego_velocity_ref_t *ref = &state->reference;
    const uint32_t span = time_us - ref->time_us;
    if (state->have_reference && span > DYNAMICS_MAX_DT_US) {
        state->have_reference = false;
        state->suspect = false;
    }
    if (!matched || out->dt_us == 0u || out->dt_us > DYNAMICS_MAX_DT_US ||
        (out->flags & unmeasured) != 0u || r == VAR_UNKNOWN) {
        out->flags |= state->suspect ? EGO_FLAG_SUSPECT : 0u;
        return;
    }
    /* Each square below 2^62, their sum below 2^63. */
    const uint64_t speed_sq = (uint64_t)((int64_t)out->vx * out->vx) +
                              (uint64_t)((int64_t)out->vy * out->vy);
    if (speed_sq > (uint64_t)EGO_MAX_SPEED * EGO_MAX_SPEED) {
        out->flags |= EGO_FLAG_SUSPECT; /* no vehicle's: not taken in */
        return;
    }
    if (!state->have_reference) {
        ref->vx = out->vx;
        ref->vy = out->vy;
        ref->var = r;
        ref->time_us = time_us;
        state->have_reference = true;
        return;
    }
    const uint64_t p = drifted_variance(ref, span);
    const uint64_t total = p + r; /* below 2^33 */
    const int64_t ex = fx_sat_s32((int64_t)out->vx - ref->vx); /* its square in int64 */
    const int64_t ey = fx_sat_s32((int64_t)out->vy - ref->vy);
    const uint64_t e_sq = ((uint64_t)(ex * ex) >> 16) + ((uint64_t)(ey * ey) >> 16); /* Q16 */
    state->suspect = e_sq * 10u > GATE_X10 * total;
    if (!state->suspect) {
        /* The inverse-variance mean of the filter and the line. */
        const int64_t gain = (total == 0u) ? 0 : (int64_t)((p << 16) / total); /* Q16, <= 1 */
        ref->vx = fx_sat_s32(ref->vx + ((ex * gain) >> 16));
        ref->vy = fx_sat_s32(ref->vy + ((ey * gain) >> 16));
        const uint64_t share = (total == 0u) ? 0u : ((uint64_t)r << 16) / total; /* Q16 */
        ref->var = (uint32_t)((p * share) >> 16); /* p r / (p + r) <= r */
        ref->time_us = time_us;
    }
    out->flags |= state->suspect ? EGO_FLAG_SUSPECT : 0u;
}

/* Standing still, or creeping: the last scan kept stays the reference
 * (the scan held) while the tracked motion from it stays small, and each
 * line is the difference of two registrations against it (issue 17).
 * Scan to scan, a car creeping off (0.4 m/s: 5 mm a scan at 75 Hz) stays
 * within the match's reach, and range noise does not average out: standing
 * still in stopgo's queue drifted 0.09-0.27 m (2 m at 3 cm of noise);
 * against the scan held, the car moves out of the fit while the static
 * world stays put, and noise does not add up. A hold begins after
 * HOLD_SLOW_LINES slow lines in a row (within HOLD_SPEED: not a vehicle
 * moving on at walking pace, whose reference would lag; fits within
 * HOLD_RESIDUAL: a noisy fit is no reference), goes on while the motion
 * from the scan held is within HOLD_DISTANCE and HOLD_TURN and the next
 * scan is within HOLD_MAX_US of it (the reference stays recent), and ends
 * at any line that is not a plain tracked match (a corridor's, a weak
 * one's: their motion along the weak direction is the prediction's). */
/* 0.75 m/s, not 0.5 (measured, 2026-12-04): behind a platoon at our speed
 * the lines that rest on the trucks say we stand, within 0.5 m/s but for a
 * line (or its prediction) now and then, and each such line started the
 * count of eight again. Held, the reference ages while the street moves
 * past, and the search after its tracking fails finds the street's motion:
 * at 181 values 585 -> 181 failed pairs of 899; stopgo's standstill drift
 * 5 -> 15 mm (181 values), 22 -> 40 mm (361) without noise. */
#define HOLD_SPEED FX_Q16_16_C(0.75)    /* m/s */
#define HOLD_DISTANCE FX_Q16_16_C(0.05) /* m */
#define HOLD_TURN FX_BAM32_DEG_C(0.2)
#define HOLD_MAX_US 1000000u
#define HOLD_SLOW_LINES 8u
/* 3 cm, not 2 (2026-12-04, with HOLD_SPEED 0.75): at 3 cm of range noise
 * the fits' residuals are 2-3 cm and no hold began; standing, the lines
 * added up to 2.06 m (181 values) and 0.41 m (361); held, 0.30 and 0.02 m,
 * 13 pairs unanswered (searches) and 11 more failed, all flagged. */
#define HOLD_RESIDUAL FX_Q16_16_C(0.03)
#define HOLD_ENDS                                                                          \
    (EGO_FLAG_FIRST | EGO_FLAG_TOO_FEW_POINTS | EGO_FLAG_PREDICTED | EGO_FLAG_RECOVERING | \
     EGO_FLAG_RECOVERED | EGO_FLAG_APERTURE | EGO_FLAG_WEAK_ROTATION |                     \
     EGO_FLAG_WEAK_TRANSLATION | EGO_FLAG_WEAK_COUPLED)

static bool holding(const ego_state_t *state)
{
    return state->have_last && state->held_time_us != state->last_time_us;
}

/* Is p within reach of from in x and in y. */
static bool within(const ego_pose_t *p, const ego_pose_t *from, int64_t reach)
{
    const int64_t dx = (int64_t)p->x - from->x;
    const int64_t dy = (int64_t)p->y - from->y;
    return dx <= reach && dx >= -reach && dy <= reach && dy >= -reach;
}

static const ego_pose_t NO_MOTION = {0u, 0, 0};

/* Counts the slow lines in a row (motion from the last scan kept and its
 * prediction within HOLD_SPEED, the fit within HOLD_RESIDUAL, not
 * suspect) that a hold begins after: trackings that stopped short among
 * cars (near-zero lines at 4 m/s) held the reference while the vehicle
 * drove on (the traffic excerpt's scans 70-72: then 0.2 s of zeros), and at
 * 3 cm of range noise the tracking against a held scan failed (searches at
 * a standstill). */
static void count_slow_lines(ego_state_t *state, const ego_pose_t *motion, const ego_output_t *out,
                             const ego_pose_t *predicted, bool had_prediction, uint32_t time_us)
{
    const int64_t slow = (int64_t)HOLD_SPEED * (time_us - state->last_time_us) / US_PER_S;
    const bool slow_line = had_prediction && (out->flags & EGO_FLAG_SUSPECT) == 0u &&
                           out->residual <= HOLD_RESIDUAL && within(motion, &NO_MOTION, slow) &&
                           within(predicted, &NO_MOTION, slow);
    state->slow_lines = !slow_line                 ? 0u
                        : (state->slow_lines < 255u) ? (uint8_t)(state->slow_lines + 1u)
                                                     : 255u;
}

/* Does the scan just matched (motion from the last scan kept, a line
 * flagged flags) hold the last scan kept for the next one? */
static bool holds(const ego_state_t *state, const ego_pose_t *motion, uint16_t flags, bool tracked,
                  uint32_t time_us)
{
    const bool begins = state->slow_lines >= HOLD_SLOW_LINES;
    const uint64_t next_us = (uint64_t)(time_us - state->last_time_us) +
                             (time_us - state->previous_time_us); /* a scan on, as the last */
    return tracked && (flags & HOLD_ENDS) == 0u && (holding(state) || begins) &&
           within(motion, &NO_MOTION, HOLD_DISTANCE) && turn_between(motion->theta, 0u) <= (int64_t)HOLD_TURN &&
           next_us <= HOLD_MAX_US;
}

/* The scan in slot cur becomes the last one, with the motion out->pose
 * (over out->dt_us) from a tracked match, another match (matched) or
 * none. Whether that motion predicts the next one: a tracked motion does;
 * any other when it came out close to its prediction. When a trusted
 * prediction misses once (a jump, a hard scan), the motion before it keeps
 * predicting; twice in a row, the motion has changed. */
static void advance(ego_state_t *state, const ego_params_t *params, uint8_t cur, uint32_t time_us,
                    ego_output_t *out, bool tracked, bool matched,
                    const ego_pose_t *predicted, bool had_prediction)
{
    /* The registration's motion, from the last scan kept; the line is from
     * the last scan processed (a scan held: the difference of the two). */
    const ego_pose_t motion = out->pose;
    const uint32_t motion_dt = out->dt_us;
    if (holding(state)) {
        out->pose = ego_pose_from(&state->held, &motion);
        out->dt_us -= state->held_time_us - state->last_time_us;
        set_velocities(out);
        /* A step over twice the hold's speed: a vehicle that starts off
         * leaves the hold's 5 cm before it reaches that (0.45 m/s at 2
         * m/s^2); a fit that a car creeping off pulled along, letting go,
         * does not. Suspect, as the dynamics check judges a line. */
        const int64_t jump = 2 * (int64_t)HOLD_SPEED;
        if (out->vx > jump || out->vx < -jump || out->vy > jump || out->vy < -jump) {
            out->flags |= EGO_FLAG_SUSPECT;
        }
    }
    judge_dynamics(state, matched, time_us, out);
    const bool close = matched && close_to(&motion, predicted, params);
    if (!matched) {
        /* The line is the prediction: it says nothing new about the
         * motion, and a motion not known stays unknown (taken as a known
         * standstill, it shrank the next search's window from 4 m to
         * 1.6 m: a vehicle moving 3 m a scan was never found again). */
        state->predictable = false;
        state->misses = 0u;
    } else if (tracked && !had_prediction &&
               (out->flags & (EGO_FLAG_APERTURE | EGO_FLAG_RECOVERED)) == EGO_FLAG_APERTURE) {
        /* Along a corridor with nothing to predict the motion along it
         * a tracking's is only its start's (a search's is its window's
         * best): the motion stays unknown (a corridor entered at 3 m a
         * scan from a standstill guess was taken for a standstill, and the
         * exit's search never looked 3 m away). */
        state->motion_dt_us = 0u;
        state->predictable = false;
        state->misses = 0u;
    } else if (!tracked && had_prediction && !close && state->misses == 0u) {
        state->misses = 1u;
    } else {
        state->motion = motion;
        state->motion_dt_us = motion_dt;
        state->predictable = tracked || close;
        state->misses = 0u;
    }
    state->lost = state->lost && !matched;
    state->along_predicted = matched && had_prediction && (out->flags & EGO_FLAG_APERTURE) != 0u;
    state->weak = matched && (out->flags & (EGO_FLAG_WEAK_TRANSLATION | EGO_FLAG_WEAK_COUPLED)) != 0u;
    /* Kept over lines without a match: they tell nothing of what the
     * scene rests on. */
    state->on_objects = matched ? (out->flags & EGO_FLAG_ON_OBJECTS) != 0u : state->on_objects;
    count_slow_lines(state, &motion, out, predicted, had_prediction, time_us);
    if (holds(state, &motion, out->flags, tracked, time_us)) {
        state->held = motion;
        state->held_time_us = time_us;
        return;
    }
    state->last = cur;
    state->last_time_us = time_us;
    state->held_time_us = time_us; /* none held: state->held is not read */
}

/* Shares of the scan's points a search's answer must hold as inliers not
 * to be suspect: half; 0.7 when its turn came from the sweep, not from a
 * histogram's peak. Measured on the real logs' keyframes (docs/
 * estimator.md, "Flags"): most answers below them are wrong minima,
 * few right ones are. */
#define SEARCH_SHARE_PERCENT 50u
#define SWEPT_SHARE_PERCENT 70u

static bool search_doubtful(const ego_search_t *se, const ego_output_t *out, uint16_t points)
{
    const uint32_t percent = (se->correlation[se->best_k] == 0) ? SWEPT_SHARE_PERCENT
                                                                 : SEARCH_SHARE_PERCENT;
    return !se->stage_tracked && 100u * (uint32_t)out->inliers < percent * (uint32_t)points;
}

static void finish_search(ego_state_t *state, const ego_params_t *params, bool recovered,
                          ego_output_t *out)
{
    ego_search_t *se = &state->search;
    out->flags |= se->flags;
    out->candidates = se->tried;
    out->dt_us = se->dt_us;
    /* The light search (under a budget) tries fewer starts: its best
     * answers when it is good enough, confirms a trusted prediction, or
     * has the balanced share tracking needs near a prediction (flagged
     * EGO_FLAG_NOT_CONVERGED when it did not converge). */
    const bool fits = !se->light || se->stage_tracked ||
                      good_enough(params, se->best_status, &se->best, false) ||
                      confirms_prediction(params, se, &se->best) ||
                      half_accepted(params, &se->best);
    const bool matched = fits && output_match(params, se->best_status, &se->best, se->have_prediction,
                                              &se->predicted, se->main_direction,
                                              state->slot[other_slot(state->last)].rms_range, out);
    if (matched) {
        out->correlation = se->correlation[se->best_k];
        out->flags |= search_doubtful(se, out, state->slot[other_slot(state->last)].count)
                          ? EGO_FLAG_SUSPECT
                          : 0u;
    } else {
        out->flags &= (uint16_t)~(EGO_FLAG_APERTURE | EGO_FLAG_NOT_CONVERGED | EGO_FLAG_WEAK_ROTATION |
                                  EGO_FLAG_WEAK_TRANSLATION | EGO_FLAG_WEAK_COUPLED);
        out->flags |= EGO_FLAG_PREDICTED | (fits ? EGO_FLAG_TOO_FEW_POINTS : 0u);
        out->pose = se->predicted;
    }
    if (recovered) {
        out->flags |= EGO_FLAG_RECOVERED;
    }
    state->bridge = recovered && matched;
    state->static_next = matched && se->best_static;
    state->before = state->motion;
    state->before_dt_us = motion_known(state, se->dt_us) ? state->motion_dt_us : 0u;
    out->points = state->slot[other_slot(state->last)].count;
    set_velocities(out);
    se->active = false;
    /* A tracking's answer, or one that spanned scans, predicts the next
     * motion as a tracked one does (the bridge after it tries the motion
     * from before it too). */
    advance(state, params, other_slot(state->last), se->time_us, out,
            se->stage_tracked || recovered, matched, &se->predicted, se->have_prediction);
    state->lost = !matched;
}

static void finish_output(ego_state_t *state, ego_output_t *out, uint32_t time_us)
{
    STAGE(EGO_STAGE_OTHER); /* the scan's last stage ends with it */
    out->work = (state->work.used > UINT32_MAX) ? UINT32_MAX : (uint32_t)state->work.used;
    out->work_limit = (state->work.limit > UINT32_MAX) ? UINT32_MAX : (uint32_t)state->work.limit;
    state->have_previous = true;
    state->previous_time_us = time_us;
}

/* ---- One scan. ---- */

/* The scan's budget: its interval since the previous scan times
 * work_per_s, at least work_min; unlimited without a rate or an interval
 * (the first scan only prepares itself). */
static uint64_t budget(const ego_state_t *state, const ego_params_t *params, uint32_t time_us)
{
    if (params->work_per_s == 0u || !state->have_previous) {
        return EGO_WORK_UNLIMITED;
    }
    const uint64_t interval = time_us - state->previous_time_us;
    const uint64_t scaled = interval * params->work_per_s / US_PER_S;
    return (scaled > params->work_min) ? scaled : params->work_min;
}

/* Does this scan's budget pay for the full search (robust tangents, HTAH,
 * every rotation's window ranked by projections, the sweep: a median of
 * about 20 M units on the real logs' keyframes, up to some hundred
 * million on hard pairs)? Below AMPLE_WORK (0.33 s of scan interval at the
 * default rate) the light one runs: chord tangents, AH, lean coarse passes
 * on the candidate's rotation only. */
#define AMPLE_WORK 10000000u

static bool ample(const ego_state_t *state)
{
    return state->work.limit >= AMPLE_WORK;
}

/* Full passes' worth of points tracking is sized for: its two coarse
 * passes (a quarter and half of the points) and one full pass, which
 * gives the statistics (ego_track.h); a run that could take more ends
 * where the budget does, converged if it had settled. (Sized for three,
 * the points of campus's 361-value scans were thinned to every other beam:
 * 1.38 mm / 0.0032 deg against 1.17 mm / 0.0030 deg now.) */
#define TRACK_PASSES 2u

/* After a tracking run the meter ended before it finished (its points
 * dearer than the typical point, and the scan's de-skewing left too
 * little: a mirror-timed 181-value scan of a busy street), the next
 * TIGHT_SCANS scans (3.3 s at 75 Hz) are sized for a pass more. Measured
 * (2026-12-05, lmsworld --timing lms, default budget, 181 values): traffic
 * 59 -> 2 failed pairs (58 lines had been left unanswered while the
 * search finished the cut runs), stopgo 101 -> 3, crossing 13 -> 2,
 * pedestrians 19 -> 1; 16 scans left traffic 10; sized for three passes
 * always, the instant streams' thinned points cost 3229 -> 3848 failed
 * pairs over the 144-sequence sweep, which this rule leaves as it was. */
#define TIGHT_SCANS 250u

/* The beams with a range among every step-th: the ones that become points
 * (a beam without one is passed over at EGO_COST_BEAM_SKIPPED). */
static uint32_t beams_with_range(const ego_range_scan_t *scan, uint32_t step)
{
    uint32_t valid = 0u;
    for (uint32_t k = 0u; k < scan->count; k += step) {
        valid += (scan->range[k] != 0u) ? 1u : 0u;
    }
    return valid;
}

/* Every how many beams a point is kept so that preparing the points and
 * tracking them fits the scan's budget (1: all; at most 8, ego_scan.h); valid: the
 * beams with a range. */
static uint32_t beams_per_point(const ego_state_t *state, const ego_range_scan_t *scan,
                                uint32_t valid, uint32_t prepare_cost)
{
    /* The scan's bookkeeping (EGO_COST_SCAN) is paid already. */
    const uint64_t left = ego_work_left(&state->work);
    const uint64_t passes = TRACK_PASSES + ((state->tight > 0u) ? 1u : 0u);
    const uint64_t per_point = prepare_cost + passes * EGO_TRACK_TYPICAL_POINT;
    const uint64_t fixed = (uint64_t)scan->count * EGO_COST_BEAM_SKIPPED;
    const uint64_t points = (left > fixed) ? (left - fixed) / per_point : 0u;
    if (points >= valid) {
        return 1u;
    }
    if (points == 0u) {
        return 8u;
    }
    const uint64_t step = (valid + points - 1u) / points;
    return (step > 8u) ? 8u : (uint32_t)step;
}

/* How far the beams kept of one pass (pass 0's) lead the scan's time, the
 * mean of all its beams' (ego_range.h), in 0.1 ms (at most 25.5): (passes
 * - 1) / 2 pass intervals (within a beam's time of the exact mean). */
static uint8_t one_pass_lead(const ego_range_scan_t *scan)
{
    const uint64_t lead = ((uint64_t)(ego_range_passes(scan) - 1u) * scan->pass_us + 100u) / 200u;
    return (uint8_t)((lead < 255u) ? lead : 255u);
}

/* The RMS offset of the scan's beams from its time, 0.1 ms (at most
 * 25.5): passes p pass_us apart, each a sweep of s, taken as independent
 * uniform spreads, (p^2 - 1) / 12 pass intervals and s^2 / 12 squared
 * (intervals within a second: the sums fit 32 bits). */
static uint8_t skew_rms(const ego_range_scan_t *scan)
{
    const uint32_t p = ego_range_passes(scan);
    const uint32_t pass = scan->pass_us / 100u;                           /* 0.1 ms */
    const uint32_t sweep = (scan->count / p) * (scan->beam_ns / 1000u) / 100u; /* 0.1 ms */
    if (p > 16u || pass > 10000u || sweep > 10000u) {
        return 255u;
    }
    const uint32_t rms = fx_sqrt_u64(((uint64_t)pass * pass * (p * p - 1u) + (uint64_t)sweep * sweep) / 12u);
    return (uint8_t)((rms < 255u) ? rms : 255u);
}

/* Prepares the scan into slot cur with its tangents and AH histogram; false (nothing changed) when the budget cannot pay for it. */
static bool prepare(ego_state_t *state, const ego_params_t *params, const ego_range_scan_t *scan,
                    const ego_skew_t *skew, uint8_t cur)
{
    /* Unbounded, a plain fit per point (on noisy real data the chords sort
     * too many points into the wrong group); under a budget, the chords,
     * and only as many beams as the budget lets tracking register. */
    const bool plain = ample(state);
    const uint32_t tangent_cost = plain ? EGO_COST_TFIT_PLAIN : EGO_COST_TFIT_CHORD;
    const bool timed = skew->dt_us != 0u && (scan->beam_ns != 0u || ego_range_passes(scan) > 1u);
    const uint32_t prep_cost = EGO_COST_PREP_BEAM + (timed ? EGO_COST_DESKEW_POINT : 0u);
    const uint32_t per_point = prep_cost + tangent_cost + EGO_COST_AH_POINT;
    ego_prep_params_t prep = params->prep;
    const uint32_t valid = beams_with_range(scan, 1u);
    uint32_t step = 1u;
    if (!plain) {
        step = beams_per_point(state, scan, valid, per_point);
        state->tight = (state->tight > 0u) ? (uint8_t)(state->tight - 1u) : 0u;
    }
    uint8_t lead = 0u;
    if (!timed && ego_range_passes(scan) > 1u) {
        /* No motion to de-skew an interlaced scan with (a cold start):
         * one of its passes, a sweep measured at once, is the scan (at
         * 30 m/s two passes 13.3 ms apart are two images 0.4 m apart). */
        const uint32_t passes = ego_range_passes(scan);
        step = ((step + passes - 1u) / passes) * passes;
        lead = one_pass_lead(scan);
    }
    if (step > 1u && scan->count > 1u) {
        /* Every step-th beam: the preparation thins to that spacing (a
         * one-beam scan has none: a table's beam 1 is past its end). */
        const uint64_t spacing = (ego_range_bearing(scan, 1u) - ego_range_bearing(scan, 0u)) * (uint64_t)step;
        prep.beam_spacing = (spacing > prep.beam_spacing && spacing < FX_BAM32_HALF)
                                ? (fx_bam32_t)spacing
                                : prep.beam_spacing;
    }
    /* Charged per point: beams without a range cost their pass only. */
    const uint32_t kept = (step == 1u) ? valid : beams_with_range(scan, step);
    const uint32_t cost = kept * per_point + (uint32_t)scan->count * EGO_COST_BEAM_SKIPPED +
                          EGO_COST_HIST_MAIN;
    if (!ego_work_allows(&state->work, cost)) {
        return false;
    }
    ego_scan_t *current = &state->slot[cur];
    STAGE(EGO_STAGE_PREPARE);
    ego_work_spend(&state->work, kept * prep_cost + (uint32_t)scan->count * EGO_COST_BEAM_SKIPPED);
    (void)ego_scan_prepare_deskewed(scan, &prep, skew, current);
    STAGE(EGO_STAGE_TANGENTS);
    ego_work_spend(&state->work, kept * tangent_cost);
    if (plain) {
        ego_tfit_params_t fit = params->tfit;
        fit.passes = 0u;
        ego_tfit_fit_scan(current, &fit);
    } else {
        ego_tfit_chord_scan(current);
    }
    STAGE(EGO_STAGE_HISTOGRAM);
    ego_work_spend(&state->work, kept * EGO_COST_AH_POINT + EGO_COST_HIST_MAIN);
    ego_hist_params_t ah = params->hist;
    ah.kind = EGO_HIST_AH;
    (void)ego_hist_build(current, &ah, &state->hist[cur]);
    state->main_direction[cur] = ego_hist_main_direction(&state->hist[cur]);
    STAGE(EGO_STAGE_OTHER);
    state->refined[cur] = false;
    state->lead_100us[cur] = lead;
    state->skew_100us = timed ? skew_rms(scan) : 0u;
    return true;
}

typedef enum { TRACK_FOUND, TRACK_UNFINISHED, TRACK_FAILED } track_outcome_t;

/* What becomes of a start's run that the scan's budget ends: it goes on in
 * the next scan's (the search's first stage), also when it was cut at the
 * end of a coarse pass (the last start), or it is dropped (a trial). */
typedef enum { START_GOES_ON, START_LAST, START_TRIAL, START_NARROW, START_PRIOR } start_kind_t;

/* The first reach of a trusted prediction's first tracking (START_NARROW,
 * a trial): a vehicle's motion changes by centimetres a scan, while a car
 * driving with it moves a third of a metre a scan against the ground, and
 * the usual 0.3 m first reach let such cars pull the fit onto them (a busy
 * road at 3 cm of noise stood still for 3.5 s). */
#define NARROW_RADIUS FX_Q16_16_C(0.1)
/* The first reach of a prediction between scans at most CLOSE_SCANS_US
 * apart (the LMS's 13 and 27 ms): 3 cm. At EGO_MAX_ACCELERATION (1.5 g)
 * a motion changes by a dt^2 = 1.4 cm a scan at most, while a car driving
 * with us at 7.5 m/s is 0.1 m off the prediction: within NARROW_RADIUS,
 * behind the platoon it pulled tracked lines onto the trucks (issue 17).
 * Against a scan held it keeps a car creeping off 3 cm from where the
 * held scan saw it out of the first pass. */
#define CLOSE_REACH FX_Q16_16_C(0.03)
#define CLOSE_SCANS_US 30000u

/* The first reach of a prior's first tracking (START_PRIOR, a trial):
 * odometry's error, up to a tenth of the distance (a wheel slipping, a
 * tyre's radius), twice over, and no less than PRIOR_REACH_MIN. Behind a
 * platoon of trucks at our speed (issue 17) the trucks are a scan's
 * motion off the prior, and standing still fits more points than the
 * street: reached narrowly, the static world is kept apart from them. A
 * prior that needs more than NARROW_RADIUS (over half a metre) is tracked
 * with the usual reach (one 0.6 m short, tracked narrowly first, cost the
 * budget the along start then needed). */
#define PRIOR_REACH_MIN FX_Q16_16_C(0.03)

/* The reach of a prior, or 0 when it needs more than NARROW_RADIUS. */
static fx_q16_16_t prior_reach(const ego_pose_t *prior)
{
    /* Each square below 2^62, their sum below 2^63. */
    const uint64_t sq = (uint64_t)((int64_t)prior->x * prior->x) +
                        (uint64_t)((int64_t)prior->y * prior->y);
    const int64_t reach = (int64_t)fx_sqrt_u64(sq) / 5; /* Q16.16 m */
    return (reach > NARROW_RADIUS)     ? 0
           : (reach < PRIOR_REACH_MIN) ? PRIOR_REACH_MIN
                                       : (fx_q16_16_t)reach;
}

/* The registration an earlier start of the scan converged to, fitting
 * loosely (half the accept share over both groups, not along a corridor). */
typedef struct {
    bool have;
    ego_itcp_result_t r;
} loose_fit_t;

/* Tracking (ego.h step 2). Unfinished when the budget ran out: the search
 * then goes on with it first (a narrow start too: a wide one from the same
 * prediction in its place had no budget left, and behind a platoon it slid
 * onto the trucks when the search finished it). */
static track_outcome_t track(ego_state_t *state, const ego_params_t *params, uint8_t cur,
                             const ego_pose_t *start, const ego_pose_t *predicted,
                             bool have_prediction, uint32_t dt_us, start_kind_t kind,
                             loose_fit_t *loose, ego_output_t *out)
{
    const ego_scan_t *last = &state->slot[state->last];
    const fx_bam32_t main_direction = state->main_direction[state->last];
    STAGE(EGO_STAGE_REGISTER);
    ego_track_start(&state->tracking, last, &state->slot[cur], main_direction, start, true,
                    &params->track);
    /* After a motion that rested on objects its prediction may be the
     * objects' (behind a platoon, standing still): the static structure's
     * own registration, from the whole reach. After one the static
     * structure measured, the same, from the narrow reach. */
    const bool after_objects = state->on_objects && !state->static_next;
    const bool static_run = state->static_next || state->on_objects;
    state->static_next = false;
    if (static_run) {
        ego_track_static_only(&state->tracking);
    }
    if (kind == START_NARROW && !after_objects) {
        ego_track_narrow(&state->tracking,
                         (dt_us <= CLOSE_SCANS_US) ? CLOSE_REACH : NARROW_RADIUS);
    } else if (kind == START_PRIOR) {
        ego_track_narrow(&state->tracking, prior_reach(start));
    }
    if (state->weak) {
        ego_track_hold_weak(&state->tracking);
    }
    if (state->on_objects) {
        ego_track_hold_objects(&state->tracking);
    }
    if (holding(state)) {
        ego_track_wary(&state->tracking);
    }
    const bool done = ego_track_step(&state->tracking, &state->work);
    STAGE(EGO_STAGE_OTHER);
    state->search.track_predicted = *predicted; /* the search is not active */
    if (!done) {
        state->tight = TIGHT_SCANS;
        return (kind == START_TRIAL || kind == START_PRIOR) ? TRACK_FAILED : TRACK_UNFINISHED;
    }
    ego_itcp_result_t r;
    const ego_itcp_status_t st = ego_track_result(&state->tracking, &r);
    if (static_run) {
        state->static_next = statically_measured(params, st, &r);
        if (state->static_next) {
            r.aperture = false; /* (statically_measured) */
        } else if (after_objects && r.weak.kind != EGO_WEAK_ROTATION) {
            /* Still unmeasured without them: flagged on objects, with the
             * registration's own motion, not the prediction's along a
             * corridor (the objects' standstill again), where it stayed
             * within tracking's reach of the prediction. */
            r.aperture = r.aperture && !within(&r.pose, start, params->track.radius_start);
            r.weak.kind = EGO_WEAK_OBJECTS;
        }
    }
    /* Two starts of the scan that converge to one pose, each fitting
     * loosely, agree: the light search's rule for its coarse passes (the
     * second may be cut by the budget on its way back). */
    const bool fits_loosely = st == EGO_ITCP_OK && !r.aperture && half_accepted(params, &r);
    const bool agrees = fits_loosely && loose->have && close_to(&r.pose, &loose->r.pose, params);
    if (agrees) {
        r = loose->r; /* the converged one answers */
    }
    /* Converged, or ended by the budget before its iterations did. */
    const bool settled = r.converged || r.iterations < params->track.max_iterations;
    if (fits_loosely && settled && !loose->have) {
        loose->have = true;
        loose->r = r;
    }
    if (!agrees &&
        !tracking_stands(params, st, &r, predicted, have_prediction, dt_us,
                         horizon_of(state, dt_us), main_direction)) {
        /* The last start, cut before it matched every point, or any start
         * the meter ended on its way to a prediction it fits loosely
         * (without one, the loose fit has its own confirmations below):
         * the next scan's budget finishes it (the search's first stage). */
        const bool goes_on = kind == START_LAST || (kind == START_GOES_ON && have_prediction &&
                                                    st == EGO_ITCP_OK && half_accepted(params, &r));
        return (goes_on && ego_track_resume(&state->tracking)) ? TRACK_UNFINISHED : TRACK_FAILED;
    }
    return output_match(params, st, &r, have_prediction, predicted, main_direction,
                        state->slot[cur].rms_range, out) ? TRACK_FOUND
                                                                                 : TRACK_FAILED;
}

/* A heading change the prediction missed (a turn begins, a bump): the
 * turn that best aligns the two scans' direction histograms within
 * TURN_GUESS_DEG of the prediction (ego_hist_turn_guess, 1-deg bins), as a
 * second start for tracking with the predicted translation; false when it
 * is within ONE_TURN_GUESS of the prediction (tracking started there
 * already) or the meter cannot pay for it. */
#define ONE_TURN_GUESS FX_BAM32_DEG_C(1.0)
#define TURN_GUESS_DEG 15u

static bool turned_start(ego_state_t *state, uint8_t cur, const ego_pose_t *predicted,
                         ego_pose_t *start)
{
    const uint32_t cost = coarse_match_cost(TURN_GUESS_DEG);
    if (!ego_work_allows(&state->work, cost)) {
        return false;
    }
    STAGE(EGO_STAGE_CORRELATE);
    ego_work_spend(&state->work, cost);
    fx_bam32_t turn = 0u;
    const bool found = ego_hist_turn_guess(&state->hist[cur], &state->hist[state->last],
                                           predicted->theta, TURN_GUESS_DEG, &turn);
    STAGE(EGO_STAGE_OTHER);
    if (!found || turn_between(turn, predicted->theta) < (int64_t)ONE_TURN_GUESS) {
        return false;
    }
    *start = *predicted;
    start->theta = turn;
    return true;
}

/* A speed the prediction missed: along a corridor the motion along it is
 * the prediction's, and over the scans a search spanned it is the speed
 * from before; at the exit, or after the search, it can be a fifth or a
 * third off while the heading holds. Without a prediction (the first
 * scans, after a reset) the speed is unknown, and a vehicle moves along
 * its heading (x). The shift along that direction of travel that best
 * aligns the two scans' projections on it (ego_project_along, surfaces
 * facing it only: not the corridor's walls), within half the predicted
 * distance (ALONG_WINDOW_MIN to _MAX; without a prediction, the first
 * window), is a start for tracking (ALONG_SHIFTED; *start either way);
 * ALONG_STILL when the best shift is within ALONG_SAME of `from`
 * (tracking starts there already); ALONG_NONE when the prediction moves too little to have a
 * direction, no surface faces it, or the meter cannot pay for it. */
#define ALONG_MOVE_MIN FX_Q16_16_C(0.3)
#define ALONG_WINDOW_MIN FX_Q16_16_C(0.5)
#define ALONG_WINDOW_MAX FX_Q16_16_C(4.0)
#define ALONG_FINE_MAX FX_Q16_16_C(2.0) /* up to here in bins of 0.1 m, beyond of 0.2 m */
#define ALONG_SAME FX_Q16_16_C(0.15)

typedef enum { ALONG_NONE, ALONG_STILL, ALONG_SHIFTED } along_t;

static along_t along_start(ego_state_t *state, const ego_params_t *params, uint8_t cur,
                           const ego_pose_t *from, bool have_prediction, ego_pose_t *start)
{
    fx_bam32_t direction = 0u;
    fx_q16_16_t window = params->coarse_window_first;
    if (have_prediction) {
        /* Each square below 2^62: their sum fits unsigned. */
        const uint64_t d2 =
            (uint64_t)((int64_t)from->x * from->x) + (uint64_t)((int64_t)from->y * from->y);
        const fx_q16_16_t distance = (fx_q16_16_t)fx_sqrt_u64(d2);
        if (distance < ALONG_MOVE_MIN) {
            return ALONG_NONE;
        }
        direction = fx_atan2(from->y, from->x);
        window = distance / 2;
        window = (window < ALONG_WINDOW_MIN) ? ALONG_WINDOW_MIN : window;
    }
    window = (window > ALONG_WINDOW_MAX) ? ALONG_WINDOW_MAX : window;
    const fx_q16_16_t bin = (window > ALONG_FINE_MAX) ? FX_Q16_16_C(0.2) : FX_Q16_16_C(0.1);
    const ego_scan_t *last = &state->slot[state->last];
    const ego_scan_t *current = &state->slot[cur];
    if (!ego_work_allows(&state->work, ego_project_along_cost_max(last, current, window, bin))) {
        return ALONG_NONE;
    }
    fx_q16_16_t shift = 0;
    uint32_t units = 0u;
    STAGE(EGO_STAGE_COARSE);
    const bool found = ego_project_along(last, current, direction, from, window, bin,
                                         &state->projection, &shift, &units);
    ego_work_spend(&state->work, units);
    STAGE(EGO_STAGE_OTHER);
    if (!found) {
        return ALONG_NONE;
    }
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(direction, &s, &c);
    *start = *from;
    start->x = fx_add_q16(from->x, fx_mul_q16_q30(shift, c));
    start->y = fx_add_q16(from->y, fx_mul_q16_q30(shift, s));
    return (shift < ALONG_SAME && shift > -ALONG_SAME) ? ALONG_STILL : ALONG_SHIFTED;
}

/* Nothing confirms a loose fit without a prediction (a cold start among
 * moving cars, whose group fits poorly) but the along start: the fit lies
 * within ALONG_SAME of its shift along the heading, two measures of the
 * speed that agree. */
static bool along_confirms(along_t first, const ego_pose_t *along, const loose_fit_t *loose)
{
    const fx_q16_16_t apart = fx_sub_q16(loose->r.pose.x, along->x);
    return first != ALONG_NONE && loose->have && apart < ALONG_SAME && apart > -ALONG_SAME;
}

/* The loose fit answers when the along start confirms it (its motion along
 * the heading then measured: *from_along). */
static track_outcome_t answer_if_along_confirms(const ego_state_t *state,
                                                const ego_params_t *params,
                                                const ego_pose_t *predicted, along_t first,
                                                const ego_pose_t *along, const loose_fit_t *loose,
                                                bool *from_along, ego_output_t *out)
{
    if (!along_confirms(first, along, loose) ||
        !output_match(params, EGO_ITCP_OK, &loose->r, false, predicted,
                      state->main_direction[state->last],
                      state->slot[other_slot(state->last)].rms_range, out)) {
        return TRACK_FAILED;
    }
    *from_along = true;
    return TRACK_FOUND;
}

/* Tracking from its starts, each while the last failed: the prediction,
 * the turned start, the along start (first where the speed is least
 * known, below), and after a search that spanned scans the motion from
 * before it (a trial). Tracking is for scans close in time (the
 * caller's may_track): over a long interval (keyframes) a prediction can
 * be metres off, and a local registration from it can settle in a wrong
 * minimum that fits well; the search is safer. Without a prediction
 * tracking starts from no motion. narrow: the prediction's first tracking
 * is narrow (START_NARROW, a prior's START_PRIOR), or not (START_GOES_ON). */
#define PROBE FX_Q16_16_C(0.25) /* within tracking's 0.3 m, beyond its trust 0.1 m */

static track_outcome_t track_from_starts(ego_state_t *state, const ego_params_t *params, uint8_t cur,
                                         const ego_pose_t *predicted, bool have_prediction,
                                         bool after_search, start_kind_t narrow, uint32_t dt,
                                         bool *from_along, ego_output_t *out)
{
    *from_along = false;
    loose_fit_t loose;
    memset(&loose, 0, sizeof loose);
    track_outcome_t tracked = TRACK_FAILED;
    ego_pose_t along = *predicted;
    /* The along start comes first where the speed is least known: without
     * a prediction (a cold start at 3 m a scan left the budget no room for
     * it after tracking from no motion, and its search took 7 scans), and
     * after a corridor, where the speed is the one from before it (or the
     * entry's): at its exit it can be a fifth off, beyond tracking's
     * reach (not where a prior gives the speed: behind a platoon the
     * projections' shift is the trucks'). A standstill's best shift is no
     * shift: no start. */
    const bool along_first =
        !have_prediction || (state->along_predicted && narrow != START_PRIOR);
    const along_t first =
        along_first ? along_start(state, params, cur, predicted, have_prediction, &along) : ALONG_NONE;
    if (first == ALONG_SHIFTED) {
        tracked = track(state, params, cur, &along, &along, have_prediction, dt, START_GOES_ON,
                        &loose, out);
        *from_along = tracked == TRACK_FOUND;
    }
    if (tracked == TRACK_FAILED && !have_prediction) {
        tracked = answer_if_along_confirms(state, params, predicted, first, &along, &loose,
                                           from_along, out);
    }
    if (tracked == TRACK_FAILED && narrow != START_GOES_ON) {
        tracked = track(state, params, cur, predicted, predicted, have_prediction, dt, narrow,
                        &loose, out);
    }
    if (tracked == TRACK_FAILED) {
        tracked = track(state, params, cur, predicted, predicted, have_prediction, dt,
                        START_GOES_ON, &loose, out);
    }
    if (tracked == TRACK_FAILED && !have_prediction) {
        tracked = answer_if_along_confirms(state, params, predicted, first, &along, &loose,
                                           from_along, out);
    }
    if (tracked == TRACK_FAILED && !have_prediction && loose.have) {
        /* Else a start PROBE ahead of the loose fit along the heading that
         * comes back to it agrees. */
        ego_pose_t probe = loose.r.pose;
        probe.x = fx_add_q16(probe.x, PROBE);
        tracked = track(state, params, cur, &probe, &probe, false, dt, START_TRIAL, &loose, out);
    }
    ego_pose_t turned = *predicted;
    if (tracked == TRACK_FAILED && turned_start(state, cur, predicted, &turned)) {
        /* The turned start stands for the prediction: the histograms' turn
         * with the predicted translation, two pieces of evidence. */
        tracked = track(state, params, cur, &turned, &turned, have_prediction, dt, START_GOES_ON,
                        &loose, out);
    }
    if (tracked == TRACK_FAILED && !along_first &&
        along_start(state, params, cur, &turned, true, &along) == ALONG_SHIFTED) {
        /* Likewise: the projections' shift with the predicted heading. */
        tracked = track(state, params, cur, &along, &along, have_prediction, dt, START_LAST, &loose,
                        out);
        *from_along = tracked == TRACK_FOUND;
    }
    if (tracked == TRACK_FAILED && after_search && state->before_dt_us != 0u) {
        /* The search's motion predicts the scans it spanned (a turn begun
         * goes on); where it was a one-off (a jump, a bump), the motion
         * from before it is a start too. */
        const ego_pose_t before = scale_motion(&state->before, state->before_dt_us, dt);
        if (!close_to(&before, predicted, params)) {
            tracked =
                track(state, params, cur, &before, &before, false, dt, START_TRIAL, &loose, out);
        }
    }
    return tracked;
}

ego_status_t ego_process(ego_state_t *state, const ego_params_t *params, const ego_range_scan_t *scan,
                         uint32_t time_us, ego_output_t *out)
{
    return ego_process_with_prior(state, params, scan, time_us, NULL, out);
}

/* The full search when its scan's budget ends: anytime, its best so far
 * answers if it fits with half the accept share over both groups (the
 * light search's finish rule; flagged EGO_FLAG_NOT_CONVERGED when it did
 * not converge) rather than costing the next scans: on keyframes a search
 * that runs on drops the next scan, and the interval after it is twice as
 * long (docs/estimator.md). */
static bool answers_now(const ego_params_t *params, const ego_search_t *se)
{
    return !se->light && se->best_status == EGO_ITCP_OK && half_accepted(params, &se->best);
}

/* A scan while a search runs: it is not prepared (both slots belong to the
 * search), its budget goes to the search. */
static void continue_search(ego_state_t *state, const ego_params_t *params, ego_output_t *out)
{
    state->search.scans++;
    if (search_run(state, params) || answers_now(params, &state->search)) {
        finish_search(state, params, true, out);
        return;
    }
    out->flags = EGO_FLAG_RECOVERING;
    if (state->search.scans >= params->max_search_scans) {
        state->search.active = false; /* too long: start over */
        state->have_last = false;
    }
}

/* The scan in slot cur is the first: no motion. */
static void start_over(ego_state_t *state, uint8_t cur, uint32_t time_us, ego_output_t *out)
{
    out->flags = EGO_FLAG_FIRST;
    state->have_last = true;
    state->last = cur;
    state->last_time_us = time_us;
    state->held_time_us = time_us;
    state->slow_lines = 0u;
    memset(&state->motion, 0, sizeof state->motion);
    state->motion_dt_us = 0u;
    state->predictable = false;
    state->misses = 0u;
    state->bridge = false;
    state->lost = false;
    state->along_predicted = false;
    state->weak = false;
    state->have_reference = false;
    state->suspect = false;
}

/* A scan de-skewed with a motion (skew, over the line's interval) that
 * the measured one left by d put its points up to d tau / dt off (tau the
 * beams' RMS offset from the scan's time): that much is added to each
 * variance, an error the residuals do not show (the first scans of an
 * arc that begins at once, de-skewed with no turn). */
static void deskew_variance(ego_output_t *out, const ego_pose_t *skew, uint32_t tau_us)
{
    const int64_t dt = (out->dt_us > 0u) ? out->dt_us : 1;
    const int64_t d[3] = {(int64_t)out->pose.x - skew->x, (int64_t)out->pose.y - skew->y,
                          fx_rad_q16_of_turn(fx_bam32_diff(out->pose.theta, skew->theta))};
    fx_q2_30_t *variance[3] = {&out->cov.xx, &out->cov.yy, &out->cov.tt};
    for (unsigned i = 0u; i < 3u; i++) {
        const int64_t off = fx_sat_s32(d[i] * (int64_t)tau_us / dt); /* Q16 */
        const int64_t add = (off * off) >> 2;                        /* Q30 */
        if (*variance[i] != EGO_COV_SATURATED) {
            *variance[i] = fx_sat_s32((int64_t)*variance[i] + add);
        }
    }
}

/* The motion from the last scan to the prepared scan in slot cur, dt_us
 * later: tracked, else searched (in this scan's budget and, if need be, the
 * next scans'). */
static void match_scan(ego_state_t *state, const ego_params_t *params, uint8_t cur,
                       uint32_t time_us, uint32_t dt, const ego_pose_t *prior, ego_output_t *out)
{
    const ego_scan_t *current = &state->slot[cur];
    const ego_scan_t *last = &state->slot[state->last];
    out->dt_us = dt;
    /* While a scan is held the vehicle is slow (HOLD_SPEED: a scan's step
     * is millimetres): it stays where the last scan processed was, as
     * the prediction (the mean velocity since the held scan, scaled up,
     * made the noise of a short hold's first registrations centimetres). */
    const ego_pose_t predicted = (prior != NULL) ? *prior
                                 : holding(state) ? state->held
                                                  : predict(state, dt);
    /* After a search that took several scans the interval spans them: the
     * search's motion predicts it, tracked whatever its length. */
    const bool after_search = state->bridge;
    state->bridge = false;
    const bool have_prediction =
        prior != NULL || (motion_known(state, dt) && (after_search || state->predictable));
    const bool may_track = dt <= TRACK_INTERVAL_US || after_search || holding(state);
    /* Against a scan held, the prediction is the motion to the last scan
     * processed and one step on: it is judged over that step. */
    const uint32_t step = holding(state) ? time_us - state->held_time_us : dt;
    /* A motion that predicts within a vehicle's reach (not after a search
     * or a suspect change) is tracked with the narrow first reach first; a
     * prior to its error (START_PRIOR), when that is within the narrow
     * reach. */
    const bool narrow = have_prediction && !after_search && !state->suspect &&
                        (prior == NULL || prior_reach(prior) != 0);
    /* The last scan's points lead its time when it kept one pass at a cold
     * start (and the current one's, likewise): the registration spans
     * dt + lead_last - lead_current, its motion scaled back to dt (at 30
     * m/s the first de-skewed pair was 0.2 m long). */
    const uint32_t ahead = dt + 100u * state->lead_100us[state->last];
    const uint32_t behind = 100u * state->lead_100us[cur];
    const uint32_t span = (ahead > behind) ? ahead - behind : dt;
    const ego_pose_t track_predicted = scale_motion(&predicted, dt, span);
    if (current->count < params->min_points || last->count < params->min_points) {
        out->flags |= EGO_FLAG_TOO_FEW_POINTS | EGO_FLAG_PREDICTED;
        out->pose = predicted;
        set_velocities(out);
        advance(state, params, cur, time_us, out, false, false, &predicted, have_prediction);
        return;
    }
    bool from_along = false;
    /* The registrations judge the prediction (output_match) over out's
     * interval: the step; the motion found spans dt. */
    out->dt_us = step;
    const track_outcome_t tracked =
        may_track ? track_from_starts(state, params, cur, &track_predicted, have_prediction,
                                      after_search,
                                      !narrow              ? START_GOES_ON
                                      : (prior != NULL) ? START_PRIOR
                                                           : START_NARROW,
                                      step, &from_along, out)
                  : TRACK_FAILED;
    out->dt_us = dt;
    if (tracked == TRACK_FOUND) {
        out->pose = scale_motion(&out->pose, span, dt);
        if (state->skew_100us != 0u) { /* de-skewed with predicted: the prior, or the last motion */
            deskew_variance(out, &predicted, 100u * (uint32_t)state->skew_100us);
        }
        set_velocities(out);
        /* An along start measured the motion along the direction of travel
         * (surfaces facing it): along a corridor that is a prediction's
         * worth, and the motion is known. */
        advance(state, params, cur, time_us, out, true, true, &predicted,
                have_prediction || from_along);
        return;
    }
    /* What the trackings left in out is no answer. */
    const uint16_t points = out->points;
    memset(out, 0, sizeof *out);
    ego_cov_unknown(&out->cov);
    out->points = points;
    if (tracked == TRACK_FAILED && after_search && prior == NULL) {
        /* Another search would span more scans still, and at speed the
         * scans so far apart may not overlap: the prediction bridges the
         * interval (flagged), and the next scan is tracked from this one. */
        out->dt_us = dt;
        out->flags = EGO_FLAG_PREDICTED;
        out->pose = predicted;
        set_velocities(out);
        advance(state, params, cur, time_us, out, false, false, &predicted, false);
        state->predictable = true;
        return;
    }
    const ego_pose_t unfinished = state->search.track_predicted; /* the last track()'s */
    search_begin(state, time_us, dt, &predicted, prior != NULL, have_prediction,
                 !ample(state));
    if (tracked == TRACK_UNFINISHED) {
        state->search.stage = SEARCH_TRACKING;
        state->search.track_predicted = unfinished;
    }
    state->search.scans = 1u;
    if (search_run(state, params) || answers_now(params, &state->search)) {
        finish_search(state, params, false, out);
    } else {
        out->flags = EGO_FLAG_RECOVERING;
    }
}

ego_status_t ego_process_with_prior(ego_state_t *state, const ego_params_t *params,
                                    const ego_range_scan_t *scan, uint32_t time_us,
                                    const ego_pose_t *prior, ego_output_t *out)
{
    if (state == NULL || params == NULL || scan == NULL || out == NULL) {
        return EGO_ERR_ARG;
    }
    if (!ego_range_check(scan)) {
        return EGO_ERR_SCAN;
    }
    memset(out, 0, sizeof *out);
    ego_cov_unknown(&out->cov);
    ego_work_start(&state->work, budget(state, params, time_us));
    /* The scan's bookkeeping: the main direction, the choice, the output. */
    ego_work_spend(&state->work, EGO_COST_SCAN);
    if (state->search.active) {
        continue_search(state, params, out);
    } else {
        const uint8_t cur = state->have_last ? other_slot(state->last) : state->last;
        const uint32_t dt = time_us - state->last_time_us;
        /* A prior is from the last scan processed: from a scan held, it
         * follows the motion to that. */
        const uint32_t held_dt = state->held_time_us - state->last_time_us;
        const bool carry = prior != NULL && holding(state);
        const ego_pose_t none = {0u, 0, 0};
        const ego_pose_t prior_held = carry ? ego_pose_then(&state->held, prior) : none;
        const ego_pose_t *prior_from_kept = carry ? &prior_held : prior;
        /* De-skewed with the prior, else the last motion, if known over a
         * short interval (a speed at the scan's time; a keyframe's is an
         * average over seconds) and measured (one that rested on objects
         * may be a platoon's standstill: an interlaced scan de-skewed with
         * it is two images a pass's travel apart, and the street's own
         * registration failed on them for 6 s at 361 values). */
        ego_skew_t skew = {{0u, 0, 0}, 0u};
        if (state->have_last && prior != NULL && dt - held_dt <= TRACK_INTERVAL_US) {
            skew.motion = *prior;
            skew.dt_us = dt - held_dt;
        } else if (state->have_last && motion_known(state, dt) && state->motion_dt_us <= TRACK_INTERVAL_US &&
                   !state->on_objects) {
            skew.motion = state->motion;
            skew.dt_us = state->motion_dt_us;
        }
        if (!prepare(state, params, scan, &skew, cur)) {
            out->flags = EGO_FLAG_RECOVERING; /* skipped: the next motion spans it */
        } else if (!state->have_last || dt == 0u || time_us == state->held_time_us) {
            /* No interval since the last scan kept or, a scan held, since
             * the last one processed (a repeated time stamp): no motion to
             * measure over it (a line's velocities divided by zero: fuzz
             * finding E6, docs/robustness.md). */
            out->points = state->slot[cur].count;
            start_over(state, cur, time_us, out);
        } else {
            out->points = state->slot[cur].count;
            match_scan(state, params, cur, time_us, dt, prior_from_kept, out);
        }
    }
    finish_output(state, out, time_us);
    return EGO_OK;
}
