/* ego_config.h - compile-time capacities of the estimator.
 *
 * Override from the build (a compile definition on the estimator and
 * everything that includes it, e.g. the CMake cache variable
 * LMSEGO_MAX_BEAMS), never per file: the sizes of the caller's structs
 * depend on them.
 */
#ifndef EGO_CONFIG_H
#define EGO_CONFIG_H

/* Beams per scan: 720 holds a full turn at 0.5 deg (and every LMS 2xx
 * layout, 401 values at most). RAM grows by about 50 bytes per beam
 * (the input scan and the two prepared scans of ego_state_t), so a
 * microcontroller build for one sensor sets its own maximum. */
#ifndef EGO_MAX_BEAMS
#define EGO_MAX_BEAMS 720u
#endif

/* Points of a prepared scan: at most one per beam. */
#define EGO_MAX_POINTS EGO_MAX_BEAMS

/* Largest tangent-fit half window n (the fit uses 2n + 1 points). */
#ifndef EGO_TFIT_MAX_HALF_WINDOW
#define EGO_TFIT_MAX_HALF_WINDOW 5u
#endif

/* What the vehicle can do (ego.c, EGO_FLAG_SUSPECT): the dynamics filter
 * lets its velocity drift by a third of this a second at one sigma (this
 * at three), and a line beyond its gate is suspect. 15 m/s^2, Q16.16
 * (1.5 g: no car brakes harder). A sensor carried by something nimbler
 * sets its own. */
#ifndef EGO_MAX_ACCELERATION
#define EGO_MAX_ACCELERATION (15 * 65536)
#endif

/* ... and how fast it can go: a line faster than this is not the
 * vehicle's motion (EGO_FLAG_SUSPECT, and the dynamics filter does not
 * take it). 150 m/s, Q16.16: over any road vehicle, and over the fast
 * synthetic world's 112 m/s (docs/synthetic-worlds.md); a room taken for
 * its mirror image 4 m away in 13 ms is 300 m/s (docs/testing.md,
 * "Adversarial streams"). */
#ifndef EGO_MAX_SPEED
#define EGO_MAX_SPEED (150 * 65536)
#endif

_Static_assert(EGO_MAX_BEAMS >= 16u, "a scan needs some beams");
_Static_assert(EGO_MAX_BEAMS <= 16384u, "16-bit indices, and ITCP's sums of 2^48 products below 2^62");

#endif /* EGO_CONFIG_H */
