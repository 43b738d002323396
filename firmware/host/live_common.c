/* live_common.c - see live_common.h. */
#include "live_common.h"

#include <signal.h>
#include <string.h>
#include <time.h>

static volatile sig_atomic_t stop_signal;

static void on_stop_signal(int sig)
{
    stop_signal = sig;
}

uint64_t live_monotonic_us(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

void live_catch_stop_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal; /* no SA_RESTART: a blocked poll returns */
    (void)sigemptyset(&sa.sa_mask);
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    (void)signal(SIGPIPE, SIG_IGN);
}

bool live_stop_requested(void)
{
    return stop_signal != 0;
}

static const char *const baud_names[LMS_BAUD_COUNT] = {"9600", "19200", "38400", "500000"};

const char *live_baud_name(lms_baud_t baud)
{
    return (unsigned)baud < LMS_BAUD_COUNT ? baud_names[baud] : "?";
}

int live_parse_baud(const char *text, lms_baud_t *baud)
{
    for (unsigned b = 0u; text != NULL && b < LMS_BAUD_COUNT; b++) {
        if (strcmp(text, baud_names[b]) == 0) {
            *baud = (lms_baud_t)b;
            return 0;
        }
    }
    return -1;
}

int live_parse_unit(const char *text, lms_unit_t *unit)
{
    if (text != NULL && strcmp(text, "cm") == 0) {
        *unit = LMS_UNIT_CM;
        return 0;
    }
    if (text != NULL && strcmp(text, "mm") == 0) {
        *unit = LMS_UNIT_MM;
        return 0;
    }
    return -1;
}
