/* report.c - see report.h. */
#include "report.h"

#include "ego_loop.h"
#include "target.h"

void report_fixed(const char *name, uint64_t value, unsigned decimals)
{
    char num[32];
    (void)ego_format_fixed(num, (int64_t)value, decimals);
    target_uart_puts(name);
    target_uart_puts(num);
}

void report_field(const char *name, uint64_t value)
{
    report_fixed(name, value, 0u);
}

uint32_t report_median(uint32_t *v, uint32_t n)
{
    for (uint32_t i = 1u; i < n; i++) {
        const uint32_t x = v[i];
        uint32_t j = i;
        for (; j > 0u && v[j - 1u] > x; j--) {
            v[j] = v[j - 1u];
        }
        v[j] = x;
    }
    return n == 0u ? 0u : v[n / 2u];
}
