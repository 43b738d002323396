/* host_board.c - firmware/target/target.h on a host, for the host build of
 * the session image (firmware/target/main_session.c): UART0 is stdout, the
 * exit is exit(). There is no instruction counter and no painted stack on
 * a host: those read 0, so the image's '#' lines show zeros for them (ctest
 * target_session compares the lines without '#'). */
#include <stdio.h>
#include <stdlib.h>

#include "target.h"

_Noreturn void target_exit(int code)
{
    if (fflush(stdout) != 0 || ferror(stdout) != 0) {
        code = TARGET_EXIT_FAILED; /* the output is incomplete */
    }
    exit(code);
}

void target_uart_init(void)
{
}

void target_uart_write(const uint8_t *bytes, size_t len)
{
    (void)fwrite(bytes, 1u, len, stdout);
}

void target_uart_puts(const char *text)
{
    (void)fputs(text, stdout);
}

void target_uart_putc(int c)
{
    (void)putchar(c);
}

void target_clock_init(void)
{
}

uint64_t target_instructions(void)
{
    return 0u;
}

uint32_t target_stack_used(void)
{
    return 0u;
}

uint32_t target_stack_size(void)
{
    return 0u;
}

int target_main_exit_code(int main_returned)
{
    return main_returned;
}
