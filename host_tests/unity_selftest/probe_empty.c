/* probe_empty.c - self-test probe: no tests at all. The summary still
 * prints, with OK, and the exit status is 0. */
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

int main(void)
{
    UNITY_BEGIN();
    return UNITY_END();
}
