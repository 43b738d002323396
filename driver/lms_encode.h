/* lms_encode.h - building LMS 2xx telegrams: host commands, and the
 * scanner's replies (for the simulated scanner, the stream generator and
 * tests).
 *
 * Every builder writes a complete telegram, STX .. CRC, into storage the
 * caller owns, and returns LMS_ERR_ARG (writing nothing useful) for an
 * argument outside the protocol: a host address above 0x7F, a variant that
 * is not one of the five legal pairs, a mode that needs parameters. Pure,
 * reentrant.
 */
#ifndef LMS_ENCODE_H
#define LMS_ENCODE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lms_config.h"
#include "lms_decode.h"
#include "lms_proto.h"

/* Writes STX, address, L = payload_len (+1 when status_or_neg >= 0),
 * payload, the status byte when status_or_neg >= 0, and the CRC.
 * *written (may be NULL) gets the total size. LMS_ERR_ARG when it does not fit in cap,
 * when payload_len is 0 or L would exceed LMS_LENGTH_MAX. */
lms_status_t lms_telegram_write(uint8_t *out, size_t cap, uint8_t address,
                                const uint8_t *payload, size_t payload_len,
                                int status_or_neg, size_t *written);

/* A host command, at most LMS_CMD_MAX bytes. */
typedef struct {
    uint8_t bytes[LMS_CMD_MAX];
    uint8_t len;
} lms_cmd_t;

/* 20 <mode>: for the modes without parameters (24, 25, 2A and the four
 * baud codes). LMS_MODE_INSTALLATION needs lms_cmd_installation. */
lms_status_t lms_cmd_mode(lms_cmd_t *out, uint8_t address, lms_mode_t mode);

/* 20 00 <password>: password is a NUL-terminated string of exactly 8
 * characters (LMS_ERR_ARG otherwise; read no further than its NUL), or
 * NULL for the default "SICK_LMS". */
lms_status_t lms_cmd_installation(lms_cmd_t *out, uint8_t address, const char *password);

/* 20 42 / 41 / 40 / 48: switch the line rate. */
lms_status_t lms_cmd_baud(lms_cmd_t *out, uint8_t address, lms_baud_t baud);

/* 30 01: one scan of all values, on request. */
lms_status_t lms_cmd_request_values(lms_cmd_t *out, uint8_t address);

/* 31: status (reply B1). */
lms_status_t lms_cmd_status(lms_cmd_t *out, uint8_t address);

/* 32: error telegram (reply B2), a harmless probe. */
lms_status_t lms_cmd_errors(lms_cmd_t *out, uint8_t address);

/* 3A: type string (reply BA). */
lms_status_t lms_cmd_type(lms_cmd_t *out, uint8_t address);

/* 10: software reset (replies 91, later 90). */
lms_status_t lms_cmd_reset(lms_cmd_t *out, uint8_t address);

/* 3B <angle u16> <resolution u16>: 180 deg at 100 or 50 cdeg, or 100 deg
 * at 100, 50 or 25 cdeg; nothing else. */
lms_status_t lms_cmd_variant(lms_cmd_t *out, uint8_t address, uint16_t angle_deg,
                             uint16_t resolution_cdeg);

/* 74: read the configuration block (reply F4). */
lms_status_t lms_cmd_config_read(lms_cmd_t *out, uint8_t address);

/* 77 <block>: write the configuration block back at its own size (32 or
 * 34 bytes). Needs installation mode on the scanner. */
lms_status_t lms_cmd_config_write(lms_cmd_t *out, uint8_t address, const lms_config_t *cfg);

/* True for the five legal (angle, resolution) variant pairs. */
bool lms_variant_is_legal(uint16_t angle_deg, uint16_t resolution_cdeg);

/* --- Scanner side ------------------------------------------------------ */

/* A B0 telegram from a scan: count word from count, unit, is_partial and
 * partial_index (as given, so that what lms_decode_scan read comes back
 * bit for bit; only the reserved bit 10 is always 0); real-time indices
 * when has_indices; then status. written may be NULL. address
 * must have bit 7 set. LMS_ERR_ARG for count > LMS_SCAN_MAX_VALUES,
 * partial_index > 3 or cap < 2 * count + 10 (+ 2). */
lms_status_t lms_encode_scan(uint8_t *out, size_t cap, uint8_t address, const lms_scan_t *scan,
                             size_t *written);

#endif /* LMS_ENCODE_H */
