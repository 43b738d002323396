/* lms_proto.h - SICK LMS 2xx serial protocol: constants, codes, status.
 *
 * Facts from docs/protocol.md (which cites ../shared/reference/lms2xx-protocol.md).
 * Every capacity here is a compile-time constant; override the LMS_*_MAX
 * defaults from the build only upwards (static assertions check the ties).
 */
#ifndef LMS_PROTO_H
#define LMS_PROTO_H

#include <stdint.h>

/* Framing bytes. */
#define LMS_STX 0x02u /* start of every telegram; there is no ETX */
#define LMS_ACK 0x06u /* single byte: host telegram received with good CRC */
#define LMS_NAK 0x15u /* single byte: host telegram had a bad CRC/framing */

/* Header = STX, address, length (u16 LE); trailer = CRC (u16 LE). */
#define LMS_HEADER_SIZE 4u
#define LMS_CRC_SIZE 2u
#define LMS_OVERHEAD (LMS_HEADER_SIZE + LMS_CRC_SIZE)

/* Largest measured-values telegram: 401 values (100 deg / 0.25 deg). */
#ifndef LMS_SCAN_MAX_VALUES
#define LMS_SCAN_MAX_VALUES 401u
#endif

/* Largest length field L accepted (code .. status): a B0 with the maximum
 * number of values and real-time indices, 1 + 2 + 2N + 2 + 1. */
#define LMS_LENGTH_MAX (2u * LMS_SCAN_MAX_VALUES + 6u)
/* Largest whole telegram, STX .. CRC (814 bytes for 401 values). */
#define LMS_TELEGRAM_MAX (LMS_LENGTH_MAX + LMS_OVERHEAD)

_Static_assert(LMS_SCAN_MAX_VALUES >= 401u, "an LMS 2xx scan can hold 401 values");
_Static_assert(LMS_SCAN_MAX_VALUES <= 1023u, "the count word holds at most 10 bits");

/* Address byte: hosts send 0x00 (broadcast) or 0x01..0x7F; every scanner
 * reply carries 0x80 | its own address. */
#define LMS_ADDR_BROADCAST 0x00u
#define LMS_ADDR_REPLY_BIT 0x80u

/* Host command codes. */
#define LMS_CMD_RESET 0x10u
#define LMS_CMD_MODE 0x20u
#define LMS_CMD_REQUEST_VALUES 0x30u
#define LMS_CMD_STATUS 0x31u
#define LMS_CMD_ERRORS 0x32u
#define LMS_CMD_TYPE 0x3Au
#define LMS_CMD_VARIANT 0x3Bu
#define LMS_CMD_PERMANENT_BAUD 0x66u /* never sent by this project */
#define LMS_CMD_CONFIG_READ 0x74u
#define LMS_CMD_CONFIG_WRITE 0x77u

/* Scanner reply codes. */
#define LMS_REPLY_POWER_ON 0x90u
#define LMS_REPLY_RESET_ACK 0x91u
#define LMS_REPLY_NOT_ACK 0x92u
#define LMS_REPLY_MODE 0xA0u
#define LMS_REPLY_VALUES 0xB0u
#define LMS_REPLY_STATUS 0xB1u
#define LMS_REPLY_ERRORS 0xB2u
#define LMS_REPLY_TYPE 0xBAu
#define LMS_REPLY_VARIANT 0xBBu
#define LMS_REPLY_CONFIG 0xF4u
#define LMS_REPLY_CONFIG_WRITE 0xF7u

/* Sizes of fixed-size replies, as the length field L counts them. */
#define LMS_TYPE_TEXT_SIZE 21u    /* ASCII identification in 90 and BA */
#define LMS_STATUS_DATA_SIZE 152u /* B1 data bytes */
#define LMS_CONFIG_SIZE_OLD 32u   /* F4/77 block, older firmware */
#define LMS_CONFIG_SIZE_NEW 34u   /* F4/77 block, Telegram Listing 2006 */
#define LMS_CONFIG_SIZE_MAX LMS_CONFIG_SIZE_NEW

/* Largest host telegram this project builds: 77 + a 34-byte block. */
#define LMS_CMD_MAX (LMS_OVERHEAD + 1u + LMS_CONFIG_SIZE_MAX)

/* Status codes shared by the driver's functions. 0 is success, negative
 * values are errors; no function returns a positive status. */
typedef enum {
    LMS_OK = 0,
    LMS_ERR_ARG = -1,   /* NULL pointer, or an argument outside its legal set */
    LMS_ERR_FRAME = -2, /* not a telegram: no STX, or L disagrees with the size */
    LMS_ERR_CRC = -3,   /* CRC mismatch */
    LMS_ERR_CODE = -4,  /* a telegram, but not the reply code asked for */
    LMS_ERR_SIZE = -5,  /* the right code, but the wrong size for it */
    LMS_ERR_VALUE = -6  /* a field holds a value the protocol reserves */
} lms_status_t;

/* Short English name of a status, for messages ("crc mismatch"). */
const char *lms_status_name(lms_status_t status);

/* Measuring units (count-word bits 14-15, status offset 121, config E). */
typedef enum {
    LMS_UNIT_CM = 0,
    LMS_UNIT_MM = 1
} lms_unit_t;

/* Measuring mode (configuration block D): which bits of a value word are
 * distance and what the upper bits mean. */
typedef enum {
    LMS_MEAS_8M_FIELDS_DAZZLE = 0x00, /* 13 bits; 13 field A, 14 field B, 15 dazzle */
    LMS_MEAS_8M_REFLECTOR = 0x01,     /* 13 bits; 13-15 reflector level 0-7 */
    LMS_MEAS_8M_FIELDS_ABC = 0x02,    /* 13 bits; 13 field A, 14 field B, 15 field C */
    LMS_MEAS_16M_REFLECTOR = 0x03,    /* 14 bits; 14-15 reflector level 0-3 */
    LMS_MEAS_16M_FIELDS_AB = 0x04,    /* 14 bits; 14 field A, 15 field B */
    LMS_MEAS_32M_REFLECTOR = 0x05,    /* 15 bits; 15 reflector */
    LMS_MEAS_32M_FIELD_A = 0x06,      /* 15 bits; 15 field A */
    LMS_MEAS_32M_IMMEDIATE = 0x0F,    /* 16 bits, no flags, no special values */
    LMS_MEAS_REFLECTIVITY = 0x3F      /* values are reflectivity, not ranges */
} lms_meas_mode_t;

/* Distance bits of a value word in a measuring mode: 13, 14, 15 or 16;
 * 0 for a code that is not a measuring mode. */
unsigned lms_meas_mode_bits(uint8_t mode);

/* Line rates the scanner supports. */
typedef enum {
    LMS_BAUD_9600 = 0,
    LMS_BAUD_19200 = 1,
    LMS_BAUD_38400 = 2,
    LMS_BAUD_500000 = 3
} lms_baud_t;

#define LMS_BAUD_COUNT 4u

/* Bits per second of a rate (9600 .. 500000); 0 for an unknown enum. */
uint32_t lms_baud_bps(lms_baud_t baud);

/* The mirror time of a scan of this many values, in microseconds: one
 * turn (13.3 ms, 75 Hz) per pass of 1-degree steps, so 361 and 201 values
 * (0.5 deg, two interlaced turns) take 26.7 ms and 401 values (0.25 deg,
 * four) 53.3 ms; every other count, partial scans included, one turn. The
 * one place that knows the scan period (the session adds the line's limit
 * at slow rates). */
uint32_t lms_scan_period_us(uint16_t values);

/* Time the line takes to carry this many bytes back to back at a rate
 * (8N1: 10 bit times a byte), microseconds rounded down (a lower bound, so
 * that an arrival stamp minus it is never earlier than the first byte's
 * start); 0 for an unknown rate. 372 bytes (181 values) at 500 kbaud:
 * 7 440 us; 732 bytes (361 values) at 38400: 190 625 us. */
uint32_t lms_wire_us(uint32_t bytes, lms_baud_t baud);

/* Time between two B0 telegrams of this many values streamed at a rate:
 * the scan period (lms_scan_period_us), or the telegram's wire time
 * (2 * values + 12 bytes, real-time indices included) rounded up to whole
 * periods at a slow rate, where the scanner skips the scans the line
 * cannot carry. The period alone for an unknown rate. */
uint32_t lms_scan_interval_us(uint16_t values, lms_baud_t baud);

/* Operating modes (the byte after command 0x20) used by this project. */
typedef enum {
    LMS_MODE_INSTALLATION = 0x00,   /* needs the 8-byte password */
    LMS_MODE_STREAM_ALL = 0x24,     /* continuous output of all values */
    LMS_MODE_ON_REQUEST = 0x25,     /* values on request; stops a stream */
    LMS_MODE_STREAM_PARTIAL = 0x2A, /* continuous partial scans */
    LMS_MODE_BAUD_38400 = 0x40,
    LMS_MODE_BAUD_19200 = 0x41,
    LMS_MODE_BAUD_9600 = 0x42,
    LMS_MODE_BAUD_500000 = 0x48
} lms_mode_t;

#endif /* LMS_PROTO_H */
