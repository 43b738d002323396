/* gen_common.c - see gen_common.h. */
#include "gen_common.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *gen_program = "generator";

void buf_free(buf_t *b)
{
    free(b->data);
    b->data = NULL;
    b->len = 0u;
    b->cap = 0u;
}

void buf_append(buf_t *b, const void *bytes, size_t n)
{
    if (n == 0u) {
        return;
    }
    if (b->len + n > b->cap) {
        size_t cap = (b->cap != 0u) ? b->cap : 4096u;
        while (cap < b->len + n) {
            cap *= 2u;
        }
        uint8_t *grown = realloc(b->data, cap);
        if (grown == NULL) {
            (void)fprintf(stderr, "%s: out of memory\n", gen_program);
            exit(1);
        }
        b->data = grown;
        b->cap = cap;
    }
    memcpy(b->data + b->len, bytes, n);
    b->len += n;
}

int write_file(const char *path, const buf_t *b)
{
    FILE *fp = fopen(path, "wb");
    if (fp == NULL) {
        (void)fprintf(stderr, "%s: cannot create '%s': %s\n", gen_program, path, strerror(errno));
        return -1;
    }
    const size_t written = (b->len > 0u) ? fwrite(b->data, 1u, b->len, fp) : 0u;
    const int closed = fclose(fp);
    if (written != b->len || closed != 0) {
        (void)fprintf(stderr, "%s: error writing '%s'\n", gen_program, path);
        return -1;
    }
    return 0;
}

bool parse_unsigned(const char *text, uint64_t max, uint64_t *out)
{
    if (text[0] < '0' || text[0] > '9') {
        return false;
    }
    errno = 0;
    char *end = NULL;
    const unsigned long long value = strtoull(text, &end, 10);
    if (errno != 0 || *end != '\0' || value > max) {
        return false;
    }
    *out = (uint64_t)value;
    return true;
}
