/* startup.c - reset and exception handling of the Cortex-M images: the
 * vector table, .data copied from flash, .bss zeroed, the stack painted
 * for the high-water mark, the FPU enabled on M4F, then main(). Every
 * fault ends the run with its own exit code (target.h), so a crash fails
 * a test instead of hanging it. */
#include <stddef.h>
#include <stdint.h>

#include "target.h"

/* From the linker script (mps2.ld). */
extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _sstack, _estack;

/* Called as main(0, {NULL}): images define int main(void) or, like the
 * host test programs, int main(int argc, char **argv) (target.h). */
int main(int argc, char **argv);
void Reset_Handler(void);
void SysTick_Handler(void);

#define STACK_PAINT 0xA5A5A5A5u

static volatile uint32_t *word_at(uintptr_t address)
{
    return (volatile uint32_t *)address;
}

static void fault_exit(int code)
{
    target_exit(code);
}

static void NMI_Handler(void)
{
    fault_exit(TARGET_EXIT_NMI);
}

static void HardFault_Handler(void)
{
    fault_exit(TARGET_EXIT_HARDFAULT);
}

static void MemManage_Handler(void)
{
    fault_exit(TARGET_EXIT_MEMMANAGE);
}

static void BusFault_Handler(void)
{
    fault_exit(TARGET_EXIT_BUSFAULT);
}

static void UsageFault_Handler(void)
{
    fault_exit(TARGET_EXIT_USAGEFAULT);
}

static void Unexpected_Handler(void)
{
    fault_exit(TARGET_EXIT_UNEXPECTED);
}

typedef void (*vector_t)(void);

/* 16 system entries and the first external interrupts (the UART's are not
 * used: output polls). */
__attribute__((section(".isr_vector"), used)) static const vector_t vectors[32] = {
    (vector_t)(uintptr_t)&_estack, /* initial stack pointer */
    Reset_Handler,
    NMI_Handler,
    HardFault_Handler,
    MemManage_Handler,
    BusFault_Handler,
    UsageFault_Handler,
    0, 0, 0, 0,                    /* reserved */
    Unexpected_Handler,            /* SVCall */
    Unexpected_Handler,            /* debug monitor */
    0,                             /* reserved */
    Unexpected_Handler,            /* PendSV */
    SysTick_Handler,
    Unexpected_Handler, Unexpected_Handler, Unexpected_Handler, Unexpected_Handler,
    Unexpected_Handler, Unexpected_Handler, Unexpected_Handler, Unexpected_Handler,
    Unexpected_Handler, Unexpected_Handler, Unexpected_Handler, Unexpected_Handler,
    Unexpected_Handler, Unexpected_Handler, Unexpected_Handler, Unexpected_Handler,
};

void Reset_Handler(void)
{
    /* The linker's symbols are separate objects to C: walk them as
     * addresses (comparing pointers to different objects is undefined). */
    uintptr_t src = (uintptr_t)&_sidata;
    for (uintptr_t a = (uintptr_t)&_sdata; a < (uintptr_t)&_edata; a += 4u, src += 4u) {
        *word_at(a) = *word_at(src);
    }
    for (uintptr_t a = (uintptr_t)&_sbss; a < (uintptr_t)&_ebss; a += 4u) {
        *word_at(a) = 0u;
    }
    /* Paint the stack below what this function uses (a 256-byte margin). */
    uintptr_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    for (uintptr_t a = (uintptr_t)&_sstack; a + 256u < sp; a += 4u) {
        *word_at(a) = STACK_PAINT;
    }
#if defined(__ARM_FP)
    /* CPACR: full access to CP10 and CP11, in case the compiler uses the
     * FPU registers (the estimator has no floating point). */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    char *no_arguments[1] = {NULL}; /* lives as long as main: this never returns */
    const int rc = main(0, no_arguments);
    target_exit(target_main_exit_code(rc));
}

/* The product images' rule (target.h); unit-test images override it. */
__attribute__((weak)) int target_main_exit_code(int main_returned)
{
    return main_returned == 0 ? TARGET_EXIT_RETURNED : main_returned;
}

uint32_t target_stack_size(void)
{
    return (uint32_t)((uintptr_t)&_estack - (uintptr_t)&_sstack);
}

uint32_t target_stack_used(void)
{
    uintptr_t a = (uintptr_t)&_sstack;
    while (a < (uintptr_t)&_estack && *word_at(a) == STACK_PAINT) {
        a += 4u;
    }
    return (uint32_t)((uintptr_t)&_estack - a);
}
