/* scan_file.c - see scan_file.h. */
#include "scan_file.h"

#include <stdio.h>
#include <stdlib.h>

#include "lms_framer.h"

size_t scan_file_load(const char *path, lms_scan_t *scans, size_t max)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        (void)fprintf(stderr, "cannot open '%s'\n", path);
        exit(1);
    }
    static lms_framer_t framer;
    lms_framer_init(&framer, LMS_FROM_SCANNER);
    size_t n = 0u;
    uint8_t chunk[4096];
    int done = 0;
    while (!done) {
        const size_t got = fread(chunk, 1u, sizeof chunk, f);
        done = got == 0u; /* then flush what the framer holds */
        size_t off = 0u;
        for (;;) {
            size_t used = 0u;
            const lms_framer_event_t ev = done ? lms_framer_flush(&framer)
                                               : lms_framer_feed(&framer, chunk + off, got - off,
                                                                 &used);
            off += used;
            if (ev == LMS_FRAMER_NEED_MORE) {
                break;
            }
            size_t len = 0u;
            const uint8_t *t = lms_framer_telegram(&framer, &len);
            if (t != NULL && n < max && lms_decode_scan(t, len, &scans[n]) == LMS_OK) {
                n++;
            }
        }
    }
    (void)fclose(f);
    return n;
}
