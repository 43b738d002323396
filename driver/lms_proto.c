/* lms_proto.c - small lookups over the protocol constants (lms_proto.h). */
#include "lms_proto.h"

const char *lms_status_name(lms_status_t status)
{
    switch (status) {
    case LMS_OK:
        return "ok";
    case LMS_ERR_ARG:
        return "bad argument";
    case LMS_ERR_FRAME:
        return "not a telegram";
    case LMS_ERR_CRC:
        return "crc mismatch";
    case LMS_ERR_CODE:
        return "unexpected reply code";
    case LMS_ERR_SIZE:
        return "wrong size for its code";
    case LMS_ERR_VALUE:
        return "reserved field value";
    }
    return "unknown status";
}

unsigned lms_meas_mode_bits(uint8_t mode)
{
    switch (mode) {
    case LMS_MEAS_8M_FIELDS_DAZZLE:
    case LMS_MEAS_8M_REFLECTOR:
    case LMS_MEAS_8M_FIELDS_ABC:
        return 13u;
    case LMS_MEAS_16M_REFLECTOR:
    case LMS_MEAS_16M_FIELDS_AB:
        return 14u;
    case LMS_MEAS_32M_REFLECTOR:
    case LMS_MEAS_32M_FIELD_A:
        return 15u;
    case LMS_MEAS_32M_IMMEDIATE:
    case LMS_MEAS_REFLECTIVITY:
        return 16u;
    default:
        return 0u;
    }
}

uint32_t lms_scan_period_us(uint16_t values)
{
    switch (values) {
    case 361u:
    case 201u:
        return 26667u;
    case 401u:
        return 53333u;
    default:
        return 13333u;
    }
}

uint32_t lms_baud_bps(lms_baud_t baud)
{
    switch (baud) {
    case LMS_BAUD_9600:
        return 9600u;
    case LMS_BAUD_19200:
        return 19200u;
    case LMS_BAUD_38400:
        return 38400u;
    case LMS_BAUD_500000:
        return 500000u;
    }
    return 0u;
}

uint32_t lms_wire_us(uint32_t bytes, lms_baud_t baud)
{
    const uint32_t bps = lms_baud_bps(baud);
    return bps == 0u ? 0u : (uint32_t)((uint64_t)bytes * 10u * 1000000u / bps);
}

uint32_t lms_scan_interval_us(uint16_t values, lms_baud_t baud)
{
    const uint32_t period = lms_scan_period_us(values);
    const uint32_t bps = lms_baud_bps(baud);
    if (bps == 0u) {
        return period;
    }
    const uint64_t wire = ((uint64_t)(2u * values + 12u) * 10u * 1000000u + bps - 1u) / bps;
    const uint64_t periods = (wire + period - 1u) / period;
    return (uint32_t)((periods < 1u ? 1u : periods) * period);
}
