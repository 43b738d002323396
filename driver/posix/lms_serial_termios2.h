/* lms_serial_termios2.h - Linux termios2 line rates (host-only, internal to
 * lms_posix; not part of the public contract).
 *
 * <asm/termbits.h>, which declares struct termios2, clashes with
 * <termios.h>, so the ioctl code lives alone in lms_serial_termios2.c and
 * talks to the rest through plain integers. Only built into the calls on
 * Linux (__linux__); elsewhere both functions return ENOTSUP.
 */
#ifndef LMS_SERIAL_TERMIOS2_H
#define LMS_SERIAL_TERMIOS2_H

#include <stdint.h>

/* Sets the input and output rate of fd to bps (the B constants for 9600,
 * 19200 and 38400, BOTHER with c_ispeed = c_ospeed = bps otherwise) and
 * leaves every other setting alone; then reads the output rate back into
 * *actual (a driver may round it). Returns 0 or an errno value. */
int lms_termios2_set_speed(int fd, uint32_t bps, uint32_t *actual);

/* The output rate of fd (c_ospeed). On a pseudo-terminal master Linux
 * answers with the slave's settings. Returns 0 or an errno value. */
int lms_termios2_get_speed(int fd, uint32_t *bps);

#endif /* LMS_SERIAL_TERMIOS2_H */
