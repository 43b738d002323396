/* lms_decode.c - see lms_decode.h. Offsets and codes: docs/protocol.md. */
#include "lms_decode.h"

#include <string.h>

#include "lms_crc.h"

#define COUNT_N_MASK 0x03FFu
#define COUNT_PARTIAL_INDEX_SHIFT 11u
#define COUNT_PARTIAL_FLAG 0x2000u
#define COUNT_UNIT_SHIFT 14u

/* B1 status offsets, from the first byte after the code. */
#define STATUS_OFF_FIRMWARE 0u
#define STATUS_OFF_OPERATING_MODE 7u
#define STATUS_OFF_DEVICE_STATUS 8u
#define STATUS_OFF_MEAS_MODE 101u
#define STATUS_OFF_ANGLE 106u
#define STATUS_OFF_RESOLUTION 108u
#define STATUS_OFF_BAUD 115u
#define STATUS_OFF_PERMANENT_BAUD 118u
#define STATUS_OFF_ADDRESS 119u
#define STATUS_OFF_UNITS 121u
#define STATUS_OFF_LASER 122u
#define STATUS_FIRMWARE_SIZE 7u

/* Little-endian u16 at base[off]. */
static uint16_t get_u16(const uint8_t *base, size_t off)
{
    return (uint16_t)(base[off] | (base[off + 1u] << 8));
}

lms_status_t lms_telegram_parse(const uint8_t *bytes, size_t len, lms_telegram_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    if (bytes == NULL) {
        return LMS_ERR_ARG;
    }
    if (len < LMS_OVERHEAD + 1u || bytes[0] != LMS_STX) {
        return LMS_ERR_FRAME;
    }
    const uint16_t field = get_u16(bytes, 2u);
    const bool is_reply = (bytes[1] & LMS_ADDR_REPLY_BIT) != 0u;
    const size_t min_field = is_reply ? 2u : 1u;
    if (field < min_field || (size_t)field + LMS_OVERHEAD != len) {
        return LMS_ERR_FRAME;
    }
    const size_t body = len - LMS_CRC_SIZE;
    if (lms_crc16(bytes, body) != get_u16(bytes, body)) {
        return LMS_ERR_CRC;
    }
    out->address = bytes[1];
    out->code = bytes[LMS_HEADER_SIZE];
    out->data = &bytes[LMS_HEADER_SIZE + 1u];
    out->is_reply = is_reply;
    /* The length field counts code, data and (replies) status. */
    out->data_len = (uint16_t)(field - (is_reply ? 2u : 1u));
    out->status = is_reply ? bytes[body - 1u] : 0u;
    return LMS_OK;
}

lms_status_byte_t lms_status_byte_decode(uint8_t raw)
{
    lms_status_byte_t s;
    s.raw = raw;
    s.severity = (uint8_t)(raw & 0x07u);
    s.restart = (raw & 0x20u) != 0u;
    s.implausible = (raw & 0x40u) != 0u;
    s.pollution = (raw & 0x80u) != 0u;
    return s;
}

/* Parses a reply and checks its code and its data size (min..max). */
static lms_status_t parse_reply(const uint8_t *bytes, size_t len, uint8_t code, size_t min_data,
                                size_t max_data, lms_telegram_t *t)
{
    const lms_status_t st = lms_telegram_parse(bytes, len, t);
    if (st != LMS_OK) {
        return st;
    }
    if (!t->is_reply || t->code != code) {
        return LMS_ERR_CODE;
    }
    if (t->data_len < min_data || t->data_len > max_data) {
        return LMS_ERR_SIZE;
    }
    return LMS_OK;
}

/* Copies n bytes of ASCII text, NUL-terminated, non-printables as '?'. */
static void copy_text(char *dst, const uint8_t *src, size_t n)
{
    for (size_t i = 0u; i < n; i++) {
        const uint8_t c = src[i];
        char printable = '?';
        if (c >= 0x20u && c < 0x7Fu) {
            printable = (char)c;
        }
        dst[i] = printable;
    }
    dst[n] = '\0';
}

lms_status_t lms_decode_scan(const uint8_t *bytes, size_t len, lms_scan_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    lms_telegram_t t;
    lms_status_t st = parse_reply(bytes, len, LMS_REPLY_VALUES, 2u, LMS_LENGTH_MAX, &t);
    if (st != LMS_OK) {
        return st;
    }
    const uint16_t count_word = get_u16(t.data, 0u);
    const uint16_t n = (uint16_t)(count_word & COUNT_N_MASK);
    const size_t plain = 2u + 2u * (size_t)n;
    if (n > LMS_SCAN_MAX_VALUES || (t.data_len != plain && t.data_len != plain + 2u)) {
        return LMS_ERR_SIZE;
    }
    const unsigned unit = (unsigned)(count_word >> COUNT_UNIT_SHIFT);
    if (unit > (unsigned)LMS_UNIT_MM) {
        return LMS_ERR_VALUE;
    }
    out->address = t.address;
    out->status = t.status;
    out->unit = (lms_unit_t)unit;
    out->count = n;
    out->is_partial = (count_word & COUNT_PARTIAL_FLAG) != 0u;
    out->partial_index = (uint8_t)((count_word >> COUNT_PARTIAL_INDEX_SHIFT) & 0x3u);
    for (uint16_t i = 0u; i < n; i++) {
        out->values[i] = get_u16(t.data, 2u + 2u * i);
    }
    if (t.data_len == plain + 2u) {
        out->has_indices = true;
        out->scan_index = t.data[plain];
        out->telegram_index = t.data[plain + 1u];
    }
    return LMS_OK;
}

/* Kinds of the nine codes at the top of a mode's range, indexed by
 * max - code. */
static const lms_value_kind_t top_code_kind[9] = {
    LMS_VALUE_NO_RETURN,     LMS_VALUE_DAZZLE,   LMS_VALUE_OVERFLOW,
    LMS_VALUE_RESERVED,      LMS_VALUE_LOW_SNR,  LMS_VALUE_CHANNEL_ERROR,
    LMS_VALUE_RESERVED,      LMS_VALUE_RESERVED, LMS_VALUE_BEYOND_MAX,
};

lms_status_t lms_scan_to_ranges(lms_scan_t *scan, uint8_t meas_mode)
{
    const unsigned bits = lms_meas_mode_bits(meas_mode);
    if (scan == NULL || bits == 0u || meas_mode == LMS_MEAS_REFLECTIVITY ||
        scan->count > LMS_SCAN_MAX_VALUES) {
        return LMS_ERR_ARG;
    }
    const uint32_t max = (1u << bits) - 1u;
    /* Mode 0F's 16 bits have no special codes: every value is a range. */
    const uint32_t first_special = (bits < 16u) ? max - 8u : 0x10000u;
    for (uint16_t k = 0u; k < scan->count; k++) {
        const uint32_t d = scan->values[k] & max;
        scan->values[k] = (uint16_t)((d >= first_special) ? 0u : d);
    }
    return LMS_OK;
}

lms_status_t lms_value_decode(uint16_t word, uint8_t meas_mode, lms_unit_t unit, lms_value_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    const unsigned bits = lms_meas_mode_bits(meas_mode);
    if (bits == 0u || (unit != LMS_UNIT_CM && unit != LMS_UNIT_MM)) {
        memset(out, 0, sizeof *out);
        return LMS_ERR_ARG;
    }
    if (meas_mode == LMS_MEAS_REFLECTIVITY) {
        out->kind = LMS_VALUE_REFLECTIVITY;
        out->distance_mm = word;
        out->flags = 0u;
        return LMS_OK;
    }
    const uint32_t max = (1u << bits) - 1u;
    const uint32_t d = word & max;
    out->flags = (uint8_t)((uint32_t)word >> bits);
    if (bits < 16u && d >= max - 8u) {
        out->kind = top_code_kind[max - d];
        out->distance_mm = 0u;
        return LMS_OK;
    }
    out->kind = LMS_VALUE_RANGE;
    out->distance_mm = (unit == LMS_UNIT_CM) ? d * 10u : d;
    return LMS_OK;
}

/* The five variants, by value count. */
static const struct {
    uint16_t count;
    uint16_t field_deg;
    uint16_t step_cdeg;
} variants[] = {
    {181u, 180u, 100u}, {361u, 180u, 50u}, {101u, 100u, 100u}, {201u, 100u, 50u}, {401u, 100u, 25u},
};

lms_status_t lms_scan_layout(const lms_scan_t *scan, lms_layout_t *out)
{
    if (scan == NULL || out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    for (size_t k = 0u; k < sizeof variants / sizeof variants[0]; k++) {
        if (variants[k].count != scan->count) {
            continue;
        }
        if (scan->is_partial && variants[k].step_cdeg != 100u) {
            return LMS_ERR_VALUE; /* partial scans are single 1-degree sweeps */
        }
        out->field_deg = variants[k].field_deg;
        out->step_cdeg = variants[k].step_cdeg;
        /* A 100-degree field is centred ahead: 40 .. 140 degrees. */
        out->start_cdeg = (uint16_t)((out->field_deg == 180u ? 0u : 4000u) +
                                     (scan->is_partial ? 25u * scan->partial_index : 0u));
        return LMS_OK;
    }
    return LMS_ERR_VALUE;
}

lms_status_t lms_decode_mode_reply(const uint8_t *bytes, size_t len, lms_mode_reply_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    lms_telegram_t t;
    const lms_status_t st = parse_reply(bytes, len, LMS_REPLY_MODE, 1u, 1u, &t);
    if (st != LMS_OK) {
        return st;
    }
    if (t.data[0] > (uint8_t)LMS_MODE_RESULT_FAULT) {
        return LMS_ERR_VALUE;
    }
    out->address = t.address;
    out->status = t.status;
    out->result = (lms_mode_result_t)t.data[0];
    return LMS_OK;
}

static lms_status_t decode_ident(const uint8_t *bytes, size_t len, uint8_t code, lms_ident_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    lms_telegram_t t;
    const lms_status_t st =
        parse_reply(bytes, len, code, LMS_TYPE_TEXT_SIZE, LMS_TYPE_TEXT_SIZE, &t);
    if (st != LMS_OK) {
        return st;
    }
    out->address = t.address;
    out->status = t.status;
    copy_text(out->text, t.data, LMS_TYPE_TEXT_SIZE);
    return LMS_OK;
}

lms_status_t lms_decode_power_on(const uint8_t *bytes, size_t len, lms_ident_t *out)
{
    return decode_ident(bytes, len, LMS_REPLY_POWER_ON, out);
}

lms_status_t lms_decode_type(const uint8_t *bytes, size_t len, lms_ident_t *out)
{
    return decode_ident(bytes, len, LMS_REPLY_TYPE, out);
}

static lms_status_t decode_bare(const uint8_t *bytes, size_t len, uint8_t code,
                                lms_bare_reply_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    lms_telegram_t t;
    const lms_status_t st = parse_reply(bytes, len, code, 0u, 0u, &t);
    if (st != LMS_OK) {
        return st;
    }
    out->address = t.address;
    out->status = t.status;
    return LMS_OK;
}

lms_status_t lms_decode_reset_ack(const uint8_t *bytes, size_t len, lms_bare_reply_t *out)
{
    return decode_bare(bytes, len, LMS_REPLY_RESET_ACK, out);
}

lms_status_t lms_decode_not_ack(const uint8_t *bytes, size_t len, lms_bare_reply_t *out)
{
    return decode_bare(bytes, len, LMS_REPLY_NOT_ACK, out);
}

/* Baud words of B1 offset 115 (low byte = 1 MHz / baud - 1). */
static bool baud_from_word(uint16_t word, lms_baud_t *baud)
{
    switch (word) {
    case 0x8067u:
        *baud = LMS_BAUD_9600;
        return true;
    case 0x8033u:
        *baud = LMS_BAUD_19200;
        return true;
    case 0x8019u:
        *baud = LMS_BAUD_38400;
        return true;
    case 0x8001u:
        *baud = LMS_BAUD_500000;
        return true;
    default:
        return false;
    }
}

lms_status_t lms_decode_status(const uint8_t *bytes, size_t len, lms_device_status_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    lms_telegram_t t;
    const lms_status_t st =
        parse_reply(bytes, len, LMS_REPLY_STATUS, LMS_STATUS_DATA_SIZE, LMS_STATUS_DATA_SIZE, &t);
    if (st != LMS_OK) {
        return st;
    }
    const uint8_t *d = t.data;
    out->address = t.address;
    out->status = t.status;
    copy_text(out->firmware, &d[STATUS_OFF_FIRMWARE], STATUS_FIRMWARE_SIZE);
    out->operating_mode = d[STATUS_OFF_OPERATING_MODE];
    out->device_status = d[STATUS_OFF_DEVICE_STATUS];
    out->meas_mode = d[STATUS_OFF_MEAS_MODE];
    out->angle_deg = get_u16(d, STATUS_OFF_ANGLE);
    out->resolution_cdeg = get_u16(d, STATUS_OFF_RESOLUTION);
    out->baud_word = get_u16(d, STATUS_OFF_BAUD);
    out->baud_known = baud_from_word(out->baud_word, &out->baud);
    out->permanent_baud = d[STATUS_OFF_PERMANENT_BAUD] != 0u;
    out->scanner_address = d[STATUS_OFF_ADDRESS];
    out->units = d[STATUS_OFF_UNITS];
    out->laser_on = d[STATUS_OFF_LASER] != 0u;
    return LMS_OK;
}

/* Result bytes of BB and F7: 01 accepted, 00 refused. */
static lms_status_t accepted_from_result(uint8_t result, bool *accepted)
{
    if (result > 1u) {
        return LMS_ERR_VALUE;
    }
    *accepted = result == 1u;
    return LMS_OK;
}

lms_status_t lms_decode_variant_reply(const uint8_t *bytes, size_t len, lms_variant_reply_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    lms_telegram_t t;
    lms_status_t st = parse_reply(bytes, len, LMS_REPLY_VARIANT, 5u, 5u, &t);
    if (st == LMS_OK) {
        st = accepted_from_result(t.data[0], &out->accepted);
    }
    if (st != LMS_OK) {
        memset(out, 0, sizeof *out);
        return st;
    }
    out->address = t.address;
    out->status = t.status;
    out->angle_deg = get_u16(t.data, 1u);
    out->resolution_cdeg = get_u16(t.data, 3u);
    return LMS_OK;
}

static void copy_config(lms_config_t *cfg, const uint8_t *block, uint16_t size)
{
    memcpy(cfg->block, block, size);
    cfg->size = (uint8_t)size;
}

lms_status_t lms_decode_config(const uint8_t *bytes, size_t len, lms_config_reply_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    lms_telegram_t t;
    const lms_status_t st =
        parse_reply(bytes, len, LMS_REPLY_CONFIG, LMS_CONFIG_SIZE_OLD, LMS_CONFIG_SIZE_NEW, &t);
    if (st != LMS_OK) {
        return st;
    }
    if (t.data_len != LMS_CONFIG_SIZE_OLD && t.data_len != LMS_CONFIG_SIZE_NEW) {
        return LMS_ERR_SIZE;
    }
    out->address = t.address;
    out->status = t.status;
    copy_config(&out->config, t.data, t.data_len);
    return LMS_OK;
}

lms_status_t lms_decode_config_write_reply(const uint8_t *bytes, size_t len,
                                           lms_config_write_reply_t *out)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    lms_telegram_t t;
    lms_status_t st = parse_reply(bytes, len, LMS_REPLY_CONFIG_WRITE, 1u + LMS_CONFIG_SIZE_OLD,
                                  1u + LMS_CONFIG_SIZE_NEW, &t);
    if (st == LMS_OK && t.data_len != 1u + LMS_CONFIG_SIZE_OLD &&
        t.data_len != 1u + LMS_CONFIG_SIZE_NEW) {
        st = LMS_ERR_SIZE;
    }
    if (st == LMS_OK) {
        st = accepted_from_result(t.data[0], &out->accepted);
    }
    if (st != LMS_OK) {
        memset(out, 0, sizeof *out);
        return st;
    }
    out->address = t.address;
    out->status = t.status;
    copy_config(&out->config, &t.data[1], (uint16_t)(t.data_len - 1u));
    return LMS_OK;
}
