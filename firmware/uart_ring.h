/* uart_ring.h - the receive ring between a UART interrupt (or a DMA
 * completion interrupt) and the main loop: one producer, one consumer,
 * bytes plus their arrival time (portable C11, no OS headers, no heap).
 *
 * Capacity UART_RING_SIZE bytes, a power of two fixed at compile time.
 * The indices are free-running counters (every byte ever stored / read; they wrap
 * at 2^32; a power-of-two size divides 2^32, so head - tail is always the
 * fill and the slot is index & (size - 1)).
 *
 * Ownership. The producer (uart_ring_put / uart_ring_write: the receive
 * interrupt, or the DMA half/full/idle-line interrupt copying what the DMA
 * wrote into its own buffer) writes head, dropped, peak, the data slots
 * and the stamps; the consumer (uart_ring_read / uart_ring_discard: the
 * main loop) writes tail. Each side only reads the other's index. A full
 * ring refuses new bytes and counts them in dropped: unread data is never
 * overwritten (a circular DMA writing straight into a buffer could not
 * promise that, hence the copy).
 *
 * Memory ordering. Every field is volatile, so the compiler keeps the
 * accesses in program order: the producer stores the byte and its stamp
 * before it publishes head, the consumer loads head before the bytes and
 * publishes tail after it has copied them. On a single-core Cortex-M
 * (M0..M7) the interrupt runs on the core that was interrupted, which sees
 * its own memory accesses in program order, and aligned 32-bit loads and
 * stores are single-copy atomic, so neither side ever sees a half-written
 * index. Nothing more is needed there. Where the other side runs on
 * another core (or a DMA engine, or a cache lies between them: M7 with
 * D-cache and DMA), a barrier is needed where the comments in uart_ring.c
 * say "publish" and "acquire" (DMB on ARM, or C11
 * atomic_thread_fence(memory_order_release / acquire)), plus cache
 * maintenance for DMA buffers.
 *
 * Arrival times. The producer passes its microsecond clock with the bytes;
 * the ring keeps one stamp per block of UART_RING_STAMP_BYTES slots: the
 * time of the latest byte stored in that block. A read returns bytes of one
 * block only and reports its stamp: the arrival time of the last byte
 * returned, or a later one when more bytes came into the same block after
 * it (then by at most the time those took: UART_RING_STAMP_BYTES - 1 byte
 * times when they came back to back, 0.6 ms at 500 kbaud, 32 ms at 9600;
 * plus the pause before them when a pause lies in between, as between two
 * telegrams), or a later lap's time when the ring was within a block of
 * full. Never an earlier one, so a deadline computed from it is never
 * early. A receive interrupt per byte stamps each byte; a DMA interrupt
 * stamps its chunk with the interrupt's time.
 *
 * Cost: UART_RING_SIZE + 4 * UART_RING_SIZE / UART_RING_STAMP_BYTES + 16
 * bytes (2 KiB + 256 + 16 by default). The producer functions are short
 * and bounded (no loops but the copy), so they may run in an interrupt.
 */
#ifndef UART_RING_H
#define UART_RING_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* 2 KiB hold 40 ms at 500 kbaud (50 000 bytes/s), one 361-value telegram
 * (734 bytes) and more; the main loop must drain it within that time. */
#ifndef UART_RING_SIZE
#define UART_RING_SIZE 2048u
#endif
/* Slots per arrival stamp: 4 bytes of RAM per this many slots. */
#ifndef UART_RING_STAMP_BYTES
#define UART_RING_STAMP_BYTES 32u
#endif

_Static_assert(UART_RING_SIZE >= 2u && (UART_RING_SIZE & (UART_RING_SIZE - 1u)) == 0u,
               "UART_RING_SIZE must be a power of two");
_Static_assert(UART_RING_SIZE <= 0x40000000u, "free-running 32-bit indices");
_Static_assert(UART_RING_STAMP_BYTES >= 1u &&
                   (UART_RING_STAMP_BYTES & (UART_RING_STAMP_BYTES - 1u)) == 0u &&
                   UART_RING_STAMP_BYTES <= UART_RING_SIZE,
               "UART_RING_STAMP_BYTES must be a power of two, at most UART_RING_SIZE");

#define UART_RING_STAMPS (UART_RING_SIZE / UART_RING_STAMP_BYTES)

typedef struct {
    /* Private: use the functions below. */
    /* Producer's. */
    volatile uint32_t head;    /* bytes ever stored */
    volatile uint32_t dropped; /* bytes refused: the ring was full */
    volatile uint32_t peak;    /* most bytes waiting at once */
    volatile uint32_t stamp_us[UART_RING_STAMPS];
    volatile uint8_t data[UART_RING_SIZE];
    /* Consumer's. */
    volatile uint32_t tail;    /* bytes ever read or discarded */
} uart_ring_t;

/* Empties the ring and clears its counters. Not while the producer may
 * run: call it before enabling the receive interrupt. */
void uart_ring_init(uart_ring_t *r);

/* Producer. Stores one byte that arrived at now_us; false when the ring is
 * full (the byte is dropped and counted). */
bool uart_ring_put(uart_ring_t *r, uint8_t byte, uint32_t now_us);

/* Producer. Stores up to len bytes that arrived by now_us, in order, and
 * returns how many; the rest (no room) is dropped and counted. */
size_t uart_ring_write(uart_ring_t *r, const uint8_t *bytes, size_t len, uint32_t now_us);

/* Consumer. Copies up to cap waiting bytes into out, oldest first, but
 * not past the end of a stamp block (at most UART_RING_STAMP_BYTES), and
 * returns how many (0: none waiting). *arrival_us (if not NULL; untouched
 * when 0 bytes are returned) gets the arrival time of the last byte copied,
 * as described above. */
size_t uart_ring_read(uart_ring_t *r, uint8_t *out, size_t cap, uint32_t *arrival_us);

/* Consumer. Drops every byte waiting now (after a change of the line rate,
 * the bytes received at the old one); returns how many. */
size_t uart_ring_discard(uart_ring_t *r);

/* Bytes waiting (either side may ask; the answer may be stale by the time
 * it is used, but never more than the ring holds). */
size_t uart_ring_count(const uart_ring_t *r);

/* Bytes refused because the ring was full, since uart_ring_init. */
uint32_t uart_ring_dropped(const uart_ring_t *r);

/* The most bytes that were waiting at once, since uart_ring_init: how much
 * of UART_RING_SIZE the loop needed. */
uint32_t uart_ring_peak(const uart_ring_t *r);

#endif /* UART_RING_H */
