/* ego.c - see ego.h. */
#include "ego.h"

#include <stddef.h>
#include <string.h>

#if defined(EGO_PROFILE)
#define STAGE(s) ego_profile_stage(s)
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
    ego_itcp_defaults(&params->itcp);
    params->use_coarse = true;
    ego_coarse_defaults(&params->coarse);
    params->coarse_window_first = FX_Q16_16_C(4.0);
    params->coarse_step_first = FX_Q16_16_C(0.2);
    params->coarse_window_wide = FX_Q16_16_C(1.6);
    params->accept_fraction = (fx_q2_30_t)(FX_Q2_30_ONE / 10 * 6);
    params->stop_fraction = (fx_q2_30_t)(FX_Q2_30_ONE / 10 * 8);
    params->max_rotation_bins = (uint16_t)(EGO_HIST_BINS / 4u); /* 45 deg */
    params->merge_bins = (uint16_t)(EGO_HIST_BINS / 60u);       /* 3 deg */
    params->min_correlation = (fx_q2_30_t)(FX_Q2_30_ONE / 10 * 3);
    params->min_points = 20u;
    params->max_gap_us = 1000000u;
    params->trust_translation = FX_Q16_16_C(0.10);
    params->prior_margin = (fx_q2_30_t)(FX_Q2_30_ONE / 10);
    params->sweep_steps = 11u;
    params->sweep_step = FX_BAM32_DEG_C(4.0);
    params->trust_rotation = FX_BAM32_DEG_C(3.0);
    params->hold_first = true;
    params->max_candidates = 0u;
    params->prediction_first = false;
}

void ego_defaults_bounded(ego_params_t *params)
{
    ego_defaults(params);
    params->prep.beam_spacing = FX_BAM32_DEG_C(1.0);
    params->tfit.passes = 0u;
    params->hist.kind = EGO_HIST_AH;
    params->max_rotation_bins = (uint16_t)(EGO_HIST_BINS / 36u); /* 5 deg */
    params->use_coarse = false;
    params->sweep_steps = 0u;
    params->hold_first = false;
    params->max_candidates = 1u;
    params->prediction_first = true;
    params->itcp.radius_start = FX_Q16_16_C(0.15);
    params->itcp.max_iterations = 6u;
    params->itcp.fine_iterations = 4u;
    params->itcp.converge_translation = FX_Q16_16_C(0.0005);
    params->itcp.converge_rotation = FX_BAM32_DEG_C(0.005);
    params->itcp.max_points = 40u;
}

void ego_reset(ego_state_t *state)
{
    state->have_last = false;
    state->last = 0u;
    state->last_time_us = 0u;
    memset(&state->motion, 0, sizeof state->motion);
    state->motion_dt_us = 0u;
    state->predictable = false;
}

/* The last motion scaled to a scan interval of dt_us. */
static ego_pose_t predict(const ego_state_t *state, uint32_t dt_us)
{
    ego_pose_t p = {0u, 0, 0};
    if (state->motion_dt_us == 0u) {
        return p;
    }
    const int64_t num = dt_us;
    const int64_t den = state->motion_dt_us;
    p.x = fx_sat_s32((int64_t)state->motion.x * num / den);
    p.y = fx_sat_s32((int64_t)state->motion.y * num / den);
    p.theta = (fx_bam32_t)(uint32_t)fx_sat_s32(
        (int64_t)fx_bam32_diff(state->motion.theta, 0u) * num / den);
    return p;
}

/* Is the estimate within the prediction's trust distance of it. */
static bool close_to(const ego_pose_t *estimate, const ego_pose_t *predicted,
                     const ego_params_t *params)
{
    const int64_t dx = (int64_t)estimate->x - predicted->x;
    const int64_t dy = (int64_t)estimate->y - predicted->y;
    const int64_t r = params->trust_translation;
    const int64_t dtheta = fx_bam32_diff(estimate->theta, predicted->theta);
    const int64_t abs_dtheta = (dtheta < 0) ? -dtheta : dtheta;
    return dx * dx + dy * dy <= r * r && abs_dtheta <= (int64_t)params->trust_rotation;
}

static void set_velocities(ego_output_t *out)
{
    const int64_t dt = out->dt_us;
    out->vx = fx_sat_s32((int64_t)out->pose.x * US_PER_S / dt);
    out->vy = fx_sat_s32((int64_t)out->pose.y * US_PER_S / dt);
    /* theta (2^32 a turn) -> rad/s in Q16.16, in two steps to stay in
     * int64: |theta| * 411775 < 2^50, then * 10^6 / 2^32. */
    const int64_t per_us = (int64_t)fx_bam32_diff(out->pose.theta, 0u) * RAD_Q16_PER_TURN / dt;
    out->omega = fx_sat_s32(per_us * US_PER_S / 4294967296LL);
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

/* The paper's two ITCP stages from start: translation with the rotation
 * held, then everything. */
static ego_itcp_status_t register_from(const ego_scan_t *last, const ego_scan_t *current,
                                   fx_bam32_t main_direction, const ego_pose_t *start,
                                   const ego_params_t *params, ego_itcp_result_t *r)
{
    STAGE(EGO_STAGE_REGISTER);
    ego_pose_t second = *start;
    if (params->hold_first) {
        ego_itcp_result_t held;
        const ego_itcp_status_t st =
            ego_itcp_register(last, current, main_direction, start, true, &params->itcp, &held);
        second = (st == EGO_ITCP_OK) ? held.pose : *start;
    }
    const ego_itcp_status_t result =
        ego_itcp_register(last, current, main_direction, &second, false, &params->itcp, r);
    STAGE(EGO_STAGE_OTHER);
    return result;
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

/* The coarse search around centre with cp, then ITCP from what it found. */
static ego_itcp_status_t search_from(const ego_scan_t *last, const ego_scan_t *current,
                                 fx_bam32_t main_direction, const ego_pose_t *centre,
                                 const ego_coarse_params_t *cp, const ego_params_t *params,
                                 ego_itcp_result_t *r)
{
    ego_pose_t found = *centre;
    uint64_t score = 0u;
    STAGE(EGO_STAGE_COARSE);
    ego_coarse_search(last, current, main_direction, centre, cp, &found, &score);
    return register_from(last, current, main_direction, &found, params, r);
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

ego_status_t ego_process(ego_state_t *state, const ego_params_t *params, const ego_range_scan_t *scan,
                         uint32_t time_us, ego_output_t *out)
{
    return ego_process_with_prior(state, params, scan, time_us, NULL, out);
}

ego_status_t ego_process_with_prior(ego_state_t *state, const ego_params_t *params,
                                    const ego_range_scan_t *scan, uint32_t time_us,
                                    const ego_pose_t *prior, ego_output_t *out)
{
    if (state == NULL || params == NULL || scan == NULL || out == NULL) {
        return EGO_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    const uint8_t cur = state->have_last ? (uint8_t)(1u - state->last) : state->last;
    ego_scan_t *current = &state->slot[cur];
    STAGE(EGO_STAGE_PREPARE);
    if (ego_scan_prepare(scan, &params->prep, current) != EGO_PREP_OK) {
        STAGE(EGO_STAGE_OTHER);
        return EGO_ERR_SCAN;
    }
    STAGE(EGO_STAGE_TANGENTS);
    if (params->hist.kind == EGO_HIST_HTAH || params->use_coarse || params->itcp.tangent_gate) {
        ego_tfit_fit_scan(current, &params->tfit);
    } else {
        /* Only ITCP's sample of the points needs a tangent (its groups). */
        const uint16_t stride = ego_itcp_sample_stride(current->count, params->itcp.max_points);
        ego_tfit_fit_scan_sample(current, &params->tfit, (uint16_t)(stride / 2u), stride);
    }
    STAGE(EGO_STAGE_HISTOGRAM);
    (void)ego_hist_build(current, &params->hist, &state->hist[cur]);
    STAGE(EGO_STAGE_OTHER);
    out->points = current->count;

    const uint32_t dt = time_us - state->last_time_us;
    if (!state->have_last || dt == 0u || dt > params->max_gap_us) {
        out->flags = EGO_FLAG_FIRST;
        state->have_last = true;
        state->last = cur;
        state->last_time_us = time_us;
        memset(&state->motion, 0, sizeof state->motion);
        state->motion_dt_us = 0u;
        return EGO_OK;
    }
    out->dt_us = dt;
    const ego_scan_t *last = &state->slot[state->last];
    const ego_pose_t predicted = (prior != NULL) ? *prior : predict(state, dt);
    /* The last motion predicts this one only if it predicted the last. */
    const bool known_motion = state->motion_dt_us != 0u;
    const bool have_prediction = prior != NULL || (known_motion && state->predictable);

    bool matched = false;
    if (current->count >= params->min_points && last->count >= params->min_points) {
        /* Candidates: the prior's rotation (or, with prediction_first, a
         * trusted prediction's), the histogram's peaks, plus the predicted
         * rotation when the histogram is not trustworthy. */
        fx_bam32_t rotation[EGO_HIST_MAX_CANDIDATES + 3u]; /* + prior, prediction, sweep */
        fx_q2_30_t correlation[EGO_HIST_MAX_CANDIDATES + 3u];
        uint8_t n = 0u;
        const bool prediction_first = prior == NULL && have_prediction && params->prediction_first;
        if (prior != NULL || prediction_first) {
            rotation[n] = predicted.theta;
            correlation[n] = 0;
            n++;
        }
        /* The histogram only when its candidates can be tried. */
        if (params->max_candidates == 0u || n < params->max_candidates) {
            ego_hist_match_t hm;
            /* Around the prior's rotation, if any. */
            const fx_bam32_t expected = (prior != NULL) ? prior->theta : 0u;
            STAGE(EGO_STAGE_CORRELATE);
            ego_hist_correlate(&state->hist[cur], &state->hist[state->last], expected,
                           params->max_rotation_bins, params->merge_bins, &hm);
            STAGE(EGO_STAGE_OTHER);
            if (n > 0u) {
                correlation[0] = (hm.count > 0u) ? hm.candidate[0].correlation : 0;
            }
            for (uint8_t k = 0u; k < hm.count; k++) {
                rotation[n] = hm.candidate[k].rotation;
                correlation[n] = hm.candidate[k].correlation;
                n++;
            }
            if (hm.count == 0u || hm.candidate[0].correlation < params->min_correlation) {
                out->flags |= EGO_FLAG_LOW_CORRELATION;
                if (prior == NULL && !prediction_first) {
                    rotation[n] = predicted.theta;
                    correlation[n] = (hm.count > 0u) ? hm.candidate[0].correlation : 0;
                    n++;
                }
            }
        }
        const fx_bam32_t main_direction = ego_hist_main_direction(&state->hist[state->last]);
        ego_itcp_result_t best;
        ego_itcp_status_t best_status = EGO_ITCP_ERR_FEW_MATCHES;
        memset(&best, 0, sizeof best);
        uint8_t best_k = 0u;
        uint8_t tried = 0u;
        if (params->max_candidates != 0u && n > params->max_candidates) {
            n = params->max_candidates;
        }
        for (uint8_t k = 0u; k < n && !good_enough(params, best_status, &best, true);
             k++) {
            ego_itcp_result_t r;
            const ego_pose_t start = {rotation[k], predicted.x, predicted.y};
            ego_itcp_status_t st = register_from(last, current, main_direction, &start, params, &r);
            /* Cheap first: from the prediction. The coarse search only when
             * that did not give a good match: around the prediction, and
             * if that is still not good, over the wide window. */
            if (params->use_coarse) {
                for (unsigned pass = have_prediction ? 0u : 1u;
                     pass < ((prior != NULL) ? 1u : 2u) && !good_enough(params, st, &r, false);
                     pass++) {
                    ego_coarse_params_t cp = params->coarse;
                    if (pass == 1u && known_motion) {
                        cp.window = params->coarse_window_wide;
                    } else if (pass == 1u) { /* nothing known: wider, coarser */
                        cp.window = params->coarse_window_first;
                        cp.step = params->coarse_step_first;
                    }
                    ego_itcp_result_t rc;
                    const ego_itcp_status_t stc =
                        search_from(last, current, main_direction, &start, &cp, params, &rc);
                    if (better(stc, &rc, st, &r, 0)) {
                        r = rc;
                        st = stc;
                    }
                }
            }
            tried++;
            /* Another rotation replaces the prior's only if clearly better. */
            const bool against_prior = prior != NULL && best_k == 0u && best_status == EGO_ITCP_OK;
            if (better(st, &r, best_status, &best, against_prior ? params->prior_margin : 0)) {
                best = r;
                best_status = st;
                best_k = k;
            }
        }
        /* Last resort, without a prior: no candidate fits. The histogram's
         * peaks can all be wrong where few walls are seen (its correlation
         * is broad and has one maximum); sweep the rotation instead. */
        if (prior == NULL && params->use_coarse && params->sweep_steps > 0u &&
            !good_enough(params, best_status, &best, false)) {
            ego_coarse_params_t cp = params->coarse;
            cp.window = known_motion ? params->coarse_window_wide : params->coarse_window_first;
            cp.step = params->coarse_step_first;
            cp.rotation_steps = params->sweep_steps;
            cp.rotation_step = params->sweep_step;
            ego_itcp_result_t r;
            const ego_itcp_status_t st =
                search_from(last, current, main_direction, &predicted, &cp, params, &r);
            tried++;
            if (better(st, &r, best_status, &best, 0)) {
                best = r;
                best_status = st;
                best_k = n; /* no histogram candidate */
                correlation[n] = 0;
            }
        }
        out->candidates = tried;
        if (best_status == EGO_ITCP_OK) {
            matched = true;
            out->pose = best.pose;
            out->iterations = best.iterations;
            out->matches = best.matches;
            out->n_main = best.n_main;
            out->n_non_main = best.n_non_main;
            out->inliers = best.inliers;
            out->residual = best.residual;
            out->correlation = correlation[best_k];
            if (best.aperture) {
                /* Along a corridor the scans cannot tell how far the vehicle
                 * went: keep the measured motion across the main direction
                 * and take the predicted one along it, if there is a
                 * prediction worth the name (else the match's own guess). */
                out->flags |= EGO_FLAG_APERTURE;
                if (have_prediction) {
                    keep_prediction_along(&out->pose, &predicted, main_direction);
                }
            }
            out->flags |= best.converged ? 0u : EGO_FLAG_NOT_CONVERGED;
        }
    }
    if (!matched) {
        out->flags |= EGO_FLAG_TOO_FEW_POINTS | EGO_FLAG_PREDICTED;
        out->pose = predicted;
    }
    set_velocities(out);

    state->predictable = matched && close_to(&out->pose, &predicted, params);
    state->motion = out->pose;
    state->motion_dt_us = dt;
    state->last = cur;
    state->last_time_us = time_us;
    return EGO_OK;
}
