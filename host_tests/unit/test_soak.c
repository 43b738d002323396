/* test_soak.c - the soak under faults (issue 18, item 3): the live core
 * (firmware/ego_live.h, as `lmsego run` runs it: deferred, every scan taken
 * into the caller's queue and estimated in order) against the simulated
 * scanner (driver/sim/lms_sim.h), in-process, on a simulated clock, for
 * minutes or an hour of simulated time, under a seeded random schedule of
 * faults of every kind:
 *
 *   power      a power cycle (lms_sim's power fault: 100 ms, back at 9600,
 *              variant reset)
 *   hangup     the line hangs up (lms_sim's hang-up flag): the board tells
 *              the core (ego_live_link_lost, as run does on POLLHUP) and
 *              the line is dead both ways for 200 .. 1000 ms (run reopens
 *              every 200 ms)
 *   silence    the scanner sends nothing and ignores the host for
 *              100 .. 1500 ms (lms_sim's silence fault)
 *   nak        a NAK storm: 40 .. 90 % of the host's good telegrams NAKed
 *              for 1 .. 4 s, with a hang-up at its start so that the
 *              bring-up runs inside it
 *   garbage    line noise: the scanner's bytes replaced by random bytes
 *              for 5 .. 60 ms (short: no restart) or 200 .. 600 ms (long:
 *              a restart on silence)
 *   baud       another host switches the scanner's rate (a 20 4x to it, at
 *              its rate, while it streams): the line is garbled until the
 *              session finds it again
 *   damage     bytes dropped, flipped and inserted at 20 .. 200 ppm each
 *              for 2 .. 10 s (lms_sim's byte faults)
 *
 * one at a time: the next one 1 .. 15 s of clean streaming after the last
 * was recovered, the kinds drawn from a shuffled bag (each kind once in
 * every seven faults). The scene: the scanner drives an ellipse (8 m x 5 m, 20 s
 * a lap, about 1 m/s) through synth_room, facing along its path; the
 * source hands out the scene scan of the current simulated time, so an
 * outage moves the vehicle on as a real one would.
 *
 * Asserted, per run:
 * - no crash (and no ASan / UBSan finding: the asan preset runs it);
 * - every fault recovered: a scan taken within RECOVERY_US (2 s) of the
 *   fault's end (power: power-on delay over; hang-up: line back; silence,
 *   NAK storm, garbage, damage: their end; baud: the switch);
 * - counters consistent: every scan taken is a scan the simulator sent,
 *   in order, none twice (matched byte for byte); taken + lost + in flight
 *   = sent; lines = taken - 1; the core's gaps = the session's restarts;
 *   every fault that must restart the session did (power, hang-up,
 *   silence, NAK storm, long garbage, baud), the others did not (short
 *   garbage, damage), and no restart and no lost scan came outside a
 *   fault's window (its start to its recovery);
 * - no line whose motion is wrong without a flag: each line's motion
 *   (dx, dy, dtheta) against the scene's true motion between the two scans
 *   it spans (ego.h: after a RECOVERING run, the RECOVERED line spans the
 *   last trusted scan to the scan the search started from, and the next
 *   line starts there); wrong is more than WRONG_M (0.10 m) or WRONG_RAD
 *   (1 deg) off; a wrong line must carry a trust flag (every EGO_FLAG_*
 *   of issue 18's list: APERTURE, LOW_CORRELATION,
 *   TOO_FEW_POINTS, PREDICTED, RECOVERING, RECOVERED, WEAK_*, SUSPECT;
 *   not NOT_CONVERGED, which most lines of this scene carry).
 * The counters are printed at the end (INFO lines).
 *
 * Found by it (docs/robustness.md, "Soak under faults"):
 * - line noise of 200 .. 600 ms was not always recovered within 2 s of
 *   its end: a 06 in the noise (or the scanner's own ACK, with the A0
 *   lost) taken as the probe's ACK held the session for the whole reply
 *   timeout (3.5 s, sized for mode changes): up to 4.3 s. Fixed in the
 *   session (junk after the ACK sends the command again after
 *   ack_timeout_us); every fault is now held to 2 s.
 * - under byte damage one service of the core could publish two scans
 *   (the framer finds a whole telegram again in the bytes held for a
 *   damaged one, and the next one completes in the same chunk), so the
 *   first was replaced in the mailbox although one_scan_per_service
 *   promises one per service: `lmsego run` dropped a good scan (64 in
 *   the hour). Fixed in the core (a service stops at its scan and keeps
 *   the rest of its chunk); no scan may be replaced now.
 *
 * Length: SOAK_CI_SECONDS of simulated time in CI (300 s optimised, 120 s
 * in the -O0 builds of the asan and clang presets); the
 * environment variable LMSEGO_SOAK_SECONDS sets another (3600: the hour of
 * issue 18, run by hand, docs/robustness.md), and LMSEGO_SOAK_SEED the
 * schedule's seed (default 1).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ego_live.h"
#include "lms_encode.h"
#include "lms_sim.h"
#include "synth_scan.h"
#include "unity.h"

#define SEC 1000000u
#define MS 1000u
#define STEP_US 1000u            /* the board's tick: bytes handed over each ms */
#define PERIOD_US 13333u         /* 75 Hz, 181 values */
#define LAP_SCANS 1500u          /* scene scans per lap (20 s) */
#define SENT_LOG 8192u           /* scans handed to the simulator, newest last */
#define MATCH_REACH 4096u        /* how far past the last match a taken scan is looked for */
#define RECOVERY_US (2u * SEC)   /* issue 18: every fault recovered within 2 s */
#define GIVE_UP_US (20u * SEC)   /* a fault not recovered by then is a failure */
/* Simulated seconds in CI: 300 optimised (about 3 s), 120 at -O0 (the
 * asan and clang presets: about 13 s under ASan). */
#if defined(__OPTIMIZE__)
#define SOAK_CI_SECONDS 300u
#else
#define SOAK_CI_SECONDS 120u
#endif
#define WRONG_M 0.10
#define WRONG_RAD (1.0 * PI_D / 180.0)
#define PI_D 3.14159265358979323846
/* The flags that say "do not trust this motion" (issue 18's list): every
 * EGO_FLAG_* but FIRST (no motion: not compared) and NOT_CONVERGED (an
 * iteration cap or budget reached: on most lines of this scene, and not a
 * statement that the motion is wrong). */
#define TRUST_FLAGS                                                                             \
    (EGO_FLAG_APERTURE | EGO_FLAG_LOW_CORRELATION | EGO_FLAG_TOO_FEW_POINTS |                   \
     EGO_FLAG_PREDICTED | EGO_FLAG_RECOVERING | EGO_FLAG_RECOVERED | EGO_FLAG_WEAK_ROTATION |   \
     EGO_FLAG_WEAK_TRANSLATION | EGO_FLAG_WEAK_COUPLED | EGO_FLAG_SUSPECT | EGO_FLAG_ON_OBJECTS)
#define LINE_MAX_CHARS 256u

typedef enum {
    F_POWER,
    F_HANGUP,
    F_SILENCE,
    F_NAK,
    F_GARBAGE,
    F_BAUD,
    F_DAMAGE,
    F_KINDS
} fault_kind_t;

static const char *const k_fault_names[F_KINDS] = {"power",   "hangup", "silence", "nak",
                                                   "garbage", "baud",   "damage"};

typedef struct {
    fault_kind_t kind;
    bool active;
    bool needs_restart;   /* must restart the session */
    bool no_restart;      /* must not */
    bool end_known;
    bool cleared;         /* nak, damage: the simulator's faults off again */
    uint64_t start_us;
    uint64_t end_us;      /* the fault's end (recovery counted from here) */
    uint32_t sent_at_set; /* scans_sent when it was set */
    uint32_t restarts_at_start;
    uint32_t param;       /* duration (us) or rate */
    uint32_t power_cycles_at_set;
} fault_t;

typedef struct {
    uint32_t injected[F_KINDS];
    uint32_t recovered[F_KINDS];
    uint64_t worst_us[F_KINDS];
    uint64_t sum_us[F_KINDS];
    uint32_t late;            /* recovered beyond RECOVERY_US (or never) */
    uint32_t restart_missing; /* a fault that must restart did not */
    uint32_t restart_extra;   /* a fault that must not restart did */
    uint32_t restarts_outside;
    uint32_t restart_faults;  /* recovered faults that needed a restart */
    uint32_t restarts_in_faults; /* the restarts they took */
    uint32_t restart_faults_twice; /* ... more than one */
    uint32_t lost_outside;
    uint32_t lost_in_faults;
    uint32_t unmatched;       /* taken scans that are no sent scan */
    uint32_t unmatched_outside; /* ... but in byte damage or line noise */
    uint32_t lines;
    uint32_t compared;
    uint32_t wrong;
    uint32_t wrong_flagged;
    uint32_t wrong_unflagged;
    uint32_t flagged;
    uint32_t first_lines;
    uint32_t by_flag[12];     /* lines with EGO_FLAG_ bit b */
    double worst_m;           /* the largest errors of an unflagged line */
    double worst_rad;
} counters_t;

typedef struct {
    uint32_t scene;       /* absolute scene index */
    bool sent;
} sent_t;

typedef struct {
    /* Grouped by size (no padding). The board. */
    lms_sim_t sim;
    ego_live_t live;
    uart_ring_t ring;
    /* The scene's scans handed out, in order. */
    sent_t sent[SENT_LOG];
    fault_t fault;
    counters_t c;
    uint64_t now;
    uint64_t line_up_at_us;
    uint64_t noisy_until_us;
    uint64_t next_fault_us;
    size_t line_len;
    lms_baud_t host_baud;
    uint32_t rnd;             /* the schedule's PRNG */
    uint32_t noise;           /* the line noise's PRNG */
    uint32_t sent_count;      /* entries ever written */
    uint32_t match_pos;       /* next entry a taken scan may be */
    /* Taken scans and their lines. */
    uint32_t taken;
    uint32_t ref_scene;       /* the scan the next motion starts from */
    uint32_t cur_scene;
    uint32_t search_start;
    /* Faults: the kinds in a shuffled bag, refilled when empty. */
    uint32_t bag_left;
    fault_kind_t bag[F_KINDS];
    uint32_t print_lines;     /* lines to print (after an unmatched scan) */
    bool line_down;           /* a hang-up: nothing passes */
    bool noisy;               /* garbage burst */
    bool asked;
    bool have_ref;
    bool in_recovering;
    bool header_seen;
    char line[LINE_MAX_CHARS];
} soak_t;

static soak_t S;

void setUp(void)
{
}

void tearDown(void)
{
}

static uint32_t rnd_next(uint32_t *state)
{
    uint32_t x = *state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *state = x;
    return x;
}

/* lo .. hi inclusive. */
static uint32_t rnd_range(uint32_t lo, uint32_t hi)
{
    return lo + rnd_next(&S.rnd) % (hi - lo + 1u);
}

/* --- The scene ---------------------------------------------------------- */

typedef struct {
    double x, y, heading;
} pose_t;

static pose_t scene_pose(uint32_t i)
{
    const double phi = 2.0 * PI_D * (double)(i % LAP_SCANS) / (double)LAP_SCANS;
    const double a = 4.0;
    const double b = 2.5;
    const pose_t p = {1.5 + a * cos(phi), b * sin(phi), atan2(b * cos(phi), -a * sin(phi))};
    return p;
}

typedef struct {
    uint8_t bytes[LMS_TELEGRAM_MAX];
    size_t len;
} telegram_t;

static telegram_t g_lap[LAP_SCANS];
static bool g_lap_built;

static void build_lap(void)
{
    static lms_scan_t scan;
    if (g_lap_built) {
        return;
    }
    for (uint32_t i = 0u; i < LAP_SCANS; i++) {
        const pose_t p = scene_pose(i);
        synth_scan(synth_room, synth_room_walls, p.x, p.y, p.heading, 181u, LMS_UNIT_CM, &scan);
        TEST_ASSERT_EQUAL_INT(LMS_OK, lms_encode_scan(g_lap[i].bytes, sizeof g_lap[i].bytes, 0x80u,
                                                      &scan, &g_lap[i].len));
    }
    g_lap_built = true;
}

static double wrap_pi(double a)
{
    while (a > PI_D) {
        a -= 2.0 * PI_D;
    }
    while (a < -PI_D) {
        a += 2.0 * PI_D;
    }
    return a;
}

/* Scene scan `to` in the frame of scene scan `from`. */
static pose_t true_motion(uint32_t from, uint32_t to)
{
    const pose_t a = scene_pose(from);
    const pose_t b = scene_pose(to);
    const double dx = b.x - a.x;
    const double dy = b.y - a.y;
    const double c = cos(a.heading);
    const double s = sin(a.heading);
    const pose_t m = {c * dx + s * dy, -s * dx + c * dy, wrap_pi(b.heading - a.heading)};
    return m;
}

/* The simulator's next scan: the scene scan of the time it is asked for
 * (a period before it is sent), never the same one twice. A new stream
 * (k = 0) asks again for the scan it never sent. */
static bool source(void *ctx, uint32_t k, uint16_t angle_deg, uint16_t resolution_cdeg,
                   bool partial, lms_unit_t unit, uint8_t reply_address, uint8_t *out, size_t cap,
                   size_t *len, uint32_t *gap_us)
{
    (void)ctx;
    (void)angle_deg;
    (void)resolution_cdeg;
    (void)partial;
    (void)unit;
    (void)reply_address;
    if (S.asked) {
        /* The one asked last was sent unless this starts a new stream. */
        S.sent[(S.sent_count - 1u) % SENT_LOG].sent = k != 0u;
    }
    uint32_t scene = (uint32_t)(S.now / PERIOD_US) + 1u;
    if (S.asked) {
        const uint32_t last = S.sent[(S.sent_count - 1u) % SENT_LOG].scene;
        scene = scene > last ? scene : last + 1u;
    }
    S.asked = true;
    sent_t *e = &S.sent[S.sent_count % SENT_LOG];
    e->scene = scene;
    e->sent = false;
    S.sent_count++;
    const telegram_t *t = &g_lap[scene % LAP_SCANS];
    if (t->len > cap) {
        return false;
    }
    memcpy(out, t->bytes, t->len);
    *len = t->len;
    *gap_us = 0u;
    return true;
}

/* --- The board ---------------------------------------------------------- */

static void hal_scanner_write(void *ctx, const uint8_t *bytes, size_t len)
{
    soak_t *s = ctx;
    if (!s->line_down) {
        lms_sim_receive(&s->sim, bytes, len, s->host_baud, s->now);
    }
}

static void hal_set_baud(void *ctx, lms_baud_t baud)
{
    soak_t *s = ctx;
    s->host_baud = baud;
}

static uint32_t hal_now_us(void *ctx)
{
    const soak_t *s = ctx;
    return (uint32_t)s->now;
}

static void check_line(const char *line);

static void hal_out(void *ctx, const uint8_t *bytes, size_t len)
{
    soak_t *s = ctx;
    for (size_t i = 0u; i < len; i++) {
        if (bytes[i] == '\n') {
            s->line[s->line_len] = '\0';
            if (s->header_seen) {
                check_line(s->line);
            }
            s->header_seen = true;
            s->line_len = 0u;
        } else if (s->line_len + 1u < sizeof s->line) {
            s->line[s->line_len++] = (char)bytes[i];
        }
    }
}

/* What the line carries to the core by now. */
static void board_receive(void)
{
    static uint8_t buf[1024];
    for (int guard = 0; guard < 64; guard++) {
        const size_t n = lms_sim_transmit(&S.sim, S.host_baud, S.now, buf, sizeof buf);
        if (S.noisy) {
            for (size_t i = 0u; i < n; i++) {
                buf[i] = (uint8_t)(rnd_next(&S.noise) >> 24);
            }
        }
        if (!S.line_down) {
            (void)uart_ring_write(&S.ring, buf, n, (uint32_t)S.now);
        }
        if (n < sizeof buf) {
            return;
        }
    }
}

/* --- Faults ------------------------------------------------------------- */

static uint32_t restarts(void)
{
    return lms_session_stats(ego_live_session(&S.live))->restarts;
}

static bool fault_needs_restart(fault_kind_t kind, uint32_t param)
{
    switch (kind) {
    case F_POWER:
    case F_HANGUP:
    case F_SILENCE:
    case F_NAK:
    case F_BAUD:
        return true;
    case F_GARBAGE:
        return param >= 200u * MS;
    case F_DAMAGE:
    case F_KINDS:
    default:
        return false;
    }
}

static void line_hangs_up(uint32_t down_us)
{
    S.line_down = true;
    S.line_up_at_us = S.now + down_us;
    ego_live_link_lost(&S.live);
}

/* Another host's 20 4x at the scanner's own rate. */
static void foreign_baud_switch(lms_baud_t to)
{
    lms_cmd_t cmd;
    TEST_ASSERT_EQUAL_INT(LMS_OK, lms_cmd_baud(&cmd, 0u, to));
    lms_sim_receive(&S.sim, cmd.bytes, cmd.len, lms_sim_baud(&S.sim), S.now);
}

static void inject(fault_kind_t kind)
{
    fault_t *f = &S.fault;
    memset(f, 0, sizeof *f);
    f->kind = kind;
    f->active = true;
    f->start_us = S.now;
    f->restarts_at_start = restarts();
    f->sent_at_set = lms_sim_stats(&S.sim)->scans_sent;
    f->power_cycles_at_set = lms_sim_stats(&S.sim)->power_cycles;
    lms_sim_faults_t sf;
    memset(&sf, 0, sizeof sf);
    switch (kind) {
    case F_POWER:
        sf.power_cycle_after_scans = 1u;
        lms_sim_set_faults(&S.sim, &sf);
        break;
    case F_HANGUP:
        f->param = rnd_range(200u, 1000u) * MS;
        sf.hangup_after_scans = 1u;
        lms_sim_set_faults(&S.sim, &sf);
        break;
    case F_SILENCE:
        f->param = rnd_range(100u, 1500u) * MS;
        sf.silence_after_scans = 1u;
        sf.silence_us = f->param;
        lms_sim_set_faults(&S.sim, &sf);
        break;
    case F_NAK:
        f->param = rnd_range(1000u, 4000u) * MS;
        sf.nak_percent = rnd_range(40u, 90u);
        sf.hangup_after_scans = 1u;
        lms_sim_set_faults(&S.sim, &sf);
        f->end_us = S.now + f->param;
        f->end_known = true;
        break;
    case F_GARBAGE:
        f->param = (rnd_next(&S.rnd) % 2u == 0u ? rnd_range(5u, 60u) : rnd_range(200u, 600u)) * MS;
        S.noisy = true;
        S.noisy_until_us = S.now + f->param;
        f->end_us = S.noisy_until_us;
        f->end_known = true;
        break;
    case F_BAUD: {
        static const lms_baud_t others[] = {LMS_BAUD_9600, LMS_BAUD_19200, LMS_BAUD_38400};
        const lms_baud_t to = others[rnd_next(&S.rnd) % 3u];
        f->param = (uint32_t)to;
        foreign_baud_switch(to);
        /* The switch follows the A0; a few ms at 500 kbaud. */
        f->end_us = S.now + 2u * MS;
        f->end_known = true;
        break;
    }
    case F_DAMAGE:
        f->param = rnd_range(2000u, 10000u) * MS;
        sf.drop_ppm = rnd_range(20u, 200u);
        sf.flip_ppm = rnd_range(20u, 200u);
        sf.insert_ppm = rnd_range(20u, 200u);
        lms_sim_set_faults(&S.sim, &sf);
        f->end_us = S.now + f->param;
        f->end_known = true;
        break;
    case F_KINDS:
    default:
        break;
    }
    f->needs_restart = fault_needs_restart(kind, f->param);
    f->no_restart = kind == F_DAMAGE || (kind == F_GARBAGE && f->param <= 60u * MS);
    S.c.injected[kind]++;
}

/* The fault's progress at S.now: when the one-shot ones fired, the end of
 * windows. */
static void fault_tick(void)
{
    fault_t *f = &S.fault;
    if (S.line_down && S.now >= S.line_up_at_us) {
        S.line_down = false;
    }
    if (S.noisy && S.now >= S.noisy_until_us) {
        S.noisy = false;
    }
    if (lms_sim_take_hangup(&S.sim)) {
        const uint32_t down = f->kind == F_HANGUP ? f->param : 200u * MS;
        line_hangs_up(down);
        if (f->kind == F_HANGUP) {
            f->end_us = S.line_up_at_us;
            f->end_known = true;
        }
    }
    if (!f->active) {
        return;
    }
    const lms_sim_stats_t *st = lms_sim_stats(&S.sim);
    if (f->kind == F_POWER && !f->end_known && st->power_cycles != f->power_cycles_at_set) {
        f->end_us = S.now + 100u * MS; /* lms_sim_defaults' power-on delay */
        f->end_known = true;
    }
    if (f->kind == F_SILENCE && !f->end_known && st->scans_sent != f->sent_at_set) {
        /* Armed on the scan queued after the set, it starts when that
         * scan's last byte is on the wire (about 372 bytes of 20 us). */
        f->end_us = S.now + 7500u + f->param;
        f->end_known = true;
    }
    if ((f->kind == F_NAK || f->kind == F_DAMAGE) && !f->cleared && S.now >= f->end_us) {
        f->cleared = true;
        lms_sim_faults_t none;
        memset(&none, 0, sizeof none);
        lms_sim_set_faults(&S.sim, &none);
    }
}

/* A scan was taken at S.now: recovery of the fault in hand? */
static void fault_on_scan(void)
{
    fault_t *f = &S.fault;
    if (!f->active || !f->end_known || S.now < f->end_us) {
        return;
    }
    if (f->needs_restart && restarts() == f->restarts_at_start) {
        return; /* a scan from before the restart: not recovered yet */
    }
    const uint64_t took = S.now - f->end_us;
    S.c.recovered[f->kind]++;
    S.c.sum_us[f->kind] += took;
    S.c.worst_us[f->kind] = took > S.c.worst_us[f->kind] ? took : S.c.worst_us[f->kind];
    if (took > RECOVERY_US) {
        S.c.late++;
        printf("INFO soak: %s at %.3f s (param %u) recovered %.3f s after its end\n",
               k_fault_names[f->kind], (double)f->start_us / SEC, f->param, (double)took / SEC);
    }
    const uint32_t r = restarts() - f->restarts_at_start;
    if (f->needs_restart) {
        S.c.restart_faults++;
        S.c.restarts_in_faults += r;
        S.c.restart_faults_twice += r > 1u ? 1u : 0u;
    }
    if (f->no_restart && r > 0u) {
        S.c.restart_extra++;
        printf("INFO soak: %s at %.3f s (param %u) restarted the session %u times\n",
               k_fault_names[f->kind], (double)f->start_us / SEC, f->param, r);
    }
    f->active = false;
    S.next_fault_us = S.now + rnd_range(1000u, 15000u) * MS;
}

static void fault_give_up(void)
{
    fault_t *f = &S.fault;
    if (f->active && S.now > f->start_us + GIVE_UP_US) {
        S.c.late++;
        printf("INFO soak: %s at %.3f s (param %u) not recovered in %u s\n",
               k_fault_names[f->kind], (double)f->start_us / SEC, f->param, GIVE_UP_US / SEC);
        if (f->needs_restart && restarts() == f->restarts_at_start) {
            S.c.restart_missing++;
        }
        f->active = false;
        S.next_fault_us = S.now + SEC;
    }
}

/* --- Scans and lines ---------------------------------------------------- */

/* The taken telegram among the scans sent since the last match. */
static void on_scan(const ego_live_slot_t *slot)
{
    S.taken++;
    uint32_t lost = 0u;
    for (uint32_t i = S.match_pos; i < S.sent_count && i < S.match_pos + MATCH_REACH; i++) {
        const sent_t *e = &S.sent[i % SENT_LOG];
        const telegram_t *t = &g_lap[e->scene % LAP_SCANS];
        if (t->len == slot->len && memcmp(t->bytes, slot->bytes, t->len) == 0) {
            S.match_pos = i + 1u;
            S.cur_scene = e->scene;
            if (lost > 0u) {
                if (S.fault.active || slot->gap) {
                    S.c.lost_in_faults += lost;
                } else {
                    S.c.lost_outside += lost;
                    printf("INFO soak: %u scans lost outside a fault at %.3f s\n", lost,
                           (double)S.now / SEC);
                }
            }
            fault_on_scan();
            return;
        }
        lost += e->sent ? 1u : 0u;
    }
    /* A damaged telegram that passed the CRC: most likely the first scan
     * sent after the last match. Its line is still checked, as that scan,
     * and printed with the next one. */
    S.c.unmatched++;
    if (!S.fault.active || (S.fault.kind != F_DAMAGE && S.fault.kind != F_GARBAGE)) {
        S.c.unmatched_outside++;
    }
    S.cur_scene = UINT32_MAX;
    for (uint32_t i = S.match_pos; i < S.sent_count; i++) {
        if (S.sent[i % SENT_LOG].sent) {
            S.cur_scene = S.sent[i % SENT_LOG].scene;
            break;
        }
    }
    S.print_lines = 2u;
    fault_on_scan();
    printf("INFO soak: a scan taken at %.3f s is none of the scans sent (%s)\n",
           (double)S.now / SEC, S.fault.active ? k_fault_names[S.fault.kind] : "no fault");
}

/* Field n (0-based) of a CSV line as a double. */
static double csv_field(const char *line, unsigned n)
{
    for (unsigned i = 0u; i < n && line != NULL; i++) {
        line = strchr(line, ',');
        line = line != NULL ? line + 1 : NULL;
    }
    return line != NULL ? strtod(line, NULL) : NAN;
}

/* One line: its motion against the scene's. */
static void check_line(const char *line)
{
    S.c.lines++;
    if (S.print_lines > 0u) {
        S.print_lines--;
        printf("INFO soak: line at %.3f s: %s\n", (double)S.now / SEC, line);
    }
    const double dx = csv_field(line, 2u);
    const double dy = csv_field(line, 3u);
    const double dth = csv_field(line, 4u);
    const unsigned flags = (unsigned)csv_field(line, 8u);
    if ((flags & TRUST_FLAGS) != 0u) {
        S.c.flagged++;
    }
    for (unsigned b = 0u; b < 12u; b++) {
        S.c.by_flag[b] += (flags >> b) & 1u;
    }
    if (S.cur_scene == UINT32_MAX) {
        S.have_ref = false;
        return;
    }
    if ((flags & EGO_FLAG_FIRST) != 0u || !S.have_ref) {
        S.c.first_lines++;
        S.have_ref = true;
        S.ref_scene = S.cur_scene;
        S.in_recovering = false;
        return;
    }
    uint32_t to = S.cur_scene;
    if ((flags & EGO_FLAG_RECOVERING) != 0u && (flags & EGO_FLAG_RECOVERED) == 0u) {
        /* No motion claimed; the search (if one started) started here. */
        if (!S.in_recovering) {
            S.in_recovering = true;
            S.search_start = S.cur_scene;
        }
        return;
    }
    if ((flags & EGO_FLAG_RECOVERED) != 0u && S.in_recovering) {
        to = S.search_start;
    }
    S.in_recovering = false;
    const pose_t m = true_motion(S.ref_scene, to);
    S.ref_scene = to;
    S.c.compared++;
    const double et = hypot(dx - m.x, dy - m.y);
    const double er = fabs(wrap_pi(dth - m.heading));
    if ((flags & TRUST_FLAGS) == 0u) {
        S.c.worst_m = et > S.c.worst_m ? et : S.c.worst_m;
        S.c.worst_rad = er > S.c.worst_rad ? er : S.c.worst_rad;
    }
    if (et > WRONG_M || er > WRONG_RAD || isnan(et) || isnan(er)) {
        S.c.wrong++;
        if ((flags & TRUST_FLAGS) != 0u) {
            S.c.wrong_flagged++;
        } else {
            S.c.wrong_unflagged++;
            printf("INFO soak: unflagged wrong line at %.3f s (seed %s): %s; true %.4f %.4f %.5f "
                   "(scenes %u -> %u)\n",
                   (double)S.now / SEC, getenv("LMSEGO_SOAK_SEED") ? getenv("LMSEGO_SOAK_SEED") : "1",
                   line, m.x, m.y, m.heading, S.ref_scene, to);
        }
    }
}

/* --- The run ------------------------------------------------------------ */

static uint32_t env_u32(const char *name, uint32_t fallback)
{
    const char *v = getenv(name);
    if (v == NULL || *v == '\0') {
        return fallback;
    }
    char *end = NULL;
    const unsigned long n = strtoul(v, &end, 10);
    return (end != NULL && *end == '\0' && n > 0u && n <= 4000u * 1000u) ? (uint32_t)n : fallback;
}

static void soak_init(uint32_t seed)
{
    build_lap();
    memset(&S, 0, sizeof S);
    S.now = 1000u;
    S.host_baud = LMS_BAUD_9600;
    S.rnd = seed * 2654435761u + 1u;
    S.noise = seed ^ 0x9E3779B9u;
    S.cur_scene = UINT32_MAX;
    lms_sim_config_t sc;
    lms_sim_defaults(&sc);
    sc.scan_source = source;
    sc.faults.seed = seed;
    lms_sim_init(&S.sim, &sc, S.now);
    ego_live_config_t lc;
    ego_live_defaults(&lc);
    lc.session.baud = LMS_BAUD_500000;
    lc.session.angle_deg = 180u;
    lc.session.resolution_cdeg = 100u;
    lc.deferred = true; /* as `lmsego run` */
    lc.one_scan_per_service = true;
    uart_ring_init(&S.ring);
    const ego_live_hal_t hal = {hal_scanner_write, hal_set_baud, hal_now_us, hal_out, &S};
    TEST_ASSERT_EQUAL_INT(LMS_OK, ego_live_init(&S.live, &lc, &hal, &S.ring));
    S.next_fault_us = 3u * SEC;
}

/* Every kind once in a random order, then again: every kind within the
 * first seven faults, whatever the length. */
static fault_kind_t next_kind(void)
{
    if (S.bag_left == 0u) {
        for (uint32_t i = 0u; i < (uint32_t)F_KINDS; i++) {
            S.bag[i] = (fault_kind_t)i;
        }
        for (uint32_t i = (uint32_t)F_KINDS - 1u; i > 0u; i--) {
            const uint32_t j = rnd_next(&S.rnd) % (i + 1u);
            const fault_kind_t t = S.bag[i];
            S.bag[i] = S.bag[j];
            S.bag[j] = t;
        }
        S.bag_left = (uint32_t)F_KINDS;
    }
    S.bag_left--;
    return S.bag[S.bag_left];
}

static void soak_run(uint64_t seconds)
{
    const uint64_t until = S.now + seconds * SEC;
    uint32_t restarts_seen = 0u;
    /* LMSEGO_SOAK_TRACE=FROM_S: the session's states from then on, 10 s. */
    const uint64_t trace_from = (uint64_t)env_u32("LMSEGO_SOAK_TRACE", 0u) * SEC;
    lms_session_state_t traced = LMS_SESSION_PROBE;
    uint32_t trace_timeouts = 0u;
    while (S.now < until) {
        S.now += STEP_US;
        fault_tick();
        board_receive();
        for (int guard = 0; guard < 16; guard++) {
            const uint32_t skipped = ego_live_stats(&S.live)->scans_skipped;
            ego_live_service(&S.live);
            if (ego_live_stats(&S.live)->scans_skipped != skipped) {
                /* Two scans published by one service (see the header): when,
                 * for the final check's failure. */
                printf("INFO soak: a scan replaced in the mailbox at %.3f s (%s)\n",
                       (double)S.now / SEC, S.fault.active ? k_fault_names[S.fault.kind] : "no fault");
            }
            const ego_live_slot_t *slot = ego_live_take(&S.live);
            if (slot != NULL) {
                on_scan(slot);
                ego_live_estimate_slot(&S.live, slot);
            }
            if (slot == NULL && ego_live_wait_us(&S.live) > 0u) {
                break;
            }
        }
        TEST_ASSERT_EQUAL_INT(EGO_LIVE_RUNNING, ego_live_status(&S.live));
        const lms_session_state_t state = lms_session_state(ego_live_session(&S.live));
        const lms_session_stats_t *ss = lms_session_stats(ego_live_session(&S.live));
        if (trace_from > 0u && S.now >= trace_from && S.now < trace_from + 10u * SEC &&
            (state != traced || ss->reply_timeouts + ss->ack_timeouts != trace_timeouts)) {
            printf("TRACE %.3f %s host %u sim %u ack_timeouts %u reply_timeouts %u\n",
                   (double)S.now / SEC, lms_session_state_name(state), (unsigned)S.host_baud,
                   (unsigned)lms_sim_baud(&S.sim), ss->ack_timeouts, ss->reply_timeouts);
        }
        trace_timeouts = ss->reply_timeouts + ss->ack_timeouts;
        traced = state;
        const uint32_t r = restarts();
        if (r != restarts_seen) {
            if (!S.fault.active) {
                S.c.restarts_outside += r - restarts_seen;
                printf("INFO soak: restart outside a fault at %.3f s\n", (double)S.now / SEC);
            }
            restarts_seen = r;
        }
        fault_give_up();
        if (!S.fault.active && S.now >= S.next_fault_us && S.now + 5u * SEC < until) {
            inject(next_kind());
        }
    }
}

static void report_and_check(uint32_t seconds, uint32_t seed)
{
    const lms_sim_stats_t *st = lms_sim_stats(&S.sim);
    const lms_session_stats_t *ss = lms_session_stats(ego_live_session(&S.live));
    const ego_live_stats_t *ls = ego_live_stats(&S.live);
    printf("INFO soak: %u s simulated, seed %u\n", seconds, seed);
    uint32_t faults = 0u;
    for (unsigned k = 0u; k < (unsigned)F_KINDS; k++) {
        faults += S.c.injected[k];
        printf("INFO soak: %-8s injected %3u recovered %3u worst %6.3f s mean %6.3f s\n",
               k_fault_names[k], S.c.injected[k], S.c.recovered[k],
               (double)S.c.worst_us[k] / SEC,
               S.c.recovered[k] > 0u ? (double)S.c.sum_us[k] / S.c.recovered[k] / SEC : 0.0);
    }
    /* Scans in flight at the end: sent, not taken yet. */
    uint32_t tail = 0u;
    for (uint32_t i = S.match_pos; i < S.sent_count; i++) {
        tail += S.sent[i % SENT_LOG].sent ? 1u : 0u;
    }
    printf("INFO soak: faults %u late %u restart_missing %u restart_extra %u restarts %u "
           "(silence %u power-on %u link %u) restarts_outside %u gaps %u\n",
           faults, S.c.late, S.c.restart_missing, S.c.restart_extra, ss->restarts,
           ss->restarts_silence, ss->restarts_power_on, ss->restarts_link, S.c.restarts_outside,
           ls->gaps);
    printf("INFO soak: faults needing a restart %u, their restarts %u (%u faults took more than "
           "one)\n",
           S.c.restart_faults, S.c.restarts_in_faults, S.c.restart_faults_twice);
    printf("INFO soak: scans sent %u taken %u lost in faults %u lost outside %u in flight %u "
           "unmatched %u (outside damage and noise %u); sim power_cycles %u baud_changes %u naks %u dropped %u flipped %u "
           "inserted %u; session scans %u bring_ups %u naks %u stray %u flushes %u\n",
           st->scans_sent, S.taken, S.c.lost_in_faults, S.c.lost_outside, tail, S.c.unmatched,
           S.c.unmatched_outside,
           st->power_cycles, st->baud_changes, st->naks_injected, st->bytes_dropped,
           st->bytes_flipped, st->bytes_inserted, ss->scans, ss->bring_ups, ss->naks,
           ss->stray_telegrams, ss->flushes);
    printf("INFO soak: lines %u compared %u first %u flagged %u wrong %u (flagged %u, "
           "unflagged %u)\n",
           S.c.lines, S.c.compared, S.c.first_lines, S.c.flagged, S.c.wrong, S.c.wrong_flagged,
           S.c.wrong_unflagged);
    printf("INFO soak: largest error of an unflagged line: %.4f m, %.4f deg\n", S.c.worst_m,
           S.c.worst_rad * 180.0 / PI_D);

    printf("INFO soak: core scans %u replaced in the mailbox %u estimated %u\n", ls->scans,
           ls->scans_skipped, ls->scans_estimated);
    printf("INFO soak: lines by flag bit 0..11:");
    for (unsigned b = 0u; b < 12u; b++) {
        printf(" %u", S.c.by_flag[b]);
    }
    printf("\n");
    for (unsigned k = 0u; k < (unsigned)F_KINDS; k++) {
        TEST_ASSERT_TRUE_MESSAGE(S.c.injected[k] > 0u, k_fault_names[k]);
    }
    TEST_ASSERT_EQUAL_UINT32(0u, S.c.late);
    TEST_ASSERT_EQUAL_UINT32(0u, S.c.restart_missing);
    TEST_ASSERT_EQUAL_UINT32(0u, S.c.restart_extra);
    TEST_ASSERT_EQUAL_UINT32(0u, S.c.restarts_outside);
    TEST_ASSERT_EQUAL_UINT32(0u, S.c.lost_outside);
    /* A damaged telegram may pass the 16-bit CRC (about one in 65536):
     * only where bytes are damaged, and its line is checked like any. */
    TEST_ASSERT_EQUAL_UINT32(0u, S.c.unmatched_outside);
    TEST_ASSERT_EQUAL_UINT32(ss->restarts, ls->gaps);
    /* Every restart belongs to a fault that needs one. */
    TEST_ASSERT_EQUAL_UINT32(ss->restarts, S.c.restarts_in_faults);
    /* The last scan may wait in the mailbox; none was replaced there. */
    TEST_ASSERT_EQUAL_UINT32(ss->scans, ls->scans);
    TEST_ASSERT_TRUE(ls->scans - S.taken <= 1u);
    TEST_ASSERT_EQUAL_UINT32(0u, ls->scans_skipped);
    TEST_ASSERT_EQUAL_UINT32(st->scans_sent, S.taken - S.c.unmatched + S.c.lost_in_faults + tail);
    TEST_ASSERT_TRUE(tail <= 2u);
    TEST_ASSERT_EQUAL_UINT32(S.taken - 1u, S.c.lines);
    TEST_ASSERT_EQUAL_UINT32(0u, S.c.wrong_unflagged);
}

static void test_soak_under_faults(void)
{
    const uint32_t seconds = env_u32("LMSEGO_SOAK_SECONDS", SOAK_CI_SECONDS);
    const uint32_t seed = env_u32("LMSEGO_SOAK_SEED", 1u);
    soak_init(seed);
    soak_run(seconds);
    report_and_check(seconds, seed);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_soak_under_faults);
    return UNITY_END();
}
