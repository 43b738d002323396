/* ego_pose.c - composing 2-D rigid transforms (ego_pose.h). */
#include "ego_pose.h"

/* (x, y) (Q16.16) turned by angle, rounded and saturated. */
static void turn_by(fx_bam32_t angle, fx_q16_16_t x, fx_q16_16_t y, fx_q16_16_t *tx, fx_q16_16_t *ty)
{
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(angle, &s, &c);
    /* Each product below 2^61: the sums fit int64. Nearest, ties away. */
    *tx = fx_sat_s32(fx_shr_round_s64((int64_t)x * c - (int64_t)y * s, 30u));
    *ty = fx_sat_s32(fx_shr_round_s64((int64_t)x * s + (int64_t)y * c, 30u));
}

ego_pose_t ego_pose_then(const ego_pose_t *a, const ego_pose_t *b)
{
    ego_pose_t p = {a->theta + b->theta, 0, 0};
    turn_by(a->theta, b->x, b->y, &p.x, &p.y);
    p.x = fx_add_q16(a->x, p.x);
    p.y = fx_add_q16(a->y, p.y);
    return p;
}

ego_pose_t ego_pose_from(const ego_pose_t *a, const ego_pose_t *b)
{
    ego_pose_t p = {b->theta - a->theta, 0, 0};
    turn_by(0u - a->theta, fx_sub_q16(b->x, a->x), fx_sub_q16(b->y, a->y), &p.x, &p.y);
    return p;
}
