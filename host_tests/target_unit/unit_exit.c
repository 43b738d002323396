/* unit_exit.c - linked into the unit-test images only: main returns
 * UNITY_END(), the number of failed tests, and this makes it the run's exit
 * code (../startup.c; the weak default there flags a return from a product
 * image's main instead). 0 passes the ctest test; counts above
 * TARGET_EXIT_TESTS_FAILED_MAX are reported as that, so they never wrap to
 * 0 or look like a fault's code. */
#include "target.h"

int target_main_exit_code(int main_returned)
{
    if (main_returned < 0) {
        return TARGET_EXIT_FAILED; /* not a count: a failure all the same */
    }
    return main_returned > TARGET_EXIT_TESTS_FAILED_MAX ? TARGET_EXIT_TESTS_FAILED_MAX
                                                         : main_returned;
}
