/* ego_frame.h - the binary ego-motion frame: what a microcontroller sends
 * to the vehicle computer per scan instead of the CSV line (ego_loop.h,
 * config.frames), and a resynchronising decoder for the receiving side.
 *
 * One frame per scan after the first, 66 bytes (version 2), multi-byte
 * fields little endian, the numbers exactly as the estimator produced
 * them (no rounding, no float):
 *
 *   offset size field       type   meaning
 *    0     1    start       u8     0xE5
 *    1     1    version     u8     0x02
 *    2     1    length      u8     61: bytes from offset 3 up to the CRC
 *    3     4    scan        u32    scan index (0 = the first scan)
 *    7     4    time_us     u32    the scan's time, us (ego_loop.h: scan * period, or its own)
 *   11     4    dx          i32    Q16.16 m, this scan in the frame of the last
 *   15     4    dy          i32    Q16.16 m
 *   19     4    dtheta      u32    binary angle, 2^32 = one turn
 *   23     4    vx          i32    Q16.16 m/s
 *   27     4    vy          i32    Q16.16 m/s
 *   31     4    omega       i32    Q16.16 rad/s
 *   35     2    flags       u16    EGO_FLAG_* (ego.h)
 *   37     1    iterations  u8     ITCP iterations
 *   38     2    matches     u16    matched point pairs
 *   40     4    cov_xx      i32    Q2.30 m^2, the covariance of (dx, dy, dtheta)
 *   44     4    cov_xy      i32    Q2.30 m^2      (ego_cov.h; a variance of
 *   48     4    cov_xt      i32    Q2.30 m rad     0x7FFFFFFF: not measured)
 *   52     4    cov_yy      i32    Q2.30 m^2
 *   56     4    cov_yt      i32    Q2.30 m rad
 *   60     4    cov_tt      i32    Q2.30 rad^2
 *   64     2    crc         u16    CRC-16/CCITT-FALSE of bytes 1..63, low byte first
 *
 * Version 1 (42 bytes, length 37) is the same up to matches, with the CRC
 * at offset 40 over bytes 1..39 and no covariance: the decoder reads it
 * too (the covariance then says not measured), so older captures still
 * decode.
 *
 * CRC-16/CCITT-FALSE: polynomial 0x1021, initial value 0xFFFF, no
 * reflection, no final XOR; check value ("123456789") 0x29B1. Not the LMS
 * telegram checksum (lms_crc.h): that one is not a textbook CRC, this one
 * has Hamming distance 4 at these sizes, so every 1-, 2- and 3-bit error in
 * a frame is detected.
 *
 * Decoder: bytes in any chunk sizes. It hunts for 0xE5, rejects a version
 * it does not know or a length byte that is not its version's as soon as
 * it arrives, checks the CRC when the version's bytes are in, and reports
 * the frame. A rejected candidate (version, length or CRC) loses only its
 * start byte: the bytes after it are searched again, so a good frame
 * inside a bad candidate is still found. Counters say what was skipped.
 * Static memory (one frame of buffer), no heap, no float; not reentrant
 * per decoder.
 */
#ifndef EGO_FRAME_H
#define EGO_FRAME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ego.h"

#define EGO_FRAME_START 0xE5u
#define EGO_FRAME_VERSION 0x02u                  /* what ego_frame_encode writes */
#define EGO_FRAME_PAYLOAD 61u                    /* its length byte */
#define EGO_FRAME_SIZE (3u + EGO_FRAME_PAYLOAD + 2u) /* 66 */
#define EGO_FRAME_V1_VERSION 0x01u               /* decoded too: no covariance */
#define EGO_FRAME_V1_PAYLOAD 37u
#define EGO_FRAME_V1_SIZE (3u + EGO_FRAME_V1_PAYLOAD + 2u) /* 42 */

/* CRC-16/CCITT-FALSE of len bytes (see above); 0xFFFF for len 0. */
uint16_t ego_frame_crc16(const uint8_t *data, size_t len);

/* Writes the frame of one scan into out: scan index, its time in us and
 * the fields of o listed above. Returns EGO_FRAME_SIZE, or 0 (nothing
 * written) when out or o is NULL or cap < EGO_FRAME_SIZE. */
size_t ego_frame_encode(uint8_t *out, size_t cap, uint32_t scan, uint32_t time_us,
                        const ego_output_t *o);

/* A decoded frame. out carries pose (x, y, theta), vx, vy, omega, flags,
 * iterations, matches and cov (unknown from a version 1 frame), which is
 * what ego_format_line (ego_loop.h) prints; its other fields are 0. */
typedef struct {
    uint32_t scan;
    uint32_t time_us;
    ego_output_t out;
} ego_frame_t;

/* Counters; they wrap modulo 2^32. At every return of feed / flush:
 * bytes_in == bytes_framed + bytes_skipped + pending. */
typedef struct {
    uint32_t bytes_in;      /* bytes given to ego_frame_feed */
    uint32_t frames;        /* CRC-valid frames reported (either version) */
    uint32_t bytes_framed;  /* their bytes */
    uint32_t crc_errors;    /* complete candidates with a wrong CRC */
    uint32_t length_errors; /* candidates with a wrong version or length byte */
    uint32_t truncated;     /* flushes that abandoned an incomplete candidate */
    uint32_t bytes_skipped; /* bytes that ended up in no frame */
} ego_frame_stats_t;

typedef struct {
    /* Private: use the functions below. */
    uint8_t buf[EGO_FRAME_SIZE];
    uint8_t fill; /* buffered bytes; buf[0] is a start byte when fill > 0 */
    ego_frame_stats_t stats;
} ego_frame_decoder_t;

typedef enum {
    EGO_FRAME_NEED_MORE = 0, /* every byte given was used, no frame completed */
    EGO_FRAME_READY = 1      /* a frame completed: *frame holds it */
} ego_frame_event_t;

/* Empty buffer, zero counters. */
void ego_frame_decoder_init(ego_frame_decoder_t *d);

/* Consumes bytes until a frame completes (EGO_FRAME_READY: *frame is
 * filled, *consumed says how many bytes were used; call again with the
 * rest) or all len bytes are used (EGO_FRAME_NEED_MORE). bytes NULL is
 * taken as len 0. Cost per byte: at most one CRC pass and one move of
 * EGO_FRAME_SIZE bytes. */
ego_frame_event_t ego_frame_feed(ego_frame_decoder_t *d, const uint8_t *bytes, size_t len,
                                 size_t *consumed, ego_frame_t *frame);

/* The input ended: an incomplete candidate is abandoned (counted in
 * truncated, its bytes in bytes_skipped); nothing stays buffered. */
void ego_frame_flush(ego_frame_decoder_t *d);

/* Bytes held for an incomplete candidate. */
size_t ego_frame_pending(const ego_frame_decoder_t *d);

const ego_frame_stats_t *ego_frame_stats(const ego_frame_decoder_t *d);

#endif /* EGO_FRAME_H */
