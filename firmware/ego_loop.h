/* ego_loop.h - the firmware main loop (portable core): bytes in from a
 * small HAL, ego-motion lines out.
 *
 * Every step reads what the HAL has waiting, feeds the telegram framer,
 * decodes each B0 scan, runs the estimator and writes one CSV line per
 * scan after the first:
 *
 *   scan,time_s,dx_m,dy_m,dtheta_rad,vx_mps,vy_mps,omega_radps,flags,iterations,matches,
 *   cov_xx,cov_xy,cov_xt,cov_yy,cov_yt,cov_tt
 *
 * (the header once, first; ego_format_line makes the line). Or, with
 * config.frames, one binary frame per scan after the first instead
 * (ego_frame.h; no header). scan counts decoded scans from 0; time_s is
 * scan * period (replay of a recording without timestamps) or the HAL
 * clock at the telegram's arrival, relative to the first scan; the pose is
 * the scan's position in the frame of the previous scan; flags are
 * EGO_FLAG_* (ego.h) in decimal. Numbers are printed without stdio (six
 * decimals, rounded to nearest).
 *
 * Static memory: ego_loop_t holds the framer, one decoded scan, the
 * estimator state and a line buffer; the caller owns it (a static in
 * main). No OS headers, no heap.
 */
#ifndef EGO_LOOP_H
#define EGO_LOOP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ego.h"
#include "ego_lms.h"
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

/* Optional: called after every scan after the first with its index, its
 * time (microseconds from the first scan) and the estimator's output, for
 * host tools that keep more than the CSV line (lmsego replay --pairs,
 * --tum). */
typedef void (*ego_loop_observer_fn)(void *ctx, uint32_t scan, uint32_t time_us,
                                     const ego_output_t *out);

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
    bool use_clock;            /* true: stamp scans with hal->now_us instead */
    bool frames;               /* true: an ego_frame.h frame per scan, not the CSV line */
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

typedef struct {
    /* Private. */
    ego_loop_config_t config;
    lms_framer_t framer;
    lms_scan_t scan;
    ego_state_t ego;
    uint32_t period_us;
    uint32_t first_time_us;
    bool header_written;
    bool ended;
    ego_loop_stats_t stats;
    uint8_t rx[EGO_LOOP_READ_CHUNK];
    char line[EGO_LOOP_LINE_MAX];
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
 * run`, a firmware with a session): one CRC-checked telegram taken at
 * time_us (with use_clock; the caller's clock, e.g. counted scan
 * intervals). B0 telegrams go through the decoder and the estimator like
 * those of ego_loop_step; others are ignored. Uses hal->write only. */
void ego_loop_telegram(ego_loop_t *loop, const ego_hal_t *hal, const uint8_t *telegram, size_t len,
                       uint32_t arrival_us);

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

/* The CSV header line ego_loop writes before the first line. */
#define EGO_LOOP_CSV_HEADER \
    "scan,time_s,dx_m,dy_m,dtheta_rad,vx_mps,vy_mps,omega_radps,flags,iterations,matches," \
    "cov_xx,cov_xy,cov_xt,cov_yy,cov_yt,cov_tt\n"

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
