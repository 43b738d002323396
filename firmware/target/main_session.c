/* main_session.c - the firmware image with a live scanner: the core of
 * firmware/ego_live.h (receive ring -> session -> loop -> UART0) against
 * the simulated LMS 2xx (driver/sim/lms_sim.h) running in the same image
 * on a simulated microsecond clock.
 *
 * The scenario: the scanner powers up at 9600 baud in 180 deg / 0.5 deg;
 * the session finds it, switches it to 500 kbaud and 180 deg / 1 deg and
 * streams the scans of the recorded campus drive (compiled into flash as
 * lmsego_stream, as for the replay images). After POWER_CYCLE_AFTER scans
 * the scanner loses power (back at 9600, variant reset): the session sees
 * the silence and brings it up again, and the estimator starts over. After
 * SCANS scans the core stops it cleanly (stream off, back to 9600).
 *
 * The board around the core is simulated (everything named sim_*, left
 * out of the memory budget with the simulator and the scene): the
 * scanner's bytes go into the receive ring as the UART interrupt would put
 * them, stamped with the simulated time; the time advances to whatever
 * either end waits for next, but at least TICK_US, so bytes arrive in
 * chunks as a DMA idle-line interrupt delivers them. The simulated clock
 * stands still while the core works: deterministic, the same output on
 * every run, on the host and on the target.
 *
 * Output (UART0): the CSV lines, those of `lmsego replay` of the scans up
 * to the power cycle but for time_s, each scan's own time on the simulated
 * clock (firmware/ego_loop.h, "Scan times from arrival stamps"); then '#'
 * lines:
 *   # session scans=.. bring_ups=.. restarts=.. (silence .., power-on .., link ..) ...
 *   # timeline_ms streaming=.. restart=.. streaming_again=.. stopped=..
 *   # ring peak=.. dropped=.. discarded=..
 *   # insns_per_scan median=N max=M scans=S
 *   # stack_bytes used=U of=T
 * The instructions per scan are those of ego_live_step between two output
 * lines (ring, session, decoder, estimator, line; not the simulator), as
 * main_replay.c counts them. The image checks its own run (scans, the one
 * restart, the clean stop, nothing dropped) and exits 0, or 1 after a
 * '# check failed:' line.
 *
 * Built for the host as well (host_tests/session_image: target.h on
 * stdio), whose output ctest target_session compares with the target's.
 *
 * With SESSION_INTERRUPTS (target only: the image session_irq_image) the
 * board runs in real time instead, as on a part: the core in deferred mode
 * (ego_live.h), ego_live_service and the receive "interrupt" in the
 * SysTick interrupt every millisecond, ego_live_estimate in the main loop,
 * preempted by it at any instruction. The simulated clock is the core's
 * own instruction count at CPU_MHZ (a 168 MHz Cortex-M4 class part), so the
 * estimator's real cost decides which scans it gets to: the newest each
 * time, the others skipped and counted. Its output is not the host's (the
 * host has no instruction clock): it checks its own run (nothing dropped,
 * the one restart, the clean stop, every scan estimated or skipped) and
 * prints '# deferred estimated=.. skipped=..' and the instructions per
 * estimate. Tracking keeps the estimator up with the 75 Hz scanner on this
 * part (about 1.1 M instructions a scan against 2.2 M in 13.3 ms at 168
 * MHz): it must skip no scan.
 */
#include <stdbool.h>
#include <stdint.h>

#include "ego_live.h"
#include "lms_decode.h"
#include "lms_sim.h"
#include "report.h"
#include "target.h"

/* Stop after SCANS scans; the power cycle after POWER_CYCLE_AFTER (0:
 * none). Overridable (-D) for measurements, e.g. a run without the fault
 * to compare with the replay image of the same recording. */
#ifndef SCANS
#define SCANS 150u
#endif
#ifndef POWER_CYCLE_AFTER
#define POWER_CYCLE_AFTER 70u
#endif
#define FAULTS (POWER_CYCLE_AFTER > 0u && POWER_CYCLE_AFTER < SCANS ? 1u : 0u)
#define TICK_US 1000u          /* least time step: 50 bytes at 500 kbaud */
#define MAX_JUMP_US 1000000u   /* largest time step when nothing is due */
#define RUN_LIMIT_US 60000000u /* simulated; the run takes about 4 s */
#define SIM_START_US 1000u
/* Per-scan counts kept for the median (ticks of 40 instructions). */
#define MAX_MEASURED 512u
#define SIM_SCENE_MAX 512u

extern const uint8_t lmsego_stream[];
extern const uint32_t lmsego_stream_size;

/* The simulated board's functions stay out of line, so that the memory
 * budget (sim_* symbols left out) does not count them inside main. */
#if defined(__GNUC__)
#define SIM_FN __attribute__((noinline))
#else
#define SIM_FN
#endif

#if defined(SESSION_INTERRUPTS)
#define CPU_MHZ 168u
/* SysTick every millisecond of the part's time: CPU_MHZ * 1000 instructions. */
#define TICK_TICKS (CPU_MHZ * 1000u / TARGET_INSNS_PER_TICK)
#define RUN_LIMIT_INSNS ((uint64_t)RUN_LIMIT_US * CPU_MHZ)
#endif

/* --- The firmware --------------------------------------------------------- */

static uart_ring_t rx;
static ego_live_t live;
static ego_live_config_t config;

/* --- Measurements --------------------------------------------------------- */

static uint32_t insns[MAX_MEASURED];
static uint32_t image_measured;
static uint32_t image_insns_max;
#if !defined(SESSION_INTERRUPTS)
static uint64_t image_loop_insns; /* spent in ego_live_step, all steps */
static uint64_t image_step_start;
static uint64_t image_last_mark;
#endif

/* --- The simulated board -------------------------------------------------- */

static lms_sim_t sim_scanner;
static uint64_t sim_now = SIM_START_US;
static lms_baud_t sim_host_baud = LMS_BAUD_9600;
/* The scene: where each B0 of lmsego_stream starts, and its size. */
static uint32_t sim_scene_offset[SIM_SCENE_MAX];
static uint16_t sim_scene_len[SIM_SCENE_MAX];
static uint32_t sim_scene_count;
static uint32_t sim_scene_base; /* scene scan of k = 0 of the current stream */
static uint32_t sim_scene_last_k;
static bool sim_scene_asked;
/* What happened when (simulated us; 0: not yet). */
static uint64_t sim_streaming_us;
static uint64_t sim_restart_us;
static uint64_t sim_streaming_again_us;
static uint64_t sim_stopped_us;
static uint8_t sim_rx_buf[256];

/* Finds the B0 telegrams of the stream (a clean recording: telegrams back
 * to back; anything else is skipped as the replay's framer skips it). */
SIM_FN static void sim_scene_load(void)
{
    uint32_t pos = 0u;
    while (pos + LMS_OVERHEAD <= lmsego_stream_size && sim_scene_count < SIM_SCENE_MAX) {
        const uint8_t *p = &lmsego_stream[pos];
        const uint32_t len = LMS_OVERHEAD + (uint32_t)p[2] + ((uint32_t)p[3] << 8);
        lms_telegram_t t;
        if (p[0] != LMS_STX || len > LMS_TELEGRAM_MAX || pos + len > lmsego_stream_size ||
            lms_telegram_parse(p, len, &t) != LMS_OK) {
            pos++;
            continue;
        }
        if (t.code == LMS_REPLY_VALUES) {
            sim_scene_offset[sim_scene_count] = pos;
            sim_scene_len[sim_scene_count] = (uint16_t)len;
            sim_scene_count++;
        }
        pos += len;
    }
}

/* Scan k of the simulator's current stream. It asks for k + 1 as soon as
 * k is queued, so when a stream starts again (k = 0) the scan asked for
 * last was never sent: the new stream starts with it, and the core gets
 * the recording's scans in order, none twice, none left out. */
SIM_FN static bool sim_scene_scan(void *ctx, uint32_t k, uint16_t angle_deg, uint16_t resolution_cdeg,
                           bool partial, lms_unit_t unit, uint8_t reply_address, uint8_t *out,
                           size_t cap, size_t *len, uint32_t *gap_us)
{
    (void)ctx;
    (void)angle_deg;
    (void)resolution_cdeg;
    (void)partial;
    (void)unit;
    (void)reply_address; /* played as recorded */
    if (k == 0u && sim_scene_asked) {
        sim_scene_base += sim_scene_last_k;
    }
    sim_scene_asked = true;
    sim_scene_last_k = k;
    const uint32_t i = sim_scene_base + k;
    if (i >= sim_scene_count || sim_scene_len[i] > cap) {
        return false;
    }
    for (uint32_t j = 0u; j < sim_scene_len[i]; j++) {
        out[j] = lmsego_stream[sim_scene_offset[i] + j];
    }
    *len = sim_scene_len[i];
    *gap_us = 0u;
    return true;
}

SIM_FN static void sim_scanner_write(void *ctx, const uint8_t *bytes, size_t len)
{
    (void)ctx;
    lms_sim_receive(&sim_scanner, bytes, len, sim_host_baud, sim_now);
}

SIM_FN static void sim_set_baud(void *ctx, lms_baud_t baud)
{
    (void)ctx;
    sim_host_baud = baud;
}

SIM_FN static uint32_t sim_now_us(void *ctx)
{
    (void)ctx;
    return (uint32_t)sim_now;
}

static void out_write(void *ctx, const uint8_t *bytes, size_t len)
{
    (void)ctx;
    target_uart_write(bytes, len);
}

/* The receive interrupt: what the scanner has sent by sim_now into the
 * ring. */
SIM_FN static void sim_receive(void)
{
    for (uint32_t guard = 0u; guard < 64u; guard++) {
        const size_t n = lms_sim_transmit(&sim_scanner, sim_host_baud, sim_now, sim_rx_buf,
                                          sizeof sim_rx_buf);
        (void)uart_ring_write(&rx, sim_rx_buf, n, (uint32_t)sim_now);
        if (n < sizeof sim_rx_buf) {
            break;
        }
    }
}

#if !defined(SESSION_INTERRUPTS)
/* Time moves on to the next thing either end waits for (at least TICK_US),
 * and the receive interrupt puts what arrived meanwhile into the ring. */
SIM_FN static void sim_advance(void)
{
    uint64_t step = ego_live_wait_us(&live);
    const uint64_t next = lms_sim_next_event_us(&sim_scanner, sim_now);
    if (next != UINT64_MAX && next - sim_now < step) {
        step = next - sim_now;
    }
    step = step < TICK_US ? TICK_US : (step > MAX_JUMP_US ? MAX_JUMP_US : step);
    sim_now += step;
    sim_receive();
}
#endif

/* The scanner: powers up at 9600, 180 deg / 0.5 deg, plays the scene,
 * loses power once. */
SIM_FN static void sim_init(void)
{
    sim_scene_load();
    lms_sim_config_t sc;
    lms_sim_defaults(&sc);
    sc.scan_source = sim_scene_scan;
    sc.faults.power_cycle_after_scans = POWER_CYCLE_AFTER;
    lms_sim_init(&sim_scanner, &sc, sim_now);
}

/* Notes when the session reached each milestone. */
SIM_FN static void sim_watch(void)
{
    const lms_session_t *s = ego_live_session(&live);
    const bool streaming = lms_session_state(s) == LMS_SESSION_STREAMING;
    const uint32_t restarts = lms_session_stats(s)->restarts;
    if (streaming && sim_streaming_us == 0u) {
        sim_streaming_us = sim_now;
    }
    if (restarts > 0u && sim_restart_us == 0u) {
        sim_restart_us = sim_now;
    }
    if (streaming && sim_restart_us != 0u && sim_streaming_again_us == 0u) {
        sim_streaming_again_us = sim_now;
    }
    if (ego_live_status(&live) != EGO_LIVE_RUNNING && sim_stopped_us == 0u) {
        sim_stopped_us = sim_now;
    }
}

#if defined(SESSION_INTERRUPTS)
static volatile bool irq_ready; /* the core is set up: the tick may serve it */

/* SysTick, every millisecond of the part's time: the clock, the receive
 * interrupt's bytes, and the core's line service (deferred mode). */
void target_tick(void)
{
    if (!irq_ready) {
        return;
    }
    sim_now = SIM_START_US + target_instructions() / CPU_MHZ;
    sim_receive();
    ego_live_service(&live);
    sim_watch();
}
#endif

/* --- Measuring and reporting ---------------------------------------------- */

/* Records one scan's instructions. */
static void image_record(uint64_t insns_spent)
{
    const uint64_t d = insns_spent / TARGET_INSNS_PER_TICK;
    const uint32_t n = d > UINT32_MAX ? UINT32_MAX : (uint32_t)d;
    if (image_measured < MAX_MEASURED) {
        insns[image_measured++] = n;
    }
    image_insns_max = n > image_insns_max ? n : image_insns_max;
}

#if !defined(SESSION_INTERRUPTS)
/* Called after every line: the core's instructions since the last line. */
static void image_observe(void *ctx, uint32_t scan, uint32_t time_us, const ego_output_t *out)
{
    (void)ctx;
    (void)scan;
    (void)time_us;
    (void)out;
    const uint64_t in_loop = image_loop_insns + (target_instructions() - image_step_start);
    image_record(in_loop - image_last_mark);
    image_last_mark = in_loop;
}
#endif

static uint64_t image_ms_since_start(uint64_t t)
{
    return t == 0u ? 0u : (t - SIM_START_US) / 1000u;
}

/* Not inlined into main: the report and the checks are the image's own
 * measurement, not the loop (excluded from its budget, session.cmake). */
__attribute__((noinline)) static void image_report(void)
{
    const lms_session_t *s = ego_live_session(&live);
    const lms_session_stats_t *ss = lms_session_stats(s);
    const lms_framer_stats_t *fs = lms_session_framer_stats(s);
    report_field("# session scans=", ss->scans);
    report_field(" bring_ups=", ss->bring_ups);
    report_field(" restarts=", ss->restarts);
    report_field(" (silence ", ss->restarts_silence);
    report_field(", power-on ", ss->restarts_power_on);
    report_field(", link ", ss->restarts_link);
    report_field(") commands=", ss->commands);
    report_field(" retries=", ss->retries);
    report_field(" ack_timeouts=", ss->ack_timeouts);
    report_field(" reply_timeouts=", ss->reply_timeouts);
    report_field(" probes=", ss->probes);
    report_field(" baud_switches=", ss->baud_switches);
    report_field(" crc_errors=", fs->crc_errors);
    report_field(" bytes_skipped=", fs->bytes_skipped);
    report_field("\n# timeline_ms streaming=", image_ms_since_start(sim_streaming_us));
    report_field(" restart=", image_ms_since_start(sim_restart_us));
    report_field(" streaming_again=", image_ms_since_start(sim_streaming_again_us));
    report_field(" stopped=", image_ms_since_start(sim_stopped_us));
#if defined(SESSION_INTERRUPTS)
    report_field("\n# deferred cpu_mhz=", CPU_MHZ);
    report_field(" estimated=", ego_live_stats(&live)->scans_estimated);
    report_field(" skipped=", ego_live_stats(&live)->scans_skipped);
#endif
    report_field("\n# ring peak=", uart_ring_peak(&rx));
    report_field(" dropped=", uart_ring_dropped(&rx));
    report_field(" discarded=", ego_live_stats(&live)->bytes_discarded);
    report_field("\n# insns_per_scan median=",
              (uint64_t)report_median(insns, image_measured) * TARGET_INSNS_PER_TICK);
    report_field(" max=", (uint64_t)image_insns_max * TARGET_INSNS_PER_TICK);
    report_field(" scans=", ego_live_stats(&live)->scans);
    report_field("\n# stack_bytes used=", target_stack_used());
    report_field(" of=", target_stack_size());
    target_uart_puts("\n");
}

/* The run's own checks: the first that fails, or NULL. */
__attribute__((noinline)) static const char *image_check(void)
{
    const ego_live_stats_t *ls = ego_live_stats(&live);
    const lms_session_stats_t *ss = lms_session_stats(ego_live_session(&live));
    const ego_loop_stats_t *lp = ego_loop_stats(ego_live_loop(&live));
    if (ego_live_status(&live) != EGO_LIVE_STOPPED) {
        return "the core did not stop cleanly";
    }
#if defined(SESSION_INTERRUPTS)
    /* Every scan estimated or skipped (the last may still wait), a line
     * per estimated scan but the first. */
    const uint32_t accounted = ls->scans_estimated + ls->scans_skipped;
    if (ls->scans != SCANS || (accounted != SCANS && accounted + 1u != SCANS) ||
        lp->lines + 1u != ls->scans_estimated || lp->decode_errors != 0u) {
        return "scans, estimated and skipped, or lines";
    }
    /* Tracking keeps up with the scanner: nothing skipped. */
    if (ls->scans_skipped != 0u) {
        return "the estimator skipped scans";
    }
#else
    if (ls->scans != SCANS || lp->lines != SCANS - 1u || lp->decode_errors != 0u) {
        return "scans or lines";
    }
#endif
    if (ss->restarts != FAULTS || ls->gaps != FAULTS || lp->restarts != FAULTS ||
        ss->bring_ups != 1u + FAULTS) {
        return "a restart after the fault, and a bring-up more";
    }
    if (lms_sim_stats(&sim_scanner)->power_cycles != FAULTS) {
        return "the power cycle";
    }
    if (lms_sim_baud(&sim_scanner) != LMS_BAUD_9600 || sim_host_baud != LMS_BAUD_9600) {
        return "both ends back at 9600 baud";
    }
    if (uart_ring_dropped(&rx) != 0u) {
        return "bytes dropped by the receive ring";
    }
    return NULL;
}

int main(void)
{
    target_uart_init();
#if defined(SESSION_INTERRUPTS)
    target_clock_init_period(TICK_TICKS);
#else
    target_clock_init();
#endif
    sim_init();
    uart_ring_init(&rx);
    ego_live_defaults(&config);
    config.session.baud = LMS_BAUD_500000;
    config.session.angle_deg = 180u;
    config.session.resolution_cdeg = 100u; /* the recording's 181 values */
    config.max_scans = SCANS;
#if defined(SESSION_INTERRUPTS)
    config.deferred = true;
#else
    config.loop.observer = image_observe;
#endif
    const ego_live_hal_t hal = {sim_scanner_write, sim_set_baud, sim_now_us, out_write, NULL};
    if (sim_scene_count < SCANS + 1u || ego_live_init(&live, &config, &hal, &rx) != LMS_OK) {
        target_uart_puts("# check failed: setup\n");
        target_exit(TARGET_EXIT_FAILED);
    }
#if defined(SESSION_INTERRUPTS)
    irq_ready = true;
    /* The main loop: the estimator on the newest scan, whenever there is
     * one; the tick serves the line meanwhile. */
    while (ego_live_status(&live) == EGO_LIVE_RUNNING &&
           target_instructions() < RUN_LIMIT_INSNS) {
        const uint64_t t0 = target_instructions();
        if (ego_live_estimate(&live)) {
            image_record(target_instructions() - t0);
        }
    }
    irq_ready = false;
#else
    while (ego_live_status(&live) == EGO_LIVE_RUNNING && sim_now < RUN_LIMIT_US) {
        sim_advance();
        image_step_start = target_instructions();
        (void)ego_live_step(&live);
        image_loop_insns += target_instructions() - image_step_start;
        sim_watch();
    }
#endif
    image_report();
    const char *failed = image_check();
    if (failed != NULL) {
        target_uart_puts("# check failed: ");
        target_uart_puts(failed);
        target_uart_puts("\n");
        target_exit(TARGET_EXIT_FAILED);
    }
    target_exit(TARGET_EXIT_OK);
}
