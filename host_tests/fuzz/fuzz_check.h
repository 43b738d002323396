/* fuzz_check.h - what the fuzz targets share: the assertion, and the
 * input read as little-endian values.
 *
 * FUZZ_CHECK(cond) aborts when cond is false: libFuzzer reports the abort
 * as a crash and writes the input that caused it. A check is a property
 * the code under test promises for every input (its header's contract),
 * never a guess; each target's header comment lists its checks.
 */
#ifndef FUZZ_CHECK_H
#define FUZZ_CHECK_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#define FUZZ_CHECK(cond)      \
    do {                      \
        if (!(cond)) {        \
            abort();          \
        }                     \
    } while (0)

/* The fuzz bytes, read in order; a missing byte reads as 0. */
typedef struct {
    const uint8_t *data;
    size_t size;
    size_t pos;
} fuzz_input_t;

/* The next `bytes` (1..4) bytes as a little-endian value. */
static inline uint32_t fuzz_take(fuzz_input_t *in, unsigned bytes)
{
    uint32_t v = 0u;
    for (unsigned k = 0u; k < bytes; k++) {
        const uint32_t b = (in->pos < in->size) ? in->data[in->pos++] : 0u;
        v |= b << (8u * k);
    }
    return v;
}

#endif /* FUZZ_CHECK_H */
