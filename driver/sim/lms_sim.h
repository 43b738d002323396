/* lms_sim.h - a simulated SICK LMS 2xx: the scanner's side of the serial
 * protocol as a pure state machine with an injected clock.
 *
 * Portable C11 (no OS headers, no heap, no stdio), so that unit tests run
 * the session against it in-process with a simulated clock, and the host
 * tools (lmsego sim, lmsego play: driver/posix/lms_pty wraps it on a
 * pseudo-terminal) use the same code.
 *
 * The line model. Both ends have a rate. The caller tells the simulator,
 * with every call, the rate the host side of the line is set to
 * (host_baud). Bytes written by the host while host_baud differs from the
 * scanner's rate arrive garbled: the simulator counts and ignores them
 * (a real UART would see framing errors). Bytes the scanner sends leave
 * at the scanner's rate, 10 bit times each (8N1), through an output queue:
 * lms_sim_transmit hands out the bytes whose last bit is on the wire by
 * `now`. While the rates differ, each byte handed out is replaced by
 * deterministic garbage, and the count scales with the rate ratio (a 500
 * kbaud telegram read at 9600 is a few bytes of noise). The rule: every
 * byte remembers the rate it left at; an accumulator gains the host's
 * bits per second for each garbled scanner byte and yields one garbage
 * byte per whole scanner bits per second it holds (so 52 bytes read at
 * 500 kbaud for each byte sent at 9600, one byte per 52 the other way).
 * Every garbage byte has its top bit set (0x80 | a counter mixed with the
 * byte it replaces), so it can never be STX, ACK or NAK: at the wrong rate
 * a driver sees nothing valid, ever. Output faults (below) do not apply to
 * garbled bytes.
 *
 * Behaviour (facts: docs/protocol.md, ../shared/reference/lms2xx-protocol.md):
 * - power-up: silent for power_on_delay_us (host bytes are ignored), then
 *   the 90 power-on telegram at power_on_baud; idle in mode 25; variant
 *   180 deg / 0.5 deg; units and measuring mode from the EEPROM block,
 *   which only lms_sim_init sets up (resets and power cycles keep it).
 * - every CRC-valid host telegram addressed to the scanner (address 0 or
 *   its own; others are ignored and counted) gets an ACK (06) at once and
 *   then its reply after reply_delay_us (77 after config_write_delay_us);
 *   a telegram with a bad CRC gets a NAK (15); unknown or disallowed
 *   commands, and known ones with wrong parameters, get 92. Commands are
 *   answered one at a time in arrival order: a command's delay starts
 *   when the previous reply went out (LMS_SIM_CMD_QUEUE of them wait;
 *   more are ignored and counted in cmds_dropped, without an ACK). State
 *   changes take effect when the reply is queued. Commands handled:
 *   10 (91, then, once the 91 is on the wire, a reboot: 90 after the
 *   power-on delay, back to power_on_baud),
 *   20 with modes 00 (the configured 8-character password, "SICK_LMS" by
 *   default: A0 00 and installation mode, else A0 01), 24, 25, 2A (A0 00),
 *   40/41/42/48 (A0 00 sent at the old rate, then the scanner switches
 *   once the A0's last byte is on the wire; the operating mode and a
 *   running stream are kept), other modes 92; any 20 mode other than 00
 *   that is accepted leaves installation mode (back to 25 if it was 00);
 *   30 01 (one B0 from the scan source in mode 25, else 92; 92 also when
 *   there is no source or it has no more scans), 31 (B1: firmware
 *   "V02.10 ", operating mode, measuring mode, variant, baud word,
 *   permanent-baud flag = power_on_baud is not 9600, address, units,
 *   laser on), 32 (B2, no errors), 3A (BA),
 *   3B (BB; refused while streaming with 92, refused with result 00 for
 *   an illegal pair or one that differs from the fixed variant), 74 (F4),
 *   77 (only in installation mode, else 92 after reply_delay_us; F7 01 and
 *   the new units / measuring mode take effect; F7 00 and nothing changes
 *   for a block of the other size, reserved units or an unknown measuring
 *   mode); 66 is answered with 92 and never obeyed.
 *   Replies carry address 0x80 | address and status byte 0x10.
 * - a host telegram left incomplete for more than LMS_SIM_HOST_GAP_US
 *   (scaled by speed_permille, but never below it) is abandoned, as the
 *   real scanner's 6 ms inter-byte limit does.
 * - streaming (modes 24 and 2A): a B0 per mirror rotation: every scan
 *   period (1/75 s at 1 deg, 1/37.5 s at 0.5 deg, 1/18.75 s at 0.25 deg,
 *   1/75 s for partial scans), scaled by speed_permille; the first one a
 *   period after the A0. A new scan is started only when the output queue
 *   is empty (at low rates the scanner skips the scan periods the line has
 *   no time for, as the real one does: scans_skipped counts them). Scans
 *   come from the scan source (below); a skipped period does not use one
 *   up: the scan waits for the next period, so k numbers the scans sent
 *   and has no gaps. The source is asked for scan k + 1 as soon as scan k
 *   is queued (so the gap it asks for is known in time); a source that has
 *   no more scans leaves the scanner silent in its streaming mode. A new
 *   stream starts again at k = 0; 20 24 while already in 24 (or 2A while
 *   in 2A) keeps the stream.
 *
 * Time scaling: with speed_permille = s (0 is taken as 1000), every
 * duration inside the scanner runs s / 1000 times faster: the scan period,
 * the reply and power-on delays, the silence fault and the byte time on
 * the wire. Byte and scan times are kept as exact fractions (no drift); a
 * byte is handed out at the first whole microsecond at or after its end.
 *
 * Faults (lms_sim_faults_t), each optional, all from one seeded PRNG
 * (xorshift32; seed 0 means a fixed nonzero default) so a run is
 * reproducible: per-byte probabilities of dropping, flipping one bit of,
 * or inserting a random byte after a byte of the scanner's output (applied
 * as bytes are handed out, so ACKs and replies are hit too); a probability
 * of answering a good host telegram with NAK (and nothing else); and three
 * one-shot events after a given number of streamed scans (counted from
 * lms_sim_init; each fires once per lms_sim_init, when that scan's last
 * byte is on the wire): silence for a duration (the scanner sends nothing,
 * defers its replies and ignores the host; the stream resumes with the
 * next scan number), a power cycle (as a reset without the 91: power-on
 * delay, 90 at power_on_baud, idle, variant reset, EEPROM kept), and a
 * hang-up (the simulator only raises a flag, lms_sim_take_hangup; the
 * pseudo-terminal wrapper acts on it).
 *
 * Time is a 64-bit microsecond count that never wraps; it must not go
 * backwards between calls (an earlier time is taken as the latest one
 * seen). Each call does at most LMS_SIM_MAX_STEPS events; work left over
 * (only after a huge jump in time) is done by the next call.
 */
#ifndef LMS_SIM_H
#define LMS_SIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lms_config.h"
#include "lms_decode.h"
#include "lms_framer.h"
#include "lms_proto.h"

/* Output queue: room for two of the largest telegrams and the replies.
 * Bytes stay in it until lms_sim_transmit hands them out. */
#define LMS_SIM_OUT_SIZE 2048u
/* Host commands waiting for their reply. */
#define LMS_SIM_CMD_QUEUE 4u
/* Largest command data kept (after the code): a 34-byte 77 block. */
#define LMS_SIM_CMD_DATA_MAX LMS_CONFIG_SIZE_MAX
/* The scanner's host inter-byte limit (protocol doc 6.2: 6 ms). */
#define LMS_SIM_HOST_GAP_US 6000u
/* Events handled per call at most (bounded work per call). */
#define LMS_SIM_MAX_STEPS 200000u

_Static_assert(LMS_SIM_OUT_SIZE >= 2u * LMS_TELEGRAM_MAX, "two of the largest telegrams");
_Static_assert(LMS_SIM_OUT_SIZE <= 0x8000u, "queue indices are 16 bits");

/* Next scan of the stream. Writes one complete B0 telegram (STX .. CRC,
 * as the scanner would send it; the simulator sends it verbatim) for scan
 * number k (0, 1, 2, ... counted from the start of this stream) in the
 * given variant and unit, into out (cap bytes), and its size into *len.
 * *gap_us: 0 to send it at the next mirror rotation, or the time wanted
 * since the previous scan (a recording played with its own timing).
 * Returns false when there are no more scans. A *len of 0 or above cap
 * is taken as "no more scans" too. */
typedef bool (*lms_sim_scan_fn)(void *ctx, uint32_t k, uint16_t angle_deg,
                                uint16_t resolution_cdeg, bool partial, lms_unit_t unit,
                                uint8_t reply_address, uint8_t *out, size_t cap, size_t *len,
                                uint32_t *gap_us);

typedef struct {
    uint32_t drop_ppm;   /* per output byte, parts per million */
    uint32_t flip_ppm;
    uint32_t insert_ppm;
    uint32_t nak_percent;           /* good host telegrams answered with NAK */
    uint32_t silence_after_scans;   /* 0: never */
    uint32_t silence_us;
    uint32_t power_cycle_after_scans; /* 0: never */
    uint32_t hangup_after_scans;      /* 0: never */
    uint32_t seed;
} lms_sim_faults_t;

typedef struct {
    uint8_t address;              /* 0x00..0x7F (bit 7 ignored); replies carry 0x80 | address */
    lms_baud_t power_on_baud;     /* LMS_BAUD_9600 unless a permanent rate is set
                                     (an unknown value: 9600) */
    uint32_t power_on_delay_us;   /* init / power cycle -> 90 telegram */
    uint32_t reply_delay_us;      /* ACK -> reply, most commands (default 10 ms) */
    uint32_t config_write_delay_us; /* ACK -> F7 (default 1 s) */
    char type_text[LMS_TYPE_TEXT_SIZE + 1u]; /* BA and 90 text, NUL-terminated */
    char password[9];             /* installation mode, default "SICK_LMS";
                                     not exactly 8 characters: the default */
    lms_unit_t unit;              /* EEPROM units at power-up (unknown: cm) */
    uint8_t meas_mode;            /* EEPROM measuring mode (unknown: 00) */
    uint8_t config_size;          /* 32 or 34 (F4 block size; others: 34) */
    uint16_t fixed_angle_deg;     /* nonzero: the only variant 3B accepts, and the power-on one */
    uint16_t fixed_resolution_cdeg;
    uint32_t speed_permille;      /* 1000 = real time; 2000 = twice as fast; 0: 1000 */
    lms_sim_faults_t faults;
    lms_sim_scan_fn scan_source;  /* NULL: streams nothing */
    void *scan_ctx;
} lms_sim_config_t;

/* Factory defaults: address 0, 9600 baud, 100 ms power-on delay, 10 ms
 * replies, 1 s config writes, "LMS200;30106x;V02.10 ", cm, measuring mode
 * 00, 34-byte block, any variant, real time, no faults, no source. */
void lms_sim_defaults(lms_sim_config_t *config);

typedef struct {
    uint32_t host_telegrams;   /* CRC-valid telegrams from the host */
    uint32_t host_bad;         /* host telegrams with a bad CRC (NAK sent) */
    uint32_t garbled_bytes;    /* host bytes received at the wrong rate */
    uint32_t naks_injected;
    uint32_t not_acks;         /* 92 replies */
    uint32_t scans_sent;       /* B0 telegrams queued while streaming */
    uint32_t scans_skipped;    /* scan periods skipped: line busy or queue full */
    uint32_t bytes_out;        /* bytes handed out by lms_sim_transmit */
    uint32_t bytes_dropped;
    uint32_t bytes_flipped;
    uint32_t bytes_inserted;
    uint32_t power_cycles;     /* resets and injected power cycles */
    uint32_t baud_changes;
    uint32_t config_writes;
    uint32_t host_framing;     /* host candidates with an impossible length, or
                                  abandoned after the inter-byte limit */
    uint32_t host_ignored;     /* host bytes while powering up or silent */
    uint32_t other_address;    /* good telegrams for another scanner address */
    uint32_t cmds_dropped;     /* good telegrams ignored: command queue full */
    uint32_t replies_dropped;  /* replies (ACK/NAK too) with no room in the queue */
} lms_sim_stats_t;

/* Private helper types of lms_sim_t. */
typedef struct {
    bool armed;
    uint32_t seq; /* fires when this many bytes in all have left the wire */
} lms_sim_mark_t;

typedef struct {
    uint64_t recv_us;
    uint16_t data_len; /* as received; only the first LMS_SIM_CMD_DATA_MAX kept */
    uint8_t code;
    uint8_t data[LMS_SIM_CMD_DATA_MAX];
} lms_sim_cmd_t;

typedef struct {
    /* Private: use the functions below. Fields may change. Grouped by
     * size to avoid padding. */
    lms_sim_config_t config;
    lms_sim_stats_t stats;
    lms_framer_t rx;                 /* host -> scanner */
    lms_sim_cmd_t cmds[LMS_SIM_CMD_QUEUE]; /* commands waiting for their reply */
    /* Times (us) and exact fractions of them. */
    uint64_t last_us;                /* latest time seen */
    uint64_t clock_us;               /* time of the event being handled */
    uint64_t wire_us;                /* end of the last byte on the wire: */
    uint64_t wire_rem;               /* wire_us + wire_rem / (bps * speed) */
    uint64_t garble_acc;
    uint64_t last_rx_us;             /* last host byte */
    uint64_t busy_until_us;          /* when the last reply was queued */
    uint64_t power_on_at_us;         /* 90 due while powering_up */
    uint64_t scan_due_us;            /* scan_due_us + scan_rem / (75 * speed) */
    uint64_t scan_rem;
    uint64_t silent_until_us;
    /* Counters and marks on the count of sent bytes. */
    uint32_t enq_seq;                /* bytes queued, in all (wraps) */
    uint32_t done_seq;               /* bytes that left the wire, in all */
    uint32_t garble_owed;            /* garbage bytes due to the host */
    uint32_t scan_k;                 /* number of the next scan */
    uint32_t streamed;               /* scans streamed since lms_sim_init */
    uint32_t prng;
    lms_baud_t baud;                 /* the scanner's line rate */
    lms_baud_t switch_baud;
    lms_sim_mark_t switch_mark;      /* baud switch after the A0 */
    lms_sim_mark_t reboot_mark;      /* reboot after the 91 */
    lms_sim_mark_t silence_mark;
    lms_sim_mark_t power_mark;
    lms_sim_mark_t hangup_mark;
    /* The output ring: out_sent bytes (from out_head) have left the wire
     * and wait for lms_sim_transmit, out_count in all. */
    uint16_t out_head;
    uint16_t out_count;
    uint16_t out_sent;
    uint16_t angle_deg;
    uint16_t resolution_cdeg;
    uint16_t next_len;
    uint8_t garble_count;
    uint8_t garble_last;
    uint8_t held;                    /* an inserted byte waiting for room */
    uint8_t cmd_head;
    uint8_t cmd_count;
    uint8_t mode;                    /* lms_mode_t code */
    bool has_held;
    bool powering_up;
    bool installation;
    bool have_next;                  /* next_scan holds scan scan_k */
    bool source_done;
    bool silence_done, power_cycle_done, hangup_done, hangup_flag;
    bool silent;
    lms_config_t eeprom;             /* the configuration block */
    uint8_t next_scan[LMS_TELEGRAM_MAX];
    uint8_t scratch[LMS_TELEGRAM_MAX]; /* replies are built here */
    uint8_t out[LMS_SIM_OUT_SIZE];
    uint8_t out_baud[LMS_SIM_OUT_SIZE]; /* rate each sent byte left at */
} lms_sim_t;

/* Powers the simulated scanner up at now_us (the 90 telegram follows after
 * the power-on delay). Copies *config (NULL: the defaults) and puts values
 * outside their documented range back to the defaults noted above. */
void lms_sim_init(lms_sim_t *sim, const lms_sim_config_t *config, uint64_t now_us);

/* Bytes the host wrote, arriving at now_us while the host side of the line
 * runs at host_baud. */
void lms_sim_receive(lms_sim_t *sim, const uint8_t *bytes, size_t len, lms_baud_t host_baud,
                     uint64_t now_us);

/* Advances the clock to now_us (runs delayed replies, the stream, faults)
 * and copies into out (up to cap) the bytes that have arrived at the host
 * by now, garbled when host_baud differs from the scanner's rate. Returns
 * the number of bytes written to out; bytes beyond cap wait for the next
 * call (and keep their room in the queue). out NULL: nothing is copied. */
size_t lms_sim_transmit(lms_sim_t *sim, lms_baud_t host_baud, uint64_t now_us, uint8_t *out,
                        size_t cap);

/* The earliest time after now_us at which lms_sim_transmit would have
 * something new to do (a byte on the wire, a delayed reply, a scan, a
 * fault, the power-on telegram); now_us when something is due already
 * (bytes not handed out yet, or work left by LMS_SIM_MAX_STEPS);
 * UINT64_MAX when nothing is scheduled. Lets a wrapper sleep exactly as
 * long as it may. */
uint64_t lms_sim_next_event_us(const lms_sim_t *sim, uint64_t now_us);

/* Replaces the faults from now on, for a schedule of faults over a long
 * run (the soak test: host_tests/unit/test_soak.c); lms_sim_init's are
 * one-shot. The byte and NAK probabilities apply from the next byte or
 * telegram. The one-shot events are armed afresh and counted from now:
 * each fires after AFTER more streamed scans (0: never), once. An event
 * already armed on a byte still on the wire fires as before. seed is
 * ignored: the PRNG runs on. */
void lms_sim_set_faults(lms_sim_t *sim, const lms_sim_faults_t *faults);

/* The scanner's current line rate. */
lms_baud_t lms_sim_baud(const lms_sim_t *sim);

/* True once when the hang-up fault fired (the flag is cleared). */
bool lms_sim_take_hangup(lms_sim_t *sim);

const lms_sim_stats_t *lms_sim_stats(const lms_sim_t *sim);

/* Parses a fault specification: comma-separated KEY=VALUE items, keys
 * drop, flip, insert (ppm), nak (percent, 0..100), silence (AFTER:MS, e.g.
 * "silence=100:500"), power (AFTER scans), hangup (AFTER scans), seed.
 * Values are plain decimal (digits only, no sign or spaces), up to
 * UINT32_MAX; ppm at most 1000000, MS at most 4294967; an AFTER of 0
 * means never; a repeated key takes the last value. The empty string means
 * no faults. Returns false for anything else (NULL, unknown key, missing
 * or non-decimal value, out of range, empty item such as a trailing comma,
 * more than 256 characters), leaving *out zeroed (when out is not NULL). */
bool lms_sim_parse_faults(const char *spec, lms_sim_faults_t *out);

#endif /* LMS_SIM_H */
