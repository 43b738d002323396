/* probe_fault.c - an image that crashes on purpose (an undefined
 * instruction), to prove that a fault ends the run with its own exit code
 * (target.h: escalated to HardFault, 121) instead of hanging: ctest
 * target_fault_exit. */
#include "target.h"

int main(void)
{
    target_uart_init();
    target_uart_puts("about to fault\n");
    __builtin_trap();
}
