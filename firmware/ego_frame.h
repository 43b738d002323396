/* ego_frame.h - the binary ego-motion frame: what a microcontroller sends
 * to the vehicle computer per scan instead of the CSV line (ego_loop.h,
 * config.frames), and a resynchronising decoder for the receiving side.
 *
 * One frame per scan after the first, 42 bytes, multi-byte fields little
 * endian, the numbers exactly as the estimator produced them (no
 * rounding, no float):
 *
 *   offset size field       type   meaning
 *    0     1    start       u8     0xE5
 *    1     1    version     u8     0x01
 *    2     1    length      u8     37: bytes from offset 3 up to the CRC
 *    3     4    scan        u32    scan index (0 = the first scan)
 *    7     4    time_us     u32    microseconds since the first scan
 *   11     4    dx          i32    Q16.16 m, this scan in the frame of the last
 *   15     4    dy          i32    Q16.16 m
 *   19     4    dtheta      u32    binary angle, 2^32 = one turn
 *   23     4    vx          i32    Q16.16 m/s
 *   27     4    vy          i32    Q16.16 m/s
 *   31     4    omega       i32    Q16.16 rad/s
 *   35     2    flags       u16    EGO_FLAG_* (ego.h)
 *   37     1    iterations  u8     ITCP iterations
 *   38     2    matches     u16    matched point pairs
 *   40     2    crc         u16    CRC-16/CCITT-FALSE of bytes 1..39, low byte first
 *
 * CRC-16/CCITT-FALSE: polynomial 0x1021, initial value 0xFFFF, no
 * reflection, no final XOR; check value ("123456789") 0x29B1. Not the LMS
 * telegram checksum (lms_crc.h): that one is not a textbook CRC, this one
 * has Hamming distance 4 at this size, so every 1-, 2- and 3-bit error in
 * a frame is detected.
 *
 * Decoder: bytes in any chunk sizes. It hunts for 0xE5, rejects a wrong
 * version or length byte as soon as it arrives, checks the CRC when 42
 * bytes are in, and reports the frame. A rejected candidate (version,
 * length or CRC) loses only its start byte: the bytes after it are
 * searched again, so a good frame inside a bad candidate is still found.
 * Counters say what was skipped. Static memory (one frame of buffer), no
 * heap, no float; not reentrant per decoder.
 */
#ifndef EGO_FRAME_H
#define EGO_FRAME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ego.h"

#define EGO_FRAME_START 0xE5u
#define EGO_FRAME_VERSION 0x01u
#define EGO_FRAME_PAYLOAD 37u                    /* the length byte's value */
#define EGO_FRAME_SIZE (3u + EGO_FRAME_PAYLOAD + 2u) /* 42 */

/* CRC-16/CCITT-FALSE of len bytes (see above); 0xFFFF for len 0. */
uint16_t ego_frame_crc16(const uint8_t *data, size_t len);

/* Writes the frame of one scan into out: scan index, its time in us and
 * the fields of o listed above. Returns EGO_FRAME_SIZE, or 0 (nothing
 * written) when out or o is NULL or cap < EGO_FRAME_SIZE. */
size_t ego_frame_encode(uint8_t *out, size_t cap, uint32_t scan, uint32_t time_us,
                        const ego_output_t *o);

/* A decoded frame. out carries pose (x, y, theta), vx, vy, omega, flags,
 * iterations and matches, which is what ego_format_line (ego_loop.h)
 * prints; its other fields are 0. */
typedef struct {
    uint32_t scan;
    uint32_t time_us;
    ego_output_t out;
} ego_frame_t;

/* Counters; they wrap modulo 2^32. At every return of feed / flush:
 * bytes_in == frames * EGO_FRAME_SIZE + bytes_skipped + pending. */
typedef struct {
    uint32_t bytes_in;      /* bytes given to ego_frame_feed */
    uint32_t frames;        /* CRC-valid frames reported */
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
