/* lms_config.c - see lms_config.h. */
#include "lms_config.h"

static bool size_is_valid(const lms_config_t *cfg)
{
    return cfg->size == LMS_CONFIG_SIZE_OLD || cfg->size == LMS_CONFIG_SIZE_NEW;
}

uint8_t lms_config_meas_mode(const lms_config_t *cfg)
{
    return cfg->block[LMS_CONFIG_OFF_MEAS_MODE];
}

uint8_t lms_config_units(const lms_config_t *cfg)
{
    return cfg->block[LMS_CONFIG_OFF_UNITS];
}

bool lms_config_has_indices(const lms_config_t *cfg)
{
    return (cfg->block[LMS_CONFIG_OFF_AVAILABILITY] & LMS_CONFIG_AVAIL_RT_INDICES) != 0u;
}

lms_status_t lms_config_set_meas_mode(lms_config_t *cfg, uint8_t meas_mode)
{
    if (cfg == NULL || !size_is_valid(cfg) || lms_meas_mode_bits(meas_mode) == 0u) {
        return LMS_ERR_ARG;
    }
    cfg->block[LMS_CONFIG_OFF_MEAS_MODE] = meas_mode;
    return LMS_OK;
}

lms_status_t lms_config_set_unit(lms_config_t *cfg, lms_unit_t unit)
{
    if (cfg == NULL || !size_is_valid(cfg) || (unit != LMS_UNIT_CM && unit != LMS_UNIT_MM)) {
        return LMS_ERR_ARG;
    }
    cfg->block[LMS_CONFIG_OFF_UNITS] = (uint8_t)unit;
    return LMS_OK;
}

lms_status_t lms_config_set_indices(lms_config_t *cfg, bool on)
{
    if (cfg == NULL || !size_is_valid(cfg)) {
        return LMS_ERR_ARG;
    }
    uint8_t avail = cfg->block[LMS_CONFIG_OFF_AVAILABILITY];
    avail = on ? (uint8_t)(avail | LMS_CONFIG_AVAIL_RT_INDICES)
               : (uint8_t)(avail & (uint8_t)~LMS_CONFIG_AVAIL_RT_INDICES);
    cfg->block[LMS_CONFIG_OFF_AVAILABILITY] = avail;
    return LMS_OK;
}
