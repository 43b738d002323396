/* lms_test_util.h - small helpers shared by the LMS 2xx unit tests:
 * a seeded PRNG, an independent telegram builder and byte checks.
 *
 * The telegram builder here deliberately does not use lms_telegram_write,
 * so decoder and framer tests do not depend on the encoder under test; it
 * uses lms_crc16 (checked against the published check values in
 * test_lms_crc.c).
 */
#ifndef LMS_TEST_UTIL_H
#define LMS_TEST_UTIL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* xorshift32 (Marsaglia 2003); state must be nonzero. Deterministic, so
 * every "random" test is reproducible from its seed. */
uint32_t tu_rand(uint32_t *state);
/* Uniform-ish value in [lo, hi] (hi >= lo; modulo bias is irrelevant here). */
uint32_t tu_rand_range(uint32_t *state, uint32_t lo, uint32_t hi);
uint8_t tu_rand_byte(uint32_t *state);

/* Writes STX, address, L = payload_len, payload, CRC (low byte first) into
 * out. payload must already hold the status byte for a reply. Returns the
 * total size, or 0 when it does not fit in cap. */
size_t tu_telegram(uint8_t *out, size_t cap, uint8_t address, const uint8_t *payload,
                   size_t payload_len);

/* Recomputes the two CRC bytes at the end of a len-byte telegram. */
void tu_fix_crc(uint8_t *telegram, size_t len);

/* True when the CRC at the end of a len-byte buffer matches its bytes. */
bool tu_crc_ok(const uint8_t *telegram, size_t len);

/* Little-endian 16-bit field helpers. */
uint16_t tu_get_le16(const uint8_t *p);
void tu_put_le16(uint8_t *p, uint16_t v);

/* True when all n bytes at p are zero. */
bool tu_all_zero(const void *p, size_t n);

#endif /* LMS_TEST_UTIL_H */
