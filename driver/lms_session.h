/* lms_session.h - brings a SICK LMS 2xx up over a serial line and keeps it
 * streaming: the session state machine (portable, no OS calls).
 *
 * Driven by three things the caller supplies: the bytes the scanner sent
 * (lms_session_feed), a microsecond clock passed into every call, and a
 * byte sink plus a "set my UART rate" hook (lms_session_io_t). It never
 * blocks and never sleeps: lms_session_wait_us says how long the caller may
 * wait for bytes before calling lms_session_poll. The same code runs in a
 * microcontroller's main loop and in `lmsego run` on a host.
 *
 * Bring-up (docs/session.md has the diagram, every timeout and retry):
 *   LISTEN      optional: wait power_wait_us for the 90 power-on telegram
 *   PROBE       baud discovery: at each candidate rate (the last one that
 *               worked, then 9600, 38400, 19200, 500000) drain stray
 *               bytes, send 20 25 (also stops a running stream) and accept
 *               the rate on an ACK and a CRC-valid A0
 *   CONFIRM     31 -> B1: its baud word must name the host's rate
 *   SWITCH      20 40/41/42/48 at the old rate; after A0 00 the host UART
 *               follows, waits settle_us, and checks with 31 (VERIFY)
 *   IDENTIFY    3A -> the type text
 *   VARIANT     3B, only when B1 shows another variant than requested
 *   INSTALL .. LEAVE   units / measuring mode, only when they differ:
 *               20 00 password, 74, 77 (read-modify-write), 74 to verify,
 *               20 25
 *   START       20 24 (all values) or 20 2A (partial scans)
 *   STREAMING   B0 telegrams are reported as LMS_SESSION_EV_SCAN
 * A step whose reply does not come is retried (NAK: after nak_wait_us;
 * no ACK: after ack_timeout_us; no reply: after reply_timeout_us) up to
 * retries times, then the session goes back to PROBE (the rates may
 * disagree now). A discovery round that finds nothing waits (BACKOFF,
 * doubling from backoff_min_us to backoff_max_us, listening at 9600 for
 * a power-on telegram) and starts again, forever: a scanner that is still
 * powering up or unplugged is found when it comes.
 *
 * Recovery while streaming: no B0 for silence_scans scan periods (the
 * period of the variant, or the telegram's wire time at slow rates), a 90
 * power-on telegram, or lms_session_link_lost (the host saw a hang-up)
 * report LMS_SESSION_EV_RESTART and run the bring-up again; the caller
 * must not match scans across it (ego_reset).
 *
 * The permanent-baud command 66 is never sent. Settings the scanner
 * refuses (a variant it does not have, a wrong password, a configuration
 * write refused) end in LMS_SESSION_FAILED with lms_session_error().
 *
 * Time: now_us is a free-running 32-bit microsecond clock; differences are
 * taken modulo 2^32, so it may wrap (every 71.6 minutes) but no single
 * timeout may exceed 2^31 us. Not reentrant; one session per line.
 */
#ifndef LMS_SESSION_H
#define LMS_SESSION_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lms_decode.h"
#include "lms_encode.h"
#include "lms_framer.h"
#include "lms_proto.h"

/* "Leave as the scanner has it" for the unit and measuring-mode fields. */
#define LMS_SESSION_KEEP 0xFFu

typedef struct {
    /* Sends bytes to the scanner (the platform paces them at 500 kbaud). */
    void (*write)(void *ctx, const uint8_t *bytes, size_t len);
    /* Reprograms the host UART to a rate and discards what it buffered. */
    void (*set_baud)(void *ctx, lms_baud_t baud);
    void *ctx;
} lms_session_io_t;

typedef struct {
    uint8_t address;            /* scanner address 0x00 (any) .. 0x7F */
    lms_baud_t baud;            /* rate to stream at */
    uint16_t angle_deg;         /* 180 or 100; 0: keep the scanner's variant */
    uint16_t resolution_cdeg;   /* 100, 50 or 25 */
    uint8_t unit;               /* lms_unit_t, or LMS_SESSION_KEEP */
    uint8_t meas_mode;          /* lms_meas_mode_t code, or LMS_SESSION_KEEP */
    bool partial;               /* stream partial scans (mode 2A) */
    bool restore_9600;          /* lms_session_stop also switches back to 9600 */
    char password[9];           /* installation mode; "SICK_LMS" by default */
    uint32_t power_wait_us;     /* LISTEN before the first probe; 0 = skip */
    uint32_t ack_timeout_us;    /* ACK after a command (spec: 60 ms) */
    uint32_t reply_timeout_us;  /* reply after the ACK (mode changes: 3 s) */
    uint32_t write_timeout_us;  /* F7 after a 77 (EEPROM write) */
    uint32_t nak_wait_us;       /* before resending after a NAK (>= 30 ms) */
    uint32_t drain_us;          /* PROBE: listen this long before sending */
    uint32_t settle_us;         /* after a baud switch, before verifying */
    uint32_t byte_gap_us;       /* flush a half telegram after this silence */
    uint32_t backoff_min_us;    /* BACKOFF: first wait ... */
    uint32_t backoff_max_us;    /* ... doubling up to this */
    uint16_t silence_scans;     /* STREAMING: periods without a B0 -> restart */
    uint8_t retries;            /* sends per step before giving up on it */
    uint8_t probe_sends;        /* sends per candidate rate */
} lms_session_config_t;

/* Defaults: address 0, 500000 baud, keep variant, units and measuring mode,
 * all values, restore 9600, "SICK_LMS", no power wait, ACK 100 ms, reply
 * 3.5 s, write 16 s, NAK wait 40 ms, drain 30 ms, settle 250 ms, byte gap
 * 40 ms, backoff 100 ms .. 5 s, 8 silent periods, 3 retries, 2 probes. */
void lms_session_defaults(lms_session_config_t *config);

/* LMS_ERR_ARG when a field is outside its legal set (address > 0x7F, an
 * illegal variant pair, a unit or mode code the driver does not know, a
 * password that is not 8 characters, a zero timeout, retries 0). */
lms_status_t lms_session_check_config(const lms_session_config_t *config);

typedef enum {
    LMS_SESSION_LISTEN = 0,
    LMS_SESSION_PROBE,
    LMS_SESSION_CONFIRM,
    LMS_SESSION_SWITCH,
    LMS_SESSION_SETTLE,
    LMS_SESSION_VERIFY,
    LMS_SESSION_IDENTIFY,
    LMS_SESSION_VARIANT,
    LMS_SESSION_INSTALL,
    LMS_SESSION_READ_CONFIG,
    LMS_SESSION_WRITE_CONFIG,
    LMS_SESSION_CHECK_CONFIG,
    LMS_SESSION_LEAVE_INSTALL,
    LMS_SESSION_START,
    LMS_SESSION_STREAMING,
    LMS_SESSION_BACKOFF,
    LMS_SESSION_STOP_STREAM,
    LMS_SESSION_STOP_BAUD,
    LMS_SESSION_STOPPED,
    LMS_SESSION_FAILED,
    LMS_SESSION_STATE_COUNT
} lms_session_state_t;

/* Short name of a state ("probe"). */
const char *lms_session_state_name(lms_session_state_t state);

typedef enum {
    LMS_SESSION_EV_NONE = 0,   /* nothing to report: all bytes used / nothing due */
    LMS_SESSION_EV_SCAN,       /* a B0 while streaming: lms_session_telegram() */
    LMS_SESSION_EV_STREAMING,  /* bring-up done; scans follow */
    LMS_SESSION_EV_RESTART,    /* link lost while streaming; bring-up runs again */
    LMS_SESSION_EV_STOPPED,    /* lms_session_stop has finished */
    LMS_SESSION_EV_FAILED      /* the scanner refused a setting: lms_session_error() */
} lms_session_event_t;

typedef enum {
    LMS_SESSION_ERR_NONE = 0,
    LMS_SESSION_ERR_VARIANT,   /* 3B refused (e.g. LMS-Fast models) */
    LMS_SESSION_ERR_PASSWORD,  /* installation mode refused (A0 01) */
    LMS_SESSION_ERR_CONFIG,    /* 77 refused, or 74 does not show the change */
    LMS_SESSION_ERR_MODE       /* A0 02: the scanner reports a fault */
} lms_session_error_t;

const char *lms_session_error_name(lms_session_error_t error);

/* Why the last restart happened. */
typedef enum {
    LMS_SESSION_CAUSE_NONE = 0,
    LMS_SESSION_CAUSE_SILENCE,  /* no B0 for silence_scans periods */
    LMS_SESSION_CAUSE_POWER_ON, /* a 90 telegram */
    LMS_SESSION_CAUSE_LINK      /* lms_session_link_lost */
} lms_session_cause_t;

typedef struct {
    uint32_t commands;        /* host telegrams sent */
    uint32_t retries;         /* of which resends */
    uint32_t ack_timeouts;
    uint32_t reply_timeouts;
    uint32_t naks;            /* 15 received */
    uint32_t not_acks;        /* 92 received */
    uint32_t probes;          /* 20 25 sent during discovery */
    uint32_t discovery_rounds;/* rounds that found nothing */
    uint32_t baud_switches;   /* 20 4x accepted */
    uint32_t config_writes;   /* 77 accepted */
    uint32_t bring_ups;       /* times STREAMING was reached */
    uint32_t restarts;        /* EV_RESTART reported */
    uint32_t restarts_silence;
    uint32_t restarts_power_on;
    uint32_t restarts_link;
    uint32_t power_ons;       /* 90 telegrams seen */
    uint32_t scans;           /* B0 reported as EV_SCAN */
    uint32_t stray_telegrams; /* valid telegrams no state wanted */
    uint32_t flushes;         /* half telegrams dropped after a byte gap */
} lms_session_stats_t;

/* What the scanner said about itself (valid once IDENTIFY has passed). */
typedef struct {
    char type_text[LMS_TYPE_TEXT_SIZE + 1u]; /* BA text, e.g. "LMS200;30106x;V02.10 " */
    lms_baud_t baud;          /* the rate in use */
    uint16_t angle_deg;       /* active variant */
    uint16_t resolution_cdeg;
    uint8_t units;            /* 0 cm, 1 mm */
    uint8_t meas_mode;
    uint8_t reply_address;    /* 0x80 | address of the scanner that answered */
} lms_session_info_t;

typedef struct {
    /* Private: use the functions below. */
    lms_session_config_t config;
    lms_session_io_t io;
    lms_framer_t framer;
    lms_session_state_t state;
    lms_session_error_t error;
    lms_session_cause_t cause;
    lms_session_info_t info;
    lms_baud_t host_baud;      /* the rate the host UART is set to */
    lms_baud_t last_good_baud; /* first candidate of the next discovery */
    uint8_t probe_index;       /* candidate in the discovery order */
    uint8_t sends;             /* sends of the current step */
    uint8_t phase;             /* within a step: drain, wait ACK, wait reply, NAK wait */
    bool report_streaming;     /* EV_STREAMING still to report */
    bool report_restart;
    bool report_stopped;
    bool report_failed;
    uint32_t deadline_us;      /* timeout of the current phase */
    uint32_t last_byte_us;     /* for the byte-gap flush */
    uint32_t last_scan_us;     /* STREAMING: the silence timer */
    uint32_t backoff_us;
    lms_cmd_t cmd;             /* the command of the current step */
    lms_config_t block;        /* configuration block being changed */
    lms_session_stats_t stats;
} lms_session_t;

/* Starts a session at now_us: LISTEN (or PROBE when power_wait_us is 0).
 * The config must pass lms_session_check_config (else LMS_ERR_ARG and the
 * session is left FAILED). io is copied. */
lms_status_t lms_session_init(lms_session_t *s, const lms_session_config_t *config,
                              const lms_session_io_t *io, uint32_t now_us);

/* Bytes from the scanner, received at now_us. Stops at the first event and
 * sets *consumed; call again with the rest until it returns
 * LMS_SESSION_EV_NONE (all bytes used). */
lms_session_event_t lms_session_feed(lms_session_t *s, const uint8_t *bytes, size_t len,
                                     size_t *consumed, uint32_t now_us);

/* Runs the timers. Call when lms_session_wait_us has elapsed, and after
 * every feed; call again until it returns LMS_SESSION_EV_NONE. */
lms_session_event_t lms_session_poll(lms_session_t *s, uint32_t now_us);

/* How long from now_us the caller may wait for bytes before the next
 * lms_session_poll is due (0: now). */
uint32_t lms_session_wait_us(const lms_session_t *s, uint32_t now_us);

/* The B0 telegram of the last LMS_SESSION_EV_SCAN (STX .. CRC) and its
 * size; valid until the next feed or poll. NULL otherwise. */
const uint8_t *lms_session_telegram(const lms_session_t *s, size_t *len);

/* The host saw the line hang up (and has reopened it, or will): the rate is
 * unknown now; runs discovery again (EV_RESTART if it was streaming). */
void lms_session_link_lost(lms_session_t *s, uint32_t now_us);

/* Asks for a clean stop: 20 25 (and 20 42 with restore_9600), each with
 * the usual retries; LMS_SESSION_EV_STOPPED comes when done or given up. A
 * session that never found the scanner stops at once. */
void lms_session_stop(lms_session_t *s, uint32_t now_us);

/* Time between two B0 telegrams while streaming with the settings found:
 * the mirror's scan period (1/75 s per 1-degree pass: 1/75 s at 1 deg and
 * for partial scans, 1/37.5 s at 0.5 deg, 1/18.75 s at 0.25 deg), or at a
 * slow rate the telegram's wire time rounded up to whole periods (the
 * scanner skips the scans the line cannot carry). */
uint32_t lms_session_scan_interval_us(const lms_session_t *s);

lms_session_state_t lms_session_state(const lms_session_t *s);
lms_session_error_t lms_session_error(const lms_session_t *s);
lms_session_cause_t lms_session_cause(const lms_session_t *s);
const lms_session_info_t *lms_session_info(const lms_session_t *s);
const lms_session_stats_t *lms_session_stats(const lms_session_t *s);
const lms_framer_stats_t *lms_session_framer_stats(const lms_session_t *s);

#endif /* LMS_SESSION_H */
