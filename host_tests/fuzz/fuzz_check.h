/* fuzz_check.h - the one assertion the fuzz targets share.
 *
 * FUZZ_CHECK(cond) aborts when cond is false: libFuzzer reports the abort
 * as a crash and writes the input that caused it. A check is a property
 * the code under test promises for every input (its header's contract),
 * never a guess; each target's header comment lists its checks.
 */
#ifndef FUZZ_CHECK_H
#define FUZZ_CHECK_H

#include <stdlib.h>

#define FUZZ_CHECK(cond)      \
    do {                      \
        if (!(cond)) {        \
            abort();          \
        }                     \
    } while (0)

#endif /* FUZZ_CHECK_H */
