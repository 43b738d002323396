/* ego_loop.h - the firmware main loop (portable core): bytes in from a
 * small HAL, ego-motion lines out.
 *
 * Every step reads what the HAL has waiting, feeds the telegram framer,
 * decodes each B0 scan, runs the estimator and writes one CSV line per
 * scan after the first:
 *
 *   scan,time_s,dx_m,dy_m,dtheta_rad,vx_mps,vy_mps,omega_radps,flags,iterations,matches,
 *   cov_xx,cov_xy,cov_xt,cov_yy,cov_yt,cov_tt[,latency_ms]
 *
 * (the header once, first; ego_format_line makes the line). Or, with
 * config.frames, one binary frame per scan after the first instead
 * (ego_frame.h; no header). scan counts decoded scans from 0; the pose is
 * the scan's position in the frame of the previous scan; flags are
 * EGO_FLAG_* (ego.h) in decimal. Numbers are printed without stdio (six
 * decimals, rounded to nearest).
 *
 * Scan times (time_s, and the dt of the velocities). Without use_clock:
 * scan * period, from 0 (a stream without arrival times). With use_clock:
 * the scan's time as the estimator defines it (ego_range.h: the mean of
 * its beams' times) on the HAL's clock (hal->now_us; its zero is the
 * clock's), derived from the arrival of the telegram's bytes (see "Scan
 * times from arrival stamps" below). config.latency adds latency_ms: the
 * clock when the line is handed to hal->write minus the scan's time.
 *
 * Static memory: ego_loop_t holds the framer, one decoded scan, the
 * estimator state, the scan-time tracker and a line buffer; the caller
 * owns it (a static in main). No OS headers, no heap.
 */
#ifndef EGO_LOOP_H
#define EGO_LOOP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ego.h"
#include "ego_lms.h"
#include "ego_moving.h"
#include "lms_decode.h"
#include "lms_framer.h"

/* The platform: three functions and their context. */
typedef struct {
    /* Copies up to cap waiting bytes into buf and returns how many (0 when
     * none are waiting now); a negative value means the input has ended. */
    int32_t (*read)(void *ctx, uint8_t *buf, size_t cap);
    /* Writes len bytes (may block). */
    void (*write)(void *ctx, const uint8_t *buf, size_t len);
    /* A free-running microsecond clock (wraps after 71 minutes: fine). */
    uint32_t (*now_us)(void *ctx);
    void *ctx;
} ego_hal_t;

#define EGO_LOOP_READ_CHUNK 256u
#define EGO_LOOP_LINE_MAX 192u

/* The moving objects (ego_moving.h) cost 3.0 KB of RAM in ego_loop_t and
 * 10 KB of flash (Cortex-M3 -Os): a build for a 64 KiB part leaves them
 * out (EGO_LOOP_OBJECTS 0, CMake option LMSEGO_LOOP_OBJECTS; the config's
 * objects fields are not there either). With them and config.objects,
 * each scan's CSV line (none for the first scan) is followed by its
 * confirmed objects, one line each:
 *
 *   o,scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points
 *
 * in the scan's vehicle frame, two decimals (the record's centimetres);
 * vx and vy "nan" while unknown. A CSV reader that wants the motion only
 * skips lines that start with "o,". */
#ifndef EGO_LOOP_OBJECTS
#define EGO_LOOP_OBJECTS 1
#endif
#define EGO_LOOP_OBJECTS_COLUMNS "scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points"

/* Optional: called after every scan after the first with its index, its
 * time (microseconds from the first scan) and the estimator's output, for
 * host tools that keep more than the CSV line (lmsego replay --pairs,
 * --tum). */
typedef void (*ego_loop_observer_fn)(void *ctx, uint32_t scan, uint32_t time_us,
                                     const ego_output_t *out);

#if EGO_LOOP_OBJECTS
/* Optional: called with the moving objects of every scan after the first
 * (n of them, maybe 0), after its line or frame, for host tools that
 * write them elsewhere (lmsego replay --objects). */
typedef void (*ego_loop_objects_fn)(void *ctx, uint32_t scan, const ego_moving_object_t *objects,
                                    uint8_t n);
#endif

/* Optional: a motion prior for scan k (its pose in the frame of scan
 * k - 1), e.g. from wheel odometry; return false when there is none. */
typedef bool (*ego_loop_prior_fn)(void *ctx, uint32_t scan, ego_pose_t *prior);

typedef struct {
    ego_params_t ego;
    ego_lms_params_t lms;          /* mounting pose, measuring mode (ego_lms.h) */
    ego_loop_prior_fn prior;       /* NULL: none */
    void *prior_ctx;
    ego_loop_observer_fn observer; /* NULL: none */
    void *observer_ctx;
    /* Time of scan k: k * period_us when nonzero; 0 with use_clock false:
     * the period of the LMS mode of the first scan (1/75 s for 1-degree
     * scans, 1/37.5 s at 0.5 deg, 1/18.75 s at 0.25 deg). */
    uint32_t period_us;
    bool use_clock;            /* true: scan times from the bytes' arrival (hal->now_us
                                  after each read stamps what it read), see above */
    bool frames;               /* true: an ego_frame.h frame per scan, not the CSV line */
    bool latency;              /* true: the CSV gains latency_ms (use_clock only) */
    uint8_t line_baud;         /* lms_baud_t the bytes came at (use_clock): wire times */
#if EGO_LOOP_OBJECTS
    bool objects;              /* true: each CSV line is followed by its scan's moving
                                  objects, one "o," line each (above; not with frames) */
    ego_loop_objects_fn objects_observer; /* NULL: none */
    void *objects_ctx;
#endif
} ego_loop_config_t;

void ego_loop_defaults(ego_loop_config_t *config);

typedef struct {
    uint32_t bytes;          /* read from the HAL */
    uint32_t scans;          /* B0 telegrams decoded */
    uint32_t decode_errors;  /* B0 telegrams the decoder, the adapter or the estimator
                                refused */
    uint32_t lines;          /* motion lines (or frames) written */
    uint32_t predicted;      /* of which carried a prediction, not a match */
    uint32_t restarts;       /* EGO_FLAG_FIRST after the first scan */
} ego_loop_stats_t;

/* --- Scan times from arrival stamps ----------------------------------------
 *
 * A scan's time is the mean of its beams' times (ego_range_mean_ns). On
 * the receiver's clock it is
 *
 *   arrival of the telegram's last byte - its wire time (bytes x 10 bit
 *   times, 8N1; the scanner sends a telegram back to back)
 *   - EGO_TIMING_SEND_DELAY_US - the lag from the scan's time to its last
 *   beam (ego_range_lag_ns)
 *
 * Stamps are only ever late (a receive ring stamps a block of bytes with
 * the time of its latest write, a host with the time of its read), so each
 * stamp bounds the start of the telegram's sending from above: bytes whose
 * stamp is s, and which are the telegram's first n bytes, say it started
 * at s - wire(n) or before. The least of these bounds over the telegram's
 * pieces is the estimate, counted from the end of the last scan's
 * telegram or of the reply that started the stream (ego_timing_boundary);
 * when other bytes came in between, whose pause the bound cannot see, the
 * last piece's alone.
 *
 * Those estimates jitter with the stamps; the scanner's mirror does not.
 * So the track counts scan intervals (lms_scan_interval_us, plus one per
 * telegram the framer saw damaged in between, at most 8): scan k is one
 * interval after scan k - 1, and the velocities' dt is that interval. The
 * estimates only keep the count from drifting (the two clocks differ by
 * tens of ppm, and the integer interval 13 333 us by 25 ppm): the track
 * stays while the estimates lie within a band of +-EGO_TIMING_BAND_BYTES
 * byte times around it (the stamp granularity; 640 us at 500 kbaud); an
 * estimate earlier than the band proves the track late and moves it back
 * towards the band's middle, and a window of EGO_TIMING_WINDOW scans whose
 * least estimate lies beyond the band moves it forward; each move is at
 * most interval >> EGO_TIMING_SLEW_SHIFT (0.4 %: 52 us at 75 Hz) a scan,
 * so dt never jumps. It follows up to 244 ppm of drift. The first scan
 * after a (re)start seeds it with its estimate.
 *
 * The tracker belongs to whoever produces the scans: ego_loop_step with
 * use_clock, or the live core (ego_live.h), whose receive side calls these
 * functions on loop->timing while ego_loop_telegram, which never touches
 * it, may run elsewhere. Times are on a free-running 32-bit microsecond
 * clock (they wrap after 71.6 minutes; differences stay right). */

/* The scanner's delay from its last beam to the first bit sent: not in
 * our sources. The scanner cannot send a scan before its last beam, so 0
 * is the bound; a measured figure belongs here (docs/firmware.md). */
#define EGO_TIMING_SEND_DELAY_US 0u
/* The band, in byte times: the receive ring's stamp block (uart_ring.h). */
#define EGO_TIMING_BAND_BYTES 32u
#define EGO_TIMING_WINDOW 16u
#define EGO_TIMING_SLEW_SHIFT 8u
/* More damaged telegrams than this between two scans would have been a
 * silence restart (the session's default silence_scans). */
#define EGO_TIMING_MAX_LOST 8u

typedef struct {
    /* Private: the functions below. */
    uint32_t time_us;   /* track: the last scan's start of sending, minus the delay */
    uint32_t bound_us;  /* the telegram in progress: the least bound on its start */
    int32_t floor_us;   /* the window's least estimate, from the track */
    uint16_t since;     /* bytes since the last scan's telegram ended (saturating) */
    uint16_t damaged;   /* the framer's damage count at the last scan (low bits) */
    uint8_t window;     /* scans in the window */
    bool started;
    bool has_bound;
} ego_timing_t;

/* Forgets the stream: the next scan seeds the track (init, restart). */
void ego_timing_reset(ego_timing_t *t);

/* A telegram that was not a scan ended with the last bytes fed: the reply
 * that starts the stream (the live core at LMS_SESSION_EV_STREAMING,
 * ego_loop_step at every A0), so the first scan's bound covers its bytes. */
void ego_timing_boundary(ego_timing_t *t);

/* n bytes fed to the framer, up to and including the latest fed, all
 * stamped stamp_us (their arrival or later), at line rate baud. */
void ego_timing_bytes(ego_timing_t *t, size_t n, uint32_t stamp_us, lms_baud_t baud);

/* The framer completed the B0 telegram [0, len) with the last bytes fed
 * (stamped stamp_us); damaged is its running count of damaged telegrams.
 * Returns the scan's track time: its start of sending minus the send
 * delay, on the stamps' clock; the scan's own time is that minus its lag
 * (ego_range_lag_ns), which the loop subtracts once it has the scan. */
uint32_t ego_timing_scan(ego_timing_t *t, const uint8_t *telegram, size_t len,
                         uint32_t stamp_us, lms_baud_t baud, uint32_t damaged);

/* The tracker's step alone (for tests): a scan whose start of sending is
 * estimated at estimate_us, steps intervals of interval_us after the last,
 * the band band_us; returns the track's time. */
uint32_t ego_timing_track(ego_timing_t *t, uint32_t estimate_us, uint32_t steps,
                          uint32_t interval_us, uint32_t band_us);


typedef struct {
    /* Private. */
    ego_loop_config_t config;
    lms_framer_t framer;
    lms_scan_t scan;
    ego_state_t ego;
    ego_timing_t timing;
    uint32_t period_us;
    bool header_written;
    bool ended;
    ego_loop_stats_t stats;
    uint8_t rx[EGO_LOOP_READ_CHUNK];
    char line[EGO_LOOP_LINE_MAX];
#if EGO_LOOP_OBJECTS
    ego_moving_t moving;
#endif
} ego_loop_t;

void ego_loop_init(ego_loop_t *loop, const ego_loop_config_t *config);

typedef enum {
    EGO_LOOP_IDLE = 0, /* nothing was waiting */
    EGO_LOOP_BUSY = 1, /* bytes were processed; call again */
    EGO_LOOP_END = 2   /* the input ended and everything is processed */
} ego_loop_status_t;

/* One round: at most EGO_LOOP_READ_CHUNK bytes. */
ego_loop_status_t ego_loop_step(ego_loop_t *loop, const ego_hal_t *hal);

/* Live input, when something else reads the line (the session of `lmsego
 * run`, a firmware with a session): one CRC-checked telegram whose track
 * time (ego_timing_scan) is track_us (with use_clock). B0 telegrams go
 * through the decoder and the estimator like those of ego_loop_step;
 * others are ignored. Uses hal->write (and hal->now_us with
 * config.latency) only. */
void ego_loop_telegram(ego_loop_t *loop, const ego_hal_t *hal, const uint8_t *telegram, size_t len,
                       uint32_t track_us);

/* The line was lost and brought up again: the next scan starts over (no
 * motion is matched across the gap; its line carries EGO_FLAG_FIRST). */
void ego_loop_gap(ego_loop_t *loop);

/* The scanner measures in this mode from now on (lms_meas_mode_t): the
 * live core passes the mode the session found or set, so the values are
 * decoded with the scanner's real masks. */
void ego_loop_set_meas_mode(ego_loop_t *loop, uint8_t meas_mode);

const ego_loop_stats_t *ego_loop_stats(const ego_loop_t *loop);

/* Formats value / 10^decimals ("-1.250000"), rounded already by the
 * caller; returns the length written (at most 24 + NUL). */
size_t ego_format_fixed(char *out, int64_t value, unsigned decimals);

/* A Q2.30 value in scientific notation with four significant digits, as
 * printf's "%.3e" prints q / 2^30 ("-1.234e-08"; "0" for 0; "inf" and
 * "-inf" for the saturated ends, EGO_COV_SATURATED: not measured). out
 * holds at least 16 bytes; returns the length. */
size_t ego_format_sci(char *out, int32_t q30);

/* The CSV header line ego_loop writes before the first line; with
 * config.latency the last column is latency_ms. */
#define EGO_LOOP_CSV_COLUMNS \
    "scan,time_s,dx_m,dy_m,dtheta_rad,vx_mps,vy_mps,omega_radps,flags,iterations,matches," \
    "cov_xx,cov_xy,cov_xt,cov_yy,cov_yt,cov_tt"
#define EGO_LOOP_CSV_HEADER EGO_LOOP_CSV_COLUMNS "\n"
#define EGO_LOOP_CSV_HEADER_LATENCY EGO_LOOP_CSV_COLUMNS ",latency_ms\n"

/* The CSV line of one scan, newline included, NUL-terminated: scan index,
 * time_us as seconds, pose x / y (Q16.16 m) and theta (binary angle, as
 * radians in [-pi, pi)), vx / vy / omega (Q16.16), flags, iterations and
 * matches of o, each rounded to six decimals where it has them. Reads no
 * other field of o. Returns the length written; a line never needs more
 * than EGO_LOOP_LINE_MAX bytes, a smaller cap truncates it (cap 0: nothing
 * written). Shared by ego_loop and the frame decoder's users, so both
 * print the same bytes. */
size_t ego_format_line(char *out, size_t cap, uint32_t scan, uint32_t time_us,
                       const ego_output_t *o);

#endif /* EGO_LOOP_H */
