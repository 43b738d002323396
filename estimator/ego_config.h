/* ego_config.h - compile-time capacities of the estimator.
 *
 * Override from the build (target_compile_definitions) only upwards; the
 * static assertions keep an override from producing a too-small buffer.
 */
#ifndef EGO_CONFIG_H
#define EGO_CONFIG_H

#include "lms_proto.h"

/* Points per scan: one per LMS value (401 at 100 deg / 0.25 deg). */
#ifndef EGO_MAX_POINTS
#define EGO_MAX_POINTS LMS_SCAN_MAX_VALUES
#endif

/* Largest tangent-fit half window n (the fit uses 2n + 1 points). */
#ifndef EGO_TFIT_MAX_HALF_WINDOW
#define EGO_TFIT_MAX_HALF_WINDOW 5u
#endif

_Static_assert(EGO_MAX_POINTS >= LMS_SCAN_MAX_VALUES, "a scan must fit");
_Static_assert(EGO_MAX_POINTS <= 0xFFFFu, "point indices are 16 bits");

#endif /* EGO_CONFIG_H */
