/* lms_decode.h - pure decoders for LMS 2xx telegrams.
 *
 * Every decoder takes a complete telegram (STX .. CRC, as lms_framer
 * reports it, or any untrusted bytes) and checks everything again: STX,
 * length field against the size, CRC, reply code and the exact size for
 * that code. On success it fills *out and returns LMS_OK; on any error it
 * returns the status, *out is zeroed, and nothing else is touched.
 * Reentrant, no hidden state.
 */
#ifndef LMS_DECODE_H
#define LMS_DECODE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lms_config.h"
#include "lms_proto.h"

/* A checked telegram, pointing into the caller's bytes. */
typedef struct {
    uint8_t address;
    uint8_t code;
    const uint8_t *data; /* after the code, up to the status byte (replies)
                            or the CRC (host telegrams) */
    uint16_t data_len;
    bool is_reply;       /* address bit 7 set: the last byte is a status */
    uint8_t status;      /* status byte of a reply; 0 for host telegrams */
} lms_telegram_t;

/* Checks framing and CRC of any telegram, either direction. LMS_ERR_FRAME
 * for a missing STX, a size below 6 + 1 (+1 for a reply's status) or a
 * length field that disagrees with len; LMS_ERR_CRC for a bad CRC. */
lms_status_t lms_telegram_parse(const uint8_t *bytes, size_t len, lms_telegram_t *out);

/* The status byte that ends every reply. */
typedef struct {
    uint8_t raw;
    uint8_t severity;  /* bits 0-2: 0 ok, 1 info, 2 warning, 3 error, 4 fatal */
    bool restart;      /* bit 5 */
    bool implausible;  /* bit 6: implausible measured values */
    bool pollution;    /* bit 7: dirty front screen */
} lms_status_byte_t;

lms_status_byte_t lms_status_byte_decode(uint8_t raw);

/* --- B0: measured values --------------------------------------------- */

typedef struct {
    lms_unit_t unit;       /* count-word bits 14-15 (reserved codes are an error) */
    uint16_t count;        /* N, count-word bits 0-9 */
    uint16_t values[LMS_SCAN_MAX_VALUES]; /* raw value words, lms_value_decode */
    uint8_t address;
    uint8_t status;        /* status byte */
    bool is_partial;       /* count-word bit 13 */
    uint8_t partial_index; /* bits 11-12: offset of +0, 0.25, 0.5, 0.75 deg */
    bool has_indices;      /* L = 2N + 6: real-time indices present */
    uint8_t scan_index;    /* real-time scan index (mod 256) */
    uint8_t telegram_index;
} lms_scan_t;

/* LMS_ERR_SIZE when L is neither 2N + 4 nor 2N + 6 or N exceeds
 * LMS_SCAN_MAX_VALUES; LMS_ERR_VALUE for reserved units (bits 14-15 = 1x). */
lms_status_t lms_decode_scan(const uint8_t *bytes, size_t len, lms_scan_t *out);

/* What one value word means. The numbers of the special kinds are the
 * codes `lmsego scans` prints. */
typedef enum {
    LMS_VALUE_REFLECTIVITY = 1,  /* measuring mode 3F: not a range */
    LMS_VALUE_RANGE = 0,         /* a distance */
    LMS_VALUE_NO_RETURN = -1,    /* max code: no return / not valid */
    LMS_VALUE_DAZZLE = -2,       /* max - 1 */
    LMS_VALUE_OVERFLOW = -3,     /* max - 2: operation overflow */
    LMS_VALUE_LOW_SNR = -4,      /* max - 4 */
    LMS_VALUE_CHANNEL_ERROR = -5,/* max - 5: error reading channel 1 */
    LMS_VALUE_BEYOND_MAX = -7,   /* max - 8: beyond the maximum range */
    LMS_VALUE_RESERVED = -8      /* max - 3, - 6, - 7: other reserved codes */
} lms_value_kind_t;

typedef struct {
    lms_value_kind_t kind;
    uint32_t distance_mm; /* RANGE: the distance in mm; REFLECTIVITY: the raw
                             16-bit value; 0 for special values */
    uint8_t flags;        /* the bits above the distance bits, shifted down to
                             bit 0 (fields, dazzle, reflector level); set for
                             special values too */
} lms_value_t;

/* Splits a value word by measuring mode (lms_meas_mode_t) and scales it by
 * the unit. Modes 00-06 have 13/14/15 distance bits, and every code from
 * max - 8 to max is special (see lms_value_kind_t); 0F has 16 bits and no
 * special codes. LMS_ERR_ARG for an unknown mode or unit. */
lms_status_t lms_value_decode(uint16_t word, uint8_t meas_mode, lms_unit_t unit,
                              lms_value_t *out);

/* Every value of scan as a plain range in place: the distance bits of its
 * word, in the scan's unit, or 0 for a special code (the same split as
 * lms_value_decode; field flags and dazzle bits dropped). One pass, no
 * scaling: for a consumer that wants ranges only (the estimator's LMS
 * adapter). LMS_ERR_ARG for a NULL scan, an unknown mode or reflectivity
 * values (mode 3F: not ranges); the scan is then untouched. */
lms_status_t lms_scan_to_ranges(lms_scan_t *scan, uint8_t meas_mode);

/* Angular layout of a scan, in 1/100 degree, scanner convention (0 right,
 * 90 ahead, 180 left). */
typedef struct {
    uint16_t field_deg;  /* 180 or 100 */
    uint16_t start_cdeg; /* angle of value 0 */
    uint16_t step_cdeg;  /* between neighbouring values */
} lms_layout_t;

/* Layout from the value count: 181/361 values -> 180 deg field at 1/0.5
 * deg; 101/201/401 -> 100 deg field starting at 40 deg. A partial scan
 * (mode 2A) has 1-deg steps (181 or 101 values) shifted by
 * 0.25 deg * partial_index. LMS_ERR_VALUE for any other count. */
lms_status_t lms_scan_layout(const lms_scan_t *scan, lms_layout_t *out);

/* --- Replies to commands --------------------------------------------- */

/* A0: reply to 20 (mode / baud switch). */
typedef enum {
    LMS_MODE_RESULT_OK = 0,
    LMS_MODE_RESULT_BAD_PASSWORD = 1,
    LMS_MODE_RESULT_FAULT = 2
} lms_mode_result_t;

typedef struct {
    uint8_t address;
    uint8_t status;
    lms_mode_result_t result; /* LMS_ERR_VALUE for codes above 2 */
} lms_mode_reply_t;

lms_status_t lms_decode_mode_reply(const uint8_t *bytes, size_t len, lms_mode_reply_t *out);

/* 90 (power-on) and BA (type): 21 ASCII bytes, e.g. "LMS200;301063;V02.10 ". */
typedef struct {
    uint8_t address;
    uint8_t status;
    char text[LMS_TYPE_TEXT_SIZE + 1u]; /* NUL-terminated; non-printable bytes become '?' */
} lms_ident_t;

lms_status_t lms_decode_power_on(const uint8_t *bytes, size_t len, lms_ident_t *out);
lms_status_t lms_decode_type(const uint8_t *bytes, size_t len, lms_ident_t *out);

/* 91 (reset acknowledged) and 92 (not acknowledged): just a status. */
typedef struct {
    uint8_t address;
    uint8_t status;
} lms_bare_reply_t;

lms_status_t lms_decode_reset_ack(const uint8_t *bytes, size_t len, lms_bare_reply_t *out);
lms_status_t lms_decode_not_ack(const uint8_t *bytes, size_t len, lms_bare_reply_t *out);

/* B1: status (152 data bytes). Offsets in docs/protocol.md. */
typedef struct {
    uint8_t address;
    uint8_t status;
    char firmware[8];          /* offset 0, 7 ASCII bytes, NUL-terminated */
    uint8_t operating_mode;    /* offset 7, lms_mode_t codes */
    uint8_t device_status;     /* offset 8, nonzero = error */
    uint8_t meas_mode;         /* offset 101, lms_meas_mode_t codes */
    uint16_t angle_deg;        /* offset 106 */
    uint16_t resolution_cdeg;  /* offset 108 */
    uint16_t baud_word;        /* offset 115, raw */
    bool baud_known;           /* baud_word is one of the four rates */
    lms_baud_t baud;           /* valid when baud_known */
    bool permanent_baud;       /* offset 118 */
    uint8_t scanner_address;   /* offset 119 */
    uint8_t units;             /* offset 121: 0 cm, 1 mm, else reserved */
    bool laser_on;             /* offset 122 */
} lms_device_status_t;

lms_status_t lms_decode_status(const uint8_t *bytes, size_t len, lms_device_status_t *out);

/* BB: reply to 3B (variant). */
typedef struct {
    uint8_t address;
    uint8_t status;
    bool accepted;            /* result 01; 00 = refused, old variant active;
                                 other result bytes: LMS_ERR_VALUE */
    uint16_t angle_deg;       /* the variant now active */
    uint16_t resolution_cdeg;
} lms_variant_reply_t;

lms_status_t lms_decode_variant_reply(const uint8_t *bytes, size_t len, lms_variant_reply_t *out);

/* F4: configuration block (reply to 74). */
typedef struct {
    uint8_t address;
    uint8_t status;
    lms_config_t config;
} lms_config_reply_t;

lms_status_t lms_decode_config(const uint8_t *bytes, size_t len, lms_config_reply_t *out);

/* F7: reply to 77 (configuration written), with the block echoed. */
typedef struct {
    uint8_t address;
    uint8_t status;
    bool accepted;            /* result 01; 00 = refused; others: LMS_ERR_VALUE */
    lms_config_t config;      /* the echoed block */
} lms_config_write_reply_t;

lms_status_t lms_decode_config_write_reply(const uint8_t *bytes, size_t len,
                                           lms_config_write_reply_t *out);

#endif /* LMS_DECODE_H */
