/* startup.c - reset and exception handling of the Cortex-M images: the
 * vector table, .data copied from flash, .bss zeroed, the stack painted
 * for the high-water mark, the FPU enabled on M4F, then main(). Every
 * fault ends the run with its own exit code (target.h), so a crash fails
 * a test instead of hanging it. */
#include <stdint.h>

#include "target.h"

/* From the linker script (mps2.ld). */
extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _sstack, _estack;

int main(void);
void Reset_Handler(void);
void SysTick_Handler(void);

#define STACK_PAINT 0xA5A5A5A5u

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
    const uint32_t *src = &_sidata;
    for (uint32_t *dst = &_sdata; dst < &_edata;) {
        *dst++ = *src++;
    }
    for (uint32_t *dst = &_sbss; dst < &_ebss;) {
        *dst++ = 0u;
    }
    /* Paint the stack below what this function uses (a 256-byte margin). */
    uintptr_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    for (uint32_t *p = &_sstack; (uintptr_t)p + 256u < sp; p++) {
        *p = STACK_PAINT;
    }
#if defined(__ARM_FP)
    /* CPACR: full access to CP10 and CP11, in case the compiler uses the
     * FPU registers (the estimator has no floating point). */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    const int rc = main();
    target_exit(rc == 0 ? TARGET_EXIT_RETURNED : rc);
}

uint32_t target_stack_size(void)
{
    return (uint32_t)((uintptr_t)&_estack - (uintptr_t)&_sstack);
}

uint32_t target_stack_used(void)
{
    const uint32_t *p = &_sstack;
    while (p < &_estack && *p == STACK_PAINT) {
        p++;
    }
    return (uint32_t)((uintptr_t)&_estack - (uintptr_t)p);
}
