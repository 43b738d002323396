/* main_replay.c - the firmware image of the loop: the same portable loop
 * as `lmsego replay` (firmware/ego_loop.h) over a recorded telegram stream
 * compiled into flash (lmsego_stream, generated from a .lms file by
 * cmake/bin2c.cmake), writing the same CSV lines to UART0. Built with
 * REPLAY_BUDGET it runs the estimator within its sensor-rate budget
 * (ego_budget_defaults: `lmsego replay --budget default` on the host);
 * with REPLAY_OBJECTS as well, the loop writes each scan's moving objects
 * after its line (`lmsego replay --moving`; ego_loop.h).
 *
 * It also measures itself: the instructions between consecutive output
 * lines (one scan: framing, decoding, the estimator and the line), counted
 * with SysTick under QEMU's -icount (target.h), and the stack high-water
 * mark. After the stream it writes, as lines starting with '#':
 *   # insns_per_scan median=N max=M scans=S   (budget images: max=M budget=B)
 *   # stage_insns prepare=.. tangents=.. ... (profile images only)
 *   # stack_bytes used=U of=T
 * and exits 0 (semihosting). The lines before them are byte-identical to
 * `lmsego replay` of the same stream (ctest target_replay_*).
 */
#include <stdbool.h>
#include <stdint.h>

#include "ego_loop.h"
#include "report.h"
#include "target.h"

extern const uint8_t lmsego_stream[];
extern const uint32_t lmsego_stream_size;

/* Per-scan counts kept for the median, in SysTick ticks of 40
 * instructions (a uint32_t holds 171 G instructions; the repository's
 * streams have at most a few hundred scans; more are still counted in the
 * maximum). */
#define MAX_MEASURED 512u

/* The loop's own work per scan beside the estimator's (measured: 32 k
 * for 181 values, 45 k for 361; docs/firmware.md). */
#define LOOP_ALLOWANCE 50000u

/* The moving objects' work per scan beside their counted units (the
 * segments, the references, the tracks: measured 20 k on the platoon,
 * whose references keep starting over), and the instructions a unit
 * costs at most (measured about 340 on the busy streets, Cortex-M3 -Os;
 * docs/firmware.md). */
#define OBJECTS_ALLOWANCE 40000u
#define OBJECTS_INSNS_PER_UNIT 400u

static ego_loop_config_t config;
static ego_loop_t loop;
static uint32_t stream_pos;
static uint32_t insns[MAX_MEASURED];
static uint32_t measured;
static uint32_t insns_max;
static uint64_t last_mark;

#if defined(REPLAY_OBJECTS)
/* The moving objects' instructions per scan: from the end of a scan's
 * motion line to the first write or read after it (its objects are found
 * before their first line is written; the rest of the read chunk's
 * framing, at most 256 bytes, is counted too). */
static uint32_t objects_insns[MAX_MEASURED];
static uint32_t objects_measured;
static uint32_t objects_max;
static uint64_t objects_mark;
static bool objects_open;

static void objects_close(void)
{
    if (!objects_open) {
        return;
    }
    objects_open = false;
    const uint32_t ticks = (uint32_t)((target_instructions() - objects_mark) / TARGET_INSNS_PER_TICK);
    objects_max = (ticks > objects_max) ? ticks : objects_max;
    if (objects_measured < MAX_MEASURED) {
        objects_insns[objects_measured++] = ticks;
    }
}
#endif

static int32_t hal_read(void *ctx, uint8_t *buf, size_t cap)
{
    (void)ctx;
#if defined(REPLAY_OBJECTS)
    objects_close();
#endif
    if (stream_pos >= lmsego_stream_size) {
        return -1;
    }
    uint32_t n = lmsego_stream_size - stream_pos;
    n = n > cap ? (uint32_t)cap : n;
    for (uint32_t i = 0u; i < n; i++) {
        buf[i] = lmsego_stream[stream_pos + i];
    }
    stream_pos += n;
    return (int32_t)n;
}

static void hal_write(void *ctx, const uint8_t *buf, size_t len)
{
    (void)ctx;
#if defined(REPLAY_OBJECTS)
    objects_close();
#endif
    target_uart_write(buf, len);
#if defined(REPLAY_OBJECTS)
    /* A motion line (it starts with its scan number; the header and the
     * objects' lines with a letter): its objects come next. */
    if (len > 0u && buf[0] >= (uint8_t)'0' && buf[0] <= (uint8_t)'9') {
        objects_open = true;
        objects_mark = target_instructions();
    }
#endif
}

static uint32_t hal_now_us(void *ctx)
{
    (void)ctx;
    return 0u; /* replay: scan times from the index and the period */
}

/* Called after every scan after the first: the instructions since the
 * previous call are this scan's. */
#if defined(EGO_PROFILE)
static void profile_scan_end(bool worst);
#endif

static void observe(void *ctx, uint32_t scan, uint32_t time_us, const ego_output_t *out)
{
    (void)ctx;
    (void)scan;
    (void)time_us;
    (void)out;
    const uint64_t now = target_instructions();
    const uint64_t d = (now - last_mark) / TARGET_INSNS_PER_TICK;
    const uint32_t n = d > UINT32_MAX ? UINT32_MAX : (uint32_t)d;
    last_mark = now;
    if (measured < MAX_MEASURED) {
        insns[measured++] = n;
    }
#if defined(EGO_PROFILE)
    profile_scan_end(n > insns_max);
#endif
    insns_max = n > insns_max ? n : insns_max;
}

#if defined(EGO_PROFILE)
/* Profile images (estimator built with EGO_PROFILE): the instructions of
 * each estimator stage, summed over the stream. Framing, decoding and the
 * output line fall into EGO_STAGE_OTHER with the estimator's own
 * bookkeeping. */
static uint64_t stage_insns[EGO_STAGE_COUNT];
static uint64_t stage_units[EGO_STAGE_COUNT];
/* The same for the current scan, and for the scan with the most
 * instructions (where the budget is tightest). */
static uint64_t scan_insns[EGO_STAGE_COUNT];
static uint64_t scan_units[EGO_STAGE_COUNT];
static uint64_t worst_insns[EGO_STAGE_COUNT];
static uint64_t worst_units[EGO_STAGE_COUNT];
static ego_stage_t stage_now = EGO_STAGE_OTHER;
static uint64_t stage_mark;
static uint64_t units_mark;

void ego_profile_stage(ego_stage_t stage, uint64_t units)
{
    const uint64_t t = target_instructions();
    /* The meter starts at 0 each scan. */
    const uint64_t spent = (units >= units_mark) ? units - units_mark : units;
    stage_insns[stage_now] += t - stage_mark;
    stage_units[stage_now] += spent;
    scan_insns[stage_now] += t - stage_mark;
    scan_units[stage_now] += spent;
    stage_now = stage;
    stage_mark = t;
    units_mark = units;
}

/* One '#' line: a figure per stage. */
static void report_stages(const char *title, const uint64_t *figures)
{
    static const char *const names[EGO_STAGE_COUNT] = {
        " prepare=", " tangents=", " histogram=", " correlate=",
        " register=", " coarse=", " other="};
    target_uart_puts(title);
    for (unsigned k = 0u; k < (unsigned)EGO_STAGE_COUNT; k++) {
        report_field(names[k], figures[k]);
    }
}

static void profile_scan_end(bool worst)
{
    for (unsigned k = 0u; k < (unsigned)EGO_STAGE_COUNT; k++) {
        if (worst) {
            worst_insns[k] = scan_insns[k];
            worst_units[k] = scan_units[k];
        }
        scan_insns[k] = 0u;
        scan_units[k] = 0u;
    }
}
#endif

int main(void)
{
    target_uart_init();
    target_clock_init();
    ego_loop_defaults(&config);
#if defined(REPLAY_BUDGET)
    ego_budget_defaults(&config.ego);
#endif
#if defined(REPLAY_PERIOD_US)
    config.period_us = REPLAY_PERIOD_US; /* keyframes: seconds apart */
#endif
#if defined(REPLAY_SWEEP_INSTANT)
    config.lms.timing = (uint8_t)EGO_LMS_TIMING_INSTANT; /* a simulator's stream */
#endif
#if defined(REPLAY_OBJECTS)
    config.objects = true; /* each line's moving objects (ego_loop.h) */
#endif
    config.observer = observe;
    ego_loop_init(&loop, &config);
    const ego_hal_t hal = {hal_read, hal_write, hal_now_us, NULL};
    last_mark = target_instructions();
    bool first_scan_done = false;
    while (ego_loop_step(&loop, &hal) != EGO_LOOP_END) {
        /* Scan k's instructions run from the step that finished scan k - 1
         * (a step reads at most 256 bytes: never two whole telegrams), so
         * the bring-up bytes and the first scan, which has no motion, are
         * nobody's. */
        if (!first_scan_done && ego_loop_stats(&loop)->scans > 0u) {
            last_mark = target_instructions();
            first_scan_done = true;
        }
    }
    report_field("# insns_per_scan median=",
                 (uint64_t)report_median(insns, measured) * TARGET_INSNS_PER_TICK);
    report_field(" max=", (uint64_t)insns_max * TARGET_INSNS_PER_TICK);
#if defined(REPLAY_BUDGET)
    /* A scan's budget in instructions: the estimator's (its units are
     * upper bounds of its instructions, ego_work.h) and LOOP_ALLOWANCE for
     * the loop's own framing, decoding and line: 1.0 M for 361 values at
     * 37.5 Hz, 0.6 M for 181 at 75 Hz (issue 15). */
    const uint64_t scaled = (uint64_t)loop.period_us * config.ego.work_per_s / 1000000u;
    uint64_t budget = LOOP_ALLOWANCE + ((scaled > config.ego.work_min) ? scaled : config.ego.work_min);
#if defined(REPLAY_OBJECTS)
    /* The objects' bound: their fixed work and their counted units at
     * most (ego_moving.h), the last scan's beams. */
    budget += OBJECTS_ALLOWANCE + (uint64_t)loop.scan.count * EGO_MOVING_UNITS_PER_BEAM * OBJECTS_INSNS_PER_UNIT;
#endif
    report_field(" budget=", budget);
#endif
    report_field(" scans=", ego_loop_stats(&loop)->scans);
#if defined(REPLAY_OBJECTS)
    objects_close();
    report_field("\n# objects_insns median=",
                 (uint64_t)report_median(objects_insns, objects_measured) * TARGET_INSNS_PER_TICK);
    report_field(" max=", (uint64_t)objects_max * TARGET_INSNS_PER_TICK);
#endif
#if defined(EGO_PROFILE)
    ego_profile_stage(EGO_STAGE_OTHER, units_mark);
    report_stages("\n# stage_insns", stage_insns);
    /* The units (ego_work.h) charged in each stage, to set against them. */
    report_stages("\n# stage_units", stage_units);
    /* The scan with the most instructions (its other stage includes the
     * line of the scan before and this scan's framing and decoding). */
    report_stages("\n# worst_insns", worst_insns);
    report_stages("\n# worst_units", worst_units);
#endif
#if defined(TARGET_PC_SAMPLING)
    /* Where the samples fell: address of each 64-byte piece of flash and
     * its count (a host script maps them to functions). */
    const uint32_t *samples = target_pc_samples();
    for (uint32_t b = 0u; b < TARGET_PC_BUCKETS; b++) {
        if (samples[b] != 0u) {
            report_field("\n# pc_sample at=", (uint64_t)b * TARGET_PC_BUCKET_BYTES);
            report_field(" count=", samples[b]);
        }
    }
#endif
    report_field("\n# stack_bytes used=", target_stack_used());
    report_field(" of=", target_stack_size());
    target_uart_puts("\n");
    target_exit(TARGET_EXIT_OK);
}
