/* ego_lms.c - see ego_lms.h. */
#include "ego_lms.h"

#include <stddef.h>
#include <string.h>

/* Centi-degrees in one turn, and a quarter turn (the scanner's 90-degree
 * beam is its x axis). */
#define CDEG_PER_TURN 36000u
#define CDEG_QUARTER 9000u

/* The mirror turns at 75 Hz: one turn, and one degree of it. A scan finer
 * than 1 deg interlaces turns, each offset by one step, in value order
 * (value k from turn k % turns). */
#define LMS_TURN_US 13333u
#define LMS_DEGREE_NS 37037u
#define CDEG_PER_TURN_STEP 100u

void ego_lms_defaults(ego_lms_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->meas_mode = (uint8_t)LMS_MEAS_8M_FIELDS_DAZZLE;
}

/* Q32.32 binary angle of an angle in centi-degrees (0 .. 35999):
 * cdeg * 2^64 / 36000, rounded, in two 32-bit halves. */
static uint64_t bearing_from_cdeg(uint32_t cdeg)
{
    const uint64_t scaled = (uint64_t)cdeg << 32;
    const uint64_t whole = scaled / CDEG_PER_TURN;
    const uint64_t rest = scaled % CDEG_PER_TURN;
    return (whole << 32) + (((rest << 32) + CDEG_PER_TURN / 2u) / CDEG_PER_TURN);
}

ego_lms_status_t ego_lms_to_range(lms_scan_t *lms, const ego_lms_params_t *params,
                                  ego_range_scan_t *out)
{
    if (out == NULL) {
        return EGO_LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    if (lms == NULL || params == NULL || (lms->unit != LMS_UNIT_CM && lms->unit != LMS_UNIT_MM)) {
        return EGO_LMS_ERR_ARG;
    }
    lms_layout_t layout;
    if (lms_scan_layout(lms, &layout) != LMS_OK || lms->count > EGO_MAX_BEAMS) {
        return EGO_LMS_ERR_LAYOUT;
    }
    if (lms_scan_to_ranges(lms, params->meas_mode) != LMS_OK) {
        return EGO_LMS_ERR_ARG; /* a mode without ranges: lms untouched */
    }
    out->count = lms->count;
    out->range = lms->values;
    out->range_unit_um = (lms->unit == LMS_UNIT_CM) ? 10000u : 1000u;
    out->origin_x = params->mount_x;
    out->origin_y = params->mount_y;
    /* The LMS angle minus 90 deg (scanner x ahead, y left), turned by the
     * mounting angle. */
    out->first_bearing =
        bearing_from_cdeg(((uint32_t)layout.start_cdeg + CDEG_PER_TURN - CDEG_QUARTER) % CDEG_PER_TURN) +
        EGO_BEARING_Q32(params->mount_theta);
    out->bearing_step = bearing_from_cdeg(layout.step_cdeg); /* bearing NULL: uniform */
    /* A partial scan (mode 2A) is one turn; a complete one at 0.5 (0.25)
     * deg is two (four). */
    if (params->timing == (uint8_t)EGO_LMS_TIMING_MIRROR) {
        out->passes = (uint8_t)(lms->is_partial ? 1u : CDEG_PER_TURN_STEP / layout.step_cdeg);
        out->pass_us = LMS_TURN_US;
        out->beam_ns = LMS_DEGREE_NS;
    }
    return EGO_LMS_OK;
}
