/* gen_common.h - pieces the host-side generators (lmsgen, lmsworld) share:
 * a growable byte buffer written to a file at the end, and strict
 * parsing of unsigned options. Host-only (heap and stdio are fine here).
 * Messages start with gen_program ("lmsgen", "lmsworld"), which each
 * program sets first thing in main. */
#ifndef GEN_COMMON_H
#define GEN_COMMON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

extern const char *gen_program;

typedef struct {
    uint8_t *data;
    size_t len;
    size_t cap;
} buf_t;

void buf_free(buf_t *b);

/* Appends n bytes; out of memory ends the program (exit status 1). */
void buf_append(buf_t *b, const void *bytes, size_t n);

/* Writes the whole buffer to path; 0, or -1 after a one-line message. */
int write_file(const char *path, const buf_t *b);

/* A decimal unsigned integer, the whole text, at most max. */
bool parse_unsigned(const char *text, uint64_t max, uint64_t *out);

#endif /* GEN_COMMON_H */
