/* probe_heap.c - an image that uses the heap, which must not link
 * (heap_guard.c): ctest target_heap_guard builds it and expects the link
 * to fail on lmsego_firmware_has_no_heap. Not part of `all`. */
#include <stdlib.h>

#include "target.h"

int main(void)
{
    char *p = malloc(16u);
    target_exit(p != NULL ? TARGET_EXIT_OK : TARGET_EXIT_FAILED);
}
