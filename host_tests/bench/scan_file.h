/* scan_file.h - every B0 scan of a recorded telegram stream, decoded into
 * memory (host-only helper of the benchmarks and experiments). */
#ifndef SCAN_FILE_H
#define SCAN_FILE_H

#include <stddef.h>

#include "lms_decode.h"

/* Decodes up to max scans of the stream at path into scans[]; returns how
 * many. An unreadable file ends the program with a message (status 1). */
size_t scan_file_load(const char *path, lms_scan_t *scans, size_t max);

#endif /* SCAN_FILE_H */
