/* hal_mps2.c - UART0, SysTick and semihosting on the MPS2 boards (see
 * target.h). */
#include "target.h"

/* CMSDK UART0. */
#define UART0_BASE 0x40004000u
#define UART_DATA (*(volatile uint32_t *)(UART0_BASE + 0x00u))
#define UART_STATE (*(volatile uint32_t *)(UART0_BASE + 0x04u))
#define UART_CTRL (*(volatile uint32_t *)(UART0_BASE + 0x08u))
#define UART_BAUDDIV (*(volatile uint32_t *)(UART0_BASE + 0x10u))
#define UART_STATE_TX_FULL 0x1u
#define UART_CTRL_TX_EN 0x1u

/* SysTick. */
#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define SYST_ENABLE_TICKINT_CORE 0x7u
#define SYST_MAX 0xFFFFFFu
#if defined(TARGET_PC_SAMPLING)
/* A wrap every 997 ticks (39 880 instructions under -icount shift=0): each
 * wrap samples the interrupted program counter. 997: no multiple of any
 * loop's period. */
#define SYST_RELOAD_DEFAULT 996u
#else
#define SYST_RELOAD_DEFAULT SYST_MAX
#endif
#define CORE_HZ 25000000u


#define SYS_EXIT_EXTENDED 0x20u
#define ADP_STOPPED_APPLICATION_EXIT 0x20026u

void SysTick_Handler(void);

static volatile uint32_t systick_wraps;
static uint32_t systick_reload = SYST_RELOAD_DEFAULT;

/* The images' periodic work (target_clock_init_period): none by default. */
__attribute__((weak)) void target_tick(void)
{
}

_Noreturn void target_exit(int code)
{
    volatile uint32_t block[2] = {ADP_STOPPED_APPLICATION_EXIT, (uint32_t)code};
    register uint32_t r0 __asm__("r0") = SYS_EXIT_EXTENDED;
    register volatile uint32_t *r1 __asm__("r1") = block;
    __asm__ volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
    for (;;) {
        /* Only without semihosting: nothing else can be done. */
    }
}

void target_uart_init(void)
{
    UART_BAUDDIV = CORE_HZ / 115200u;
    UART_CTRL = UART_CTRL_TX_EN;
}

void target_uart_write(const uint8_t *bytes, size_t len)
{
    for (size_t i = 0u; i < len; i++) {
        while ((UART_STATE & UART_STATE_TX_FULL) != 0u) {
        }
        UART_DATA = bytes[i];
    }
}

void target_uart_putc(int c)
{
    while ((UART_STATE & UART_STATE_TX_FULL) != 0u) {
    }
    UART_DATA = (unsigned char)c;
}

/* A byte at a time: gcc turns a counting loop into a call to newlib's
 * strlen, which costs 220 bytes of flash on the M4F (92 on the M3) for
 * the board's few messages. */
void target_uart_puts(const char *text)
{
    for (; *text != '\0'; text++) {
        target_uart_write((const uint8_t *)text, 1u);
    }
}

#if defined(TARGET_PC_SAMPLING)
static uint32_t pc_samples[TARGET_PC_BUCKETS];

/* Entered from SysTick_Handler with the exception frame: r0 r1 r2 r3 r12
 * lr pc xpsr (the FPU context, if any, follows). */
void systick_sample(const uint32_t *frame);
void systick_sample(const uint32_t *frame)
{
    systick_wraps++;
    target_tick();
    const uint32_t bucket = frame[6] / TARGET_PC_BUCKET_BYTES;
    if (bucket < TARGET_PC_BUCKETS) {
        pc_samples[bucket]++;
    }
}

/* Naked: the frame is at the stack pointer before anything is pushed. The
 * main program runs on the main stack, so the frame is on MSP. */
__attribute__((naked)) void SysTick_Handler(void)
{
    __asm__ volatile("mrs r0, msp\n"
                     "b systick_sample\n");
}

const uint32_t *target_pc_samples(void)
{
    return pc_samples;
}
#else
void SysTick_Handler(void)
{
    systick_wraps++;
    target_tick();
}
#endif

void target_clock_init(void)
{
    SYST_RVR = systick_reload;
    SYST_CVR = 0u;
    SYST_CSR = SYST_ENABLE_TICKINT_CORE;
}

void target_clock_init_period(uint32_t ticks)
{
    systick_reload = (ticks >= 2u && ticks - 1u <= SYST_MAX) ? ticks - 1u : SYST_RELOAD_DEFAULT;
    target_clock_init();
}

uint64_t target_instructions(void)
{
    /* A wrap between the two reads shows as a changed wrap count: read
     * again. */
    uint32_t wraps;
    uint32_t value;
    do {
        wraps = systick_wraps;
        value = SYST_CVR;
    } while (wraps != systick_wraps);
    const uint64_t ticks = (uint64_t)wraps * (systick_reload + 1u) + (systick_reload - value);
    return ticks * TARGET_INSNS_PER_TICK;
}
