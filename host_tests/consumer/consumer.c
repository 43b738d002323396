/* consumer.c - uses lmsego as a user would, through API that stays put:
 * the driver's telegram checksum, the estimator's integer math and the
 * firmware loop behind its three-function HAL, fed one scan telegram.
 *
 * Host builds print one line that consumer_tests.cmake checks:
 *   lmsego 0.2.0 crc=a656 sqrt=1000000 sin90=1073741824 cos90=0 bytes=372 scans=1 lines=0
 * and exit 0 when every value is the expected one. Cortex-M builds are
 * only linked (no stdio, no board).
 */
#include <stddef.h>
#include <stdint.h>

#include "ego_fx_math.h"
#include "ego_loop.h"
#include "lms_crc.h"
#include "lmsego_version.h"

#ifdef CONSUMER_HOST
#include <stdio.h>
#endif

/* One B0 scan as an LMS 2xx sends it (docs/protocol.md): STX, address
 * 0x80, length, code B0, count word (181 values in cm), the values, the
 * status byte, the CRC. */
#define SCAN_VALUES 181u
#define SCAN_LENGTH (1u + 2u + 2u * SCAN_VALUES + 1u)
#define SCAN_TELEGRAM_SIZE (4u + SCAN_LENGTH + 2u)

static uint8_t telegram[SCAN_TELEGRAM_SIZE];

static void make_scan(void)
{
    telegram[0] = 0x02u;
    telegram[1] = 0x80u;
    telegram[2] = (uint8_t)(SCAN_LENGTH & 0xFFu);
    telegram[3] = (uint8_t)(SCAN_LENGTH >> 8);
    telegram[4] = 0xB0u;
    telegram[5] = (uint8_t)(SCAN_VALUES & 0xFFu);
    telegram[6] = (uint8_t)(SCAN_VALUES >> 8);
    for (size_t i = 0u; i < SCAN_VALUES; i++) {
        telegram[7u + 2u * i] = 0xF4u; /* 500 cm */
        telegram[8u + 2u * i] = 0x01u;
    }
    telegram[4u + SCAN_LENGTH - 1u] = 0x10u; /* status: healthy */
    const uint16_t crc = lms_crc16(telegram, 4u + SCAN_LENGTH);
    telegram[4u + SCAN_LENGTH] = (uint8_t)(crc & 0xFFu);
    telegram[5u + SCAN_LENGTH] = (uint8_t)(crc >> 8);
}

/* The HAL: the telegram in chunks, then the end of input. */
typedef struct {
    size_t pos;
    size_t written;
} feed_t;

static int32_t feed_read(void *ctx, uint8_t *buf, size_t cap)
{
    feed_t *feed = ctx;
    size_t n = sizeof telegram - feed->pos;
    if (n == 0u) {
        return -1;
    }
    n = n < cap ? n : cap;
    for (size_t i = 0u; i < n; i++) {
        buf[i] = telegram[feed->pos + i];
    }
    feed->pos += n;
    return (int32_t)n;
}

static void feed_write(void *ctx, const uint8_t *buf, size_t len)
{
    feed_t *feed = ctx;
    (void)buf;
    feed->written += len;
}

static uint32_t feed_now_us(void *ctx)
{
    (void)ctx;
    return 0u;
}

/* Deliberately defined without a prototype: lmsego's own
 * -Wmissing-prototypes -Werror (cmake/warnings.cmake) would reject it, so
 * this file compiling shows that lmsego's flags do not reach a consumer. */
ego_loop_stats_t consumer_run_loop(size_t *written)
{
    static ego_loop_t loop;
    ego_loop_config_t config;
    ego_loop_defaults(&config);
    ego_loop_init(&loop, &config);
    feed_t feed = {0u, 0u};
    const ego_hal_t hal = {feed_read, feed_write, feed_now_us, &feed};
    for (uint32_t guard = 0u; guard < 100u; guard++) {
        if (ego_loop_step(&loop, &hal) == EGO_LOOP_END) {
            break;
        }
    }
    *written = feed.written;
    return *ego_loop_stats(&loop);
}

int main(void)
{
    static const uint8_t check[] = "123456789";
    const uint16_t crc = lms_crc16(check, sizeof check - 1u);
    const uint32_t root = fx_sqrt_u64(1000000000000u);
    fx_q2_30_t sin90 = 0;
    fx_q2_30_t cos90 = 0;
    fx_sincos(0x40000000u, &sin90, &cos90); /* a quarter turn */

    /* The scan goes through the framer, the decoder and the estimator;
     * the first scan has no motion, so no line is written. */
    make_scan();
    size_t written = 0u;
    const ego_loop_stats_t stats = consumer_run_loop(&written);

#ifdef CONSUMER_HOST
    (void)printf("lmsego %s crc=%04x sqrt=%lu sin90=%ld cos90=%ld bytes=%lu scans=%lu lines=%lu\n",
                 LMSEGO_VERSION, (unsigned)crc, (unsigned long)root, (long)sin90, (long)cos90,
                 (unsigned long)stats.bytes, (unsigned long)stats.scans,
                 (unsigned long)stats.lines);
#endif
    const int ok = crc == 0xA656u && root == 1000000u && sin90 == 0x40000000 && cos90 == 0 &&
                   stats.bytes == SCAN_TELEGRAM_SIZE && stats.scans == 1u && stats.lines == 0u &&
                   written == 0u;
    return ok ? 0 : 1;
}
