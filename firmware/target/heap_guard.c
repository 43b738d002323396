/* heap_guard.c - the firmware has no heap. newlib's allocator (pulled in by
 * any stdio, for instance) calls _sbrk; this _sbrk needs a symbol that
 * exists nowhere, so an image that uses the heap fails to link ("undefined
 * reference to lmsego_firmware_has_no_heap"). An image that does not is
 * unaffected: --gc-sections drops the unused function. */
#include <stddef.h>

void *_sbrk(ptrdiff_t increment);

extern char lmsego_firmware_has_no_heap[];

void *_sbrk(ptrdiff_t increment)
{
    return lmsego_firmware_has_no_heap + increment;
}
