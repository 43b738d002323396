/* uart_ring.c - see uart_ring.h. */
#include "uart_ring.h"

#define MASK (UART_RING_SIZE - 1u)

void uart_ring_init(uart_ring_t *r)
{
    r->head = 0u;
    r->tail = 0u;
    r->dropped = 0u;
    r->peak = 0u;
    for (uint32_t i = 0u; i < UART_RING_STAMPS; i++) {
        r->stamp_us[i] = 0u;
    }
}

/* Stores bytes[0..n) at head (room checked by the caller), stamps them and
 * publishes them. Producer only. */
static void store(uart_ring_t *r, uint32_t head, uint32_t used, const uint8_t *bytes, uint32_t n,
                  uint32_t now_us)
{
    for (uint32_t i = 0u; i < n; i++) {
        const uint32_t slot = (head + i) & MASK;
        r->data[slot] = bytes[i];
        r->stamp_us[slot / UART_RING_STAMP_BYTES] = now_us;
    }
    if (used + n > r->peak) {
        r->peak = used + n;
    }
    /* Publish: the bytes and stamps above are stored before head moves
     * (volatile order; a DMB here on a multi-core part). */
    r->head = head + n;
}

bool uart_ring_put(uart_ring_t *r, uint8_t byte, uint32_t now_us)
{
    const uint32_t head = r->head;
    const uint32_t used = head - r->tail;
    if (used >= UART_RING_SIZE) {
        r->dropped = r->dropped + 1u;
        return false;
    }
    store(r, head, used, &byte, 1u, now_us);
    return true;
}

size_t uart_ring_write(uart_ring_t *r, const uint8_t *bytes, size_t len, uint32_t now_us)
{
    const uint32_t head = r->head;
    const uint32_t used = head - r->tail;
    const uint32_t room = used >= UART_RING_SIZE ? 0u : UART_RING_SIZE - used;
    const uint32_t n = len < room ? (uint32_t)len : room;
    if (n < len) {
        /* At most len - room; a count of dropped bytes may wrap after 4 G. */
        r->dropped = r->dropped + (uint32_t)(len - n);
    }
    if (n > 0u) {
        store(r, head, used, bytes, n, now_us);
    }
    return n;
}

size_t uart_ring_read(uart_ring_t *r, uint8_t *out, size_t cap, uint32_t *arrival_us)
{
    const uint32_t tail = r->tail;
    /* Acquire: head is loaded before the bytes it covers (a DMB after this
     * load on a multi-core part). */
    const uint32_t head = r->head;
    const uint32_t waiting = head - tail; /* at most UART_RING_SIZE */
    /* Up to the end of tail's stamp block, so one stamp covers them all. */
    const uint32_t block_left = UART_RING_STAMP_BYTES - (tail & (UART_RING_STAMP_BYTES - 1u));
    uint32_t n = cap < waiting ? (uint32_t)cap : waiting;
    if (n > block_left) {
        n = block_left;
    }
    if (n == 0u) {
        return 0u;
    }
    for (uint32_t i = 0u; i < n; i++) {
        out[i] = r->data[(tail + i) & MASK];
    }
    if (arrival_us != NULL) {
        *arrival_us = r->stamp_us[((tail + n - 1u) & MASK) / UART_RING_STAMP_BYTES];
    }
    /* Publish: the slots are free only after they were copied. */
    r->tail = tail + n;
    return n;
}

size_t uart_ring_discard(uart_ring_t *r)
{
    const uint32_t tail = r->tail;
    const uint32_t head = r->head;
    r->tail = head;
    return head - tail;
}

size_t uart_ring_count(const uart_ring_t *r)
{
    const uint32_t tail = r->tail;
    const uint32_t n = r->head - tail;
    return n > UART_RING_SIZE ? UART_RING_SIZE : n;
}

uint32_t uart_ring_dropped(const uart_ring_t *r)
{
    return r->dropped;
}

uint32_t uart_ring_peak(const uart_ring_t *r)
{
    return r->peak;
}
