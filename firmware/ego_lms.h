/* ego_lms.h - the SICK LMS 2xx adapter: a decoded B0 scan (lms_decode.h)
 * as the estimator's generic range scan (ego_range.h).
 *
 * Everything LMS-specific the estimator used to know lives here: the value
 * layout (which angles a count of values covers), the units, the measuring
 * mode (which bits of a value are range and which flag special values: the
 * session reports the scanner's real mode, lms_session_info), the LMS angle
 * convention (0 deg on the scanner's right, 90 deg straight ahead) and the
 * scanner's mounting pose on the vehicle. Special values (no return,
 * dazzle, beyond max, ...) become beams without a range. The ranges are
 * written over the scan's own values (no second buffer: RAM is what a
 * microcontroller lacks), so the range scan points into lms. Portable
 * C11: no OS headers, no heap.
 */
#ifndef EGO_LMS_H
#define EGO_LMS_H

#include <stdint.h>

#include "ego_fx.h"
#include "ego_range.h"
#include "lms_decode.h"

_Static_assert(EGO_MAX_BEAMS >= LMS_SCAN_MAX_VALUES, "every LMS layout must fit a range scan");

/* When the values of a scan were measured. */
typedef enum {
    EGO_LMS_TIMING_MIRROR = 0, /* as the scanner measures them: its mirror's sweep,
                                  0.5- and 0.25-deg scans interlacing turns (the
                                  estimator de-skews them) */
    EGO_LMS_TIMING_INSTANT = 1 /* all at once: a simulator's stream (lmsworld's
                                  default) */
} ego_lms_timing_t;

typedef struct {
    fx_q16_16_t mount_x;   /* the scanner's origin in the vehicle frame, m */
    fx_q16_16_t mount_y;
    fx_bam32_t mount_theta; /* the scanner's 90-deg beam in the vehicle frame */
    uint8_t meas_mode;      /* lms_meas_mode_t the scanner measures in */
    uint8_t timing;         /* ego_lms_timing_t */
} ego_lms_params_t;

/* Mounted at the vehicle's origin looking ahead, measuring mode 00 (the
 * scanner's factory setting), the mirror's timing. */
void ego_lms_defaults(ego_lms_params_t *params);

typedef enum {
    EGO_LMS_OK = 0,
    EGO_LMS_ERR_ARG = -1,   /* NULL pointer, or a measuring mode without ranges */
    EGO_LMS_ERR_LAYOUT = -2 /* the value count is not an LMS variant */
} ego_lms_status_t;

/* Turns lms's values into ranges in place (in the scan's unit, 0 for a
 * special value: the raw words are gone) and fills out to point at them:
 * one beam per value, uniform bearings from the LMS layout turned by
 * mount_theta (each bearing comes out as the LMS angle rounded to a binary
 * angle on its own would) and the beam times of the mirror (75 turns a
 * second; a 0.5-deg scan from two turns, a 0.25-deg one from four, value k
 * from turn k % turns: ego_range.h). On an error lms is untouched and out->count
 * is 0. */
ego_lms_status_t ego_lms_to_range(lms_scan_t *lms, const ego_lms_params_t *params,
                                  ego_range_scan_t *out);

#endif /* EGO_LMS_H */
