/* lms_config.h - the LMS 2xx configuration block (read with 74 -> F4,
 * written with 77 -> F7).
 *
 * The block is kept as the bytes the scanner sent, so a read-modify-write
 * changes only the fields a setter touches. Older firmware sends 32 bytes,
 * the 2006 Telegram Listing 34; both are accepted and written back at the
 * size they were read. Offsets (from the first byte after the code):
 * 0-1 blanking, 2 stop threshold, 3 peak threshold / sensitivity,
 * 4 availability (bit 1 = send real-time indices), 5 measuring mode,
 * 6 measuring units (0 cm, 1 mm), 7.. fields, contours, restart times.
 */
#ifndef LMS_CONFIG_H
#define LMS_CONFIG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lms_proto.h"

#define LMS_CONFIG_OFF_AVAILABILITY 4u
#define LMS_CONFIG_OFF_MEAS_MODE 5u
#define LMS_CONFIG_OFF_UNITS 6u
#define LMS_CONFIG_AVAIL_RT_INDICES 0x02u

typedef struct {
    uint8_t block[LMS_CONFIG_SIZE_MAX];
    uint8_t size; /* LMS_CONFIG_SIZE_OLD or LMS_CONFIG_SIZE_NEW */
} lms_config_t;

/* Raw measuring-mode byte (block D); see lms_meas_mode_t. */
uint8_t lms_config_meas_mode(const lms_config_t *cfg);
/* Raw units byte (block E): 0 cm, 1 mm, other values reserved. */
uint8_t lms_config_units(const lms_config_t *cfg);
/* True when the scanner appends real-time indices to every B0. */
bool lms_config_has_indices(const lms_config_t *cfg);

/* Setters; LMS_ERR_ARG for a mode that lms_meas_mode_bits() does not know,
 * a unit other than cm/mm, or a block whose size is not 32 or 34. */
lms_status_t lms_config_set_meas_mode(lms_config_t *cfg, uint8_t meas_mode);
lms_status_t lms_config_set_unit(lms_config_t *cfg, lms_unit_t unit);
lms_status_t lms_config_set_indices(lms_config_t *cfg, bool on);

#endif /* LMS_CONFIG_H */
