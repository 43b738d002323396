/* lms_pty.h - the scanner's end of a pseudo-terminal, for the simulated
 * LMS 2xx and the hardware-in-loop player (host-only, POSIX).
 *
 * lms_pty_open creates a pseudo-terminal (posix_openpt, grantpt,
 * unlockpt), keeps the master side non-blocking, and gives the slave's
 * path: the "serial device" a driver opens. The slave starts raw 8N1 at
 * 9600 (the scanner's power-up rate), so nothing the simulator writes is
 * echoed or translated before a driver has configured the line. With a
 * link path it also creates a symbolic link there pointing at the slave
 * (replacing an older link, atomically: a new link renamed over it; a
 * file there that is not a symbolic link is left alone and the open fails
 * with EEXIST), like a udev name for a USB adapter; lms_pty_reopen then
 * emulates a hang-up and reconnect: it closes the master (the driver's
 * reads see a hang-up), opens a new pseudo-terminal and points the link at
 * it. If that fails, everything is closed and the link (still pointing at
 * the dead slave) is removed: the device is then missing.
 *
 * The pseudo-terminal keeps a descriptor of its own slave open
 * (slave_keep) for as long as the pair exists, so the line never reads as
 * hung up on the master side: not before anybody connected, and not while
 * a driver closes and reopens its port. (Linux cannot tell a master that
 * someone else opened the slave, so "until a driver has opened it" is not
 * implementable without polling; a real scanner cannot see the host close
 * its port either.) The master therefore never sees POLLHUP; bytes the
 * simulator writes while no driver listens wait in the slave's input
 * queue, and lms_serial_open discards them. Nobody reads slave_keep.
 *
 * lms_pty_host_baud reads the rate the driver set on the slave (termios2
 * c_ospeed on Linux, cfgetospeed otherwise) and maps it to an LMS rate; a
 * rate that is none of the four reads as "unknown" (the simulator then
 * garbles everything, as a real line would). On Linux, TCGETS2 on the
 * master answers with the slave's settings (tested in test_lms_posix.c);
 * elsewhere the master's termios may be its own (untested).
 *
 * Every descriptor is close-on-exec.
 */
#ifndef LMS_PTY_H
#define LMS_PTY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lms_proto.h"

typedef struct {
    int master;          /* -1 when closed */
    int slave_keep;      /* slave descriptor held open by us, -1 if none */
    char slave_path[128];
    char link_path[256]; /* empty: no link */
    int error;           /* errno of the last failure */
} lms_pty_t;

/* 0, or an errno value with nothing left open (ENAMETOOLONG for a link
 * path of 256 bytes or more, EEXIST for a non-link file at it). link may
 * be NULL. */
int lms_pty_open(lms_pty_t *pty, const char *link);

/* The path a driver should open: the link when there is one, else the
 * slave. */
const char *lms_pty_path(const lms_pty_t *pty);

/* Reads the host's line rate. Returns false (and leaves *baud) when the
 * rate is not one of the four LMS rates or cannot be read. */
bool lms_pty_host_baud(const lms_pty_t *pty, lms_baud_t *baud);

/* Hang-up and reconnect (see above); 0 or an errno value (then closed). */
int lms_pty_reopen(lms_pty_t *pty);

/* Closes everything and removes the link (if it still points at our
 * slave). Safe on a closed pseudo-terminal. */
void lms_pty_close(lms_pty_t *pty);

#endif /* LMS_PTY_H */
