/* ego_pose.h - a 2-D rigid transform in fixed point.
 *
 * The relative pose of a scan maps its points into the frame of the
 * previous scan: P' = R(theta) P + (x, y). It is the vehicle's motion
 * between the two scans, in the frame of the earlier one.
 */
#ifndef EGO_POSE_H
#define EGO_POSE_H

#include "ego_fx.h"
#include "ego_fx_math.h"

typedef struct {
    fx_bam32_t theta; /* rotation, binary angle (signed via fx_bam32_diff) */
    fx_q16_16_t x;    /* translation, metres */
    fx_q16_16_t y;
} ego_pose_t;

/* R(theta) (px, py) + (x, y), with sin/cos of theta given (Q2.30). */
static inline void ego_pose_apply(const ego_pose_t *pose, fx_q2_30_t s, fx_q2_30_t c,
                                  fx_q16_16_t px, fx_q16_16_t py, fx_q16_16_t *qx,
                                  fx_q16_16_t *qy)
{
    *qx = fx_add_q16(pose->x, fx_sub_q16(fx_mul_q16_q30(px, c), fx_mul_q16_q30(py, s)));
    *qy = fx_add_q16(pose->y, fx_add_q16(fx_mul_q16_q30(px, s), fx_mul_q16_q30(py, c)));
}

/* Composition. The angles add modulo a turn; the translations are
 * rounded to Q16.16 (nearest, ties away; the turn's sine and cosine are
 * fx_sincos's) and saturate at its range. */

/* a, then b (given in the frame a ends in): b in a's start frame. */
ego_pose_t ego_pose_then(const ego_pose_t *a, const ego_pose_t *b);

/* b in the frame a ends in (a and b given in one frame): inverse(a), then b. */
ego_pose_t ego_pose_from(const ego_pose_t *a, const ego_pose_t *b);

#endif /* EGO_POSE_H */
