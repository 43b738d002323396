/* ego_lms.c - see ego_lms.h. */
#include "ego_lms.h"

#include <stddef.h>
#include <string.h>

/* Centi-degrees in one turn, and a quarter turn (the scanner's 90-degree
 * beam is its x axis). */
#define CDEG_PER_TURN 36000u
#define CDEG_QUARTER 9000u

void ego_lms_defaults(ego_lms_params_t *params)
{
    memset(params, 0, sizeof *params);
    params->meas_mode = (uint8_t)LMS_MEAS_8M_FIELDS_DAZZLE;
}

/* Binary angle of an angle in centi-degrees (0 .. 35999), rounded. */
static fx_bam32_t bam_from_cdeg(uint32_t cdeg)
{
    return (fx_bam32_t)((((uint64_t)cdeg << 32) + CDEG_PER_TURN / 2u) / CDEG_PER_TURN);
}

/* Millimetres to Q16.16 metres, rounded. */
static fx_q16_16_t q16_from_mm(uint32_t mm)
{
    return (fx_q16_16_t)((((uint64_t)mm << 16) + 500u) / 1000u);
}

ego_lms_status_t ego_lms_to_range(const lms_scan_t *lms, const ego_lms_params_t *params,
                                  ego_range_scan_t *out)
{
    if (out == NULL) {
        return EGO_LMS_ERR_ARG;
    }
    out->count = 0u;
    if (lms == NULL || params == NULL || lms_meas_mode_bits(params->meas_mode) == 0u ||
        params->meas_mode == (uint8_t)LMS_MEAS_REFLECTIVITY) {
        return EGO_LMS_ERR_ARG;
    }
    lms_layout_t layout;
    if (lms_scan_layout(lms, &layout) != LMS_OK || lms->count > EGO_MAX_BEAMS) {
        return EGO_LMS_ERR_LAYOUT;
    }
    out->origin_x = params->mount_x;
    out->origin_y = params->mount_y;
    out->per_beam_bearing = true;
    for (uint16_t k = 0u; k < lms->count; k++) {
        /* The LMS angle minus 90 deg (scanner x ahead, y left), turned by
         * the mounting angle. Rounding each angle on its own keeps every
         * bearing within half a unit of the truth. */
        const uint32_t lms_cdeg = (uint32_t)layout.start_cdeg + (uint32_t)k * layout.step_cdeg;
        out->bearing[k] =
            bam_from_cdeg((lms_cdeg + CDEG_PER_TURN - CDEG_QUARTER) % CDEG_PER_TURN) +
            params->mount_theta;
        lms_value_t v;
        out->valid[k] = lms_value_decode(lms->values[k], params->meas_mode, lms->unit, &v) == LMS_OK &&
                        v.kind == LMS_VALUE_RANGE;
        out->range[k] = out->valid[k] ? q16_from_mm(v.distance_mm) : 0;
    }
    /* The nominal step, for readers that want one; the bearings above rule. */
    out->first_bearing = out->bearing[0];
    out->bearing_step = (lms->count > 1u) ? out->bearing[1] - out->bearing[0] : 0u;
    out->count = lms->count;
    return EGO_LMS_OK;
}
