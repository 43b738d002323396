/* lms_encode.c - see lms_encode.h. */
#include "lms_encode.h"

#include <string.h>

#include "lms_crc.h"

#define HOST_ADDRESS_MAX 0x7Fu
#define PASSWORD_SIZE 8u
#define REQUEST_ALL_VALUES 0x01u

static void put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}

lms_status_t lms_telegram_write(uint8_t *out, size_t cap, uint8_t address,
                                const uint8_t *payload, size_t payload_len,
                                int status_or_neg, size_t *written)
{
    if (written != NULL) {
        *written = 0u;
    }
    if (out == NULL || payload == NULL || payload_len == 0u) {
        return LMS_ERR_ARG;
    }
    const bool has_status = status_or_neg >= 0;
    if (status_or_neg > 0xFF) {
        return LMS_ERR_ARG;
    }
    const size_t field = payload_len + (has_status ? 1u : 0u);
    if (field > LMS_LENGTH_MAX || cap < field + LMS_OVERHEAD) {
        return LMS_ERR_ARG;
    }
    out[0] = LMS_STX;
    out[1] = address;
    put_u16(&out[2], (uint16_t)field);
    memcpy(&out[LMS_HEADER_SIZE], payload, payload_len);
    if (has_status) {
        out[LMS_HEADER_SIZE + payload_len] = (uint8_t)status_or_neg;
    }
    const size_t body = LMS_HEADER_SIZE + field;
    put_u16(&out[body], lms_crc16(out, body));
    if (written != NULL) {
        *written = body + LMS_CRC_SIZE;
    }
    return LMS_OK;
}

/* An illegal argument: an empty command and LMS_ERR_ARG. */
static lms_status_t reject_cmd(lms_cmd_t *out)
{
    if (out != NULL) {
        memset(out, 0, sizeof *out);
    }
    return LMS_ERR_ARG;
}

/* A host command from its payload (code + data). */
static lms_status_t build_cmd(lms_cmd_t *out, uint8_t address, const uint8_t *payload,
                              size_t payload_len)
{
    if (out == NULL) {
        return LMS_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    if (address > HOST_ADDRESS_MAX) {
        return LMS_ERR_ARG;
    }
    size_t written = 0u;
    const lms_status_t st = lms_telegram_write(out->bytes, sizeof out->bytes, address, payload,
                                               payload_len, -1, &written);
    out->len = (uint8_t)written;
    return st;
}

static bool mode_has_no_parameters(lms_mode_t mode)
{
    switch (mode) {
    case LMS_MODE_STREAM_ALL:
    case LMS_MODE_ON_REQUEST:
    case LMS_MODE_STREAM_PARTIAL:
    case LMS_MODE_BAUD_38400:
    case LMS_MODE_BAUD_19200:
    case LMS_MODE_BAUD_9600:
    case LMS_MODE_BAUD_500000:
        return true;
    case LMS_MODE_INSTALLATION:
        return false;
    }
    return false;
}

lms_status_t lms_cmd_mode(lms_cmd_t *out, uint8_t address, lms_mode_t mode)
{
    if (!mode_has_no_parameters(mode)) {
        return reject_cmd(out);
    }
    const uint8_t payload[] = {LMS_CMD_MODE, (uint8_t)mode};
    return build_cmd(out, address, payload, sizeof payload);
}

lms_status_t lms_cmd_installation(lms_cmd_t *out, uint8_t address, const char *password)
{
    static const char default_password[PASSWORD_SIZE] = {'S', 'I', 'C', 'K', '_', 'L', 'M', 'S'};
    const char *pw = default_password;
    if (password != NULL) {
        for (size_t i = 0u; i < PASSWORD_SIZE; i++) {
            if (password[i] == '\0') {
                return reject_cmd(out); /* too short */
            }
        }
        if (password[PASSWORD_SIZE] != '\0') {
            return reject_cmd(out); /* too long */
        }
        pw = password;
    }
    uint8_t payload[2u + PASSWORD_SIZE];
    payload[0] = LMS_CMD_MODE;
    payload[1] = (uint8_t)LMS_MODE_INSTALLATION;
    for (size_t i = 0u; i < PASSWORD_SIZE; i++) {
        payload[2u + i] = (uint8_t)pw[i];
    }
    return build_cmd(out, address, payload, sizeof payload);
}

lms_status_t lms_cmd_baud(lms_cmd_t *out, uint8_t address, lms_baud_t baud)
{
    switch (baud) {
    case LMS_BAUD_9600:
        return lms_cmd_mode(out, address, LMS_MODE_BAUD_9600);
    case LMS_BAUD_19200:
        return lms_cmd_mode(out, address, LMS_MODE_BAUD_19200);
    case LMS_BAUD_38400:
        return lms_cmd_mode(out, address, LMS_MODE_BAUD_38400);
    case LMS_BAUD_500000:
        return lms_cmd_mode(out, address, LMS_MODE_BAUD_500000);
    }
    return reject_cmd(out);
}

lms_status_t lms_cmd_request_values(lms_cmd_t *out, uint8_t address)
{
    const uint8_t payload[] = {LMS_CMD_REQUEST_VALUES, REQUEST_ALL_VALUES};
    return build_cmd(out, address, payload, sizeof payload);
}

static lms_status_t bare_cmd(lms_cmd_t *out, uint8_t address, uint8_t code)
{
    return build_cmd(out, address, &code, 1u);
}

lms_status_t lms_cmd_status(lms_cmd_t *out, uint8_t address)
{
    return bare_cmd(out, address, LMS_CMD_STATUS);
}

lms_status_t lms_cmd_errors(lms_cmd_t *out, uint8_t address)
{
    return bare_cmd(out, address, LMS_CMD_ERRORS);
}

lms_status_t lms_cmd_type(lms_cmd_t *out, uint8_t address)
{
    return bare_cmd(out, address, LMS_CMD_TYPE);
}

lms_status_t lms_cmd_reset(lms_cmd_t *out, uint8_t address)
{
    return bare_cmd(out, address, LMS_CMD_RESET);
}

lms_status_t lms_cmd_config_read(lms_cmd_t *out, uint8_t address)
{
    return bare_cmd(out, address, LMS_CMD_CONFIG_READ);
}

bool lms_variant_is_legal(uint16_t angle_deg, uint16_t resolution_cdeg)
{
    if (angle_deg == 180u) {
        return resolution_cdeg == 100u || resolution_cdeg == 50u;
    }
    if (angle_deg == 100u) {
        return resolution_cdeg == 100u || resolution_cdeg == 50u || resolution_cdeg == 25u;
    }
    return false;
}

lms_status_t lms_cmd_variant(lms_cmd_t *out, uint8_t address, uint16_t angle_deg,
                             uint16_t resolution_cdeg)
{
    if (!lms_variant_is_legal(angle_deg, resolution_cdeg)) {
        return reject_cmd(out);
    }
    uint8_t payload[5];
    payload[0] = LMS_CMD_VARIANT;
    put_u16(&payload[1], angle_deg);
    put_u16(&payload[3], resolution_cdeg);
    return build_cmd(out, address, payload, sizeof payload);
}

lms_status_t lms_cmd_config_write(lms_cmd_t *out, uint8_t address, const lms_config_t *cfg)
{
    if (cfg == NULL || (cfg->size != LMS_CONFIG_SIZE_OLD && cfg->size != LMS_CONFIG_SIZE_NEW)) {
        return reject_cmd(out);
    }
    uint8_t payload[1u + LMS_CONFIG_SIZE_MAX];
    payload[0] = LMS_CMD_CONFIG_WRITE;
    memcpy(&payload[1], cfg->block, cfg->size);
    return build_cmd(out, address, payload, 1u + (size_t)cfg->size);
}

lms_status_t lms_encode_scan(uint8_t *out, size_t cap, uint8_t address, const lms_scan_t *scan,
                             size_t *written)
{
    if (written != NULL) {
        *written = 0u;
    }
    if (out == NULL || scan == NULL || (address & LMS_ADDR_REPLY_BIT) == 0u ||
        scan->count > LMS_SCAN_MAX_VALUES || scan->partial_index > 3u ||
        (scan->unit != LMS_UNIT_CM && scan->unit != LMS_UNIT_MM)) {
        return LMS_ERR_ARG;
    }
    const size_t field = 4u + 2u * (size_t)scan->count + (scan->has_indices ? 2u : 0u);
    if (cap < field + LMS_OVERHEAD) {
        return LMS_ERR_ARG;
    }
    /* The payload is written in place after the header: code, count word,
     * values, optional indices; lms_telegram_write then adds the rest. To
     * avoid a second scan-sized buffer, build the telegram directly. */
    uint16_t count_word = (uint16_t)(scan->count | ((unsigned)scan->unit << 14) |
                                     ((unsigned)scan->partial_index << 11));
    if (scan->is_partial) {
        count_word = (uint16_t)(count_word | 0x2000u);
    }
    out[0] = LMS_STX;
    out[1] = address;
    put_u16(&out[2], (uint16_t)field);
    size_t at = LMS_HEADER_SIZE;
    out[at++] = LMS_REPLY_VALUES;
    put_u16(&out[at], count_word);
    at += 2u;
    for (uint16_t i = 0u; i < scan->count; i++) {
        put_u16(&out[at], scan->values[i]);
        at += 2u;
    }
    if (scan->has_indices) {
        out[at++] = scan->scan_index;
        out[at++] = scan->telegram_index;
    }
    out[at++] = scan->status;
    put_u16(&out[at], lms_crc16(out, at));
    at += LMS_CRC_SIZE;
    if (written != NULL) {
        *written = at;
    }
    return LMS_OK;
}
