/* lms_vectors.h - the published/synthetic LMS 2xx test vectors V01..V35
 * (host_tests/data/vectors/lms2xx-vectors.txt), embedded as C arrays so
 * the tests depend on neither files nor the working directory.
 */
#ifndef LMS_VECTORS_H
#define LMS_VECTORS_H

#include <stddef.h>
#include <stdint.h>

#include "lms_framer.h"

#define LMS_VECTOR_COUNT 35u

typedef struct {
    const char *id;            /* "V01" .. "V35", also the assertion message */
    lms_direction_t direction; /* LMS_FROM_HOST for H>S, LMS_FROM_SCANNER for S>H */
    const uint8_t *bytes;      /* complete telegram, STX .. CRC */
    size_t len;
    const char *desc;
} lms_vector_t;

/* In file order: lms_vectors[0] is V01, lms_vectors[34] is V35. */
extern const lms_vector_t lms_vectors[LMS_VECTOR_COUNT];

/* The vector with that ID, or NULL. */
const lms_vector_t *lms_vector_find(const char *id);

#endif /* LMS_VECTORS_H */
