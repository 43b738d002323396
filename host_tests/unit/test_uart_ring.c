/* test_uart_ring.c - the receive ring (firmware/uart_ring.h): empty reads,
 * order across the wrap-around of the slots and of the 32-bit indices, a
 * full ring (new bytes dropped and counted, no unread byte overwritten),
 * discarding, arrival stamps, and a long run of odd-sized writes and reads
 * against a model. */
#include <string.h>

#include "uart_ring.h"
#include "unity.h"

static uart_ring_t R;

void setUp(void)
{
    uart_ring_init(&R);
}

void tearDown(void)
{
}

/* Reads up to cap bytes in as many reads as that takes (each within one
 * stamp block); *t (if not NULL) gets the last read's stamp. */
static size_t drain(uint8_t *out, size_t cap, uint32_t *t)
{
    size_t total = 0u;
    for (uint32_t guard = 0u; guard <= UART_RING_SIZE && total < cap; guard++) {
        const size_t n = uart_ring_read(&R, out + total, cap - total, t);
        TEST_ASSERT_TRUE(n <= UART_RING_STAMP_BYTES);
        if (n == 0u) {
            break;
        }
        total += n;
    }
    return total;
}

/* Byte i of a test sequence: never the same for 251 bytes in a row. */
static uint8_t seq(uint32_t i)
{
    return (uint8_t)(i % 251u);
}

static void test_uart_ring_empty_reads_nothing(void)
{
    uint8_t out[8] = {0xAAu, 0xAAu, 0xAAu, 0xAAu, 0xAAu, 0xAAu, 0xAAu, 0xAAu};
    uint32_t t = 12345u;
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_count(&R));
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_read(&R, out, sizeof out, &t));
    TEST_ASSERT_EQUAL_UINT32(12345u, t); /* untouched */
    TEST_ASSERT_EQUAL_HEX8(0xAAu, out[0]);
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_read(&R, out, 0u, NULL));
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_discard(&R));
    /* After bytes were read, empty again. */
    TEST_ASSERT_TRUE(uart_ring_put(&R, 7u, 1u));
    TEST_ASSERT_EQUAL_UINT(1u, uart_ring_read(&R, out, sizeof out, &t));
    TEST_ASSERT_EQUAL_HEX8(7u, out[0]);
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_read(&R, out, sizeof out, &t));
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_count(&R));
    TEST_ASSERT_EQUAL_UINT32(0u, uart_ring_dropped(&R));
}

static void test_uart_ring_keeps_order_across_the_wrap(void)
{
    static uint8_t out[UART_RING_SIZE];
    uint32_t next_in = 0u;
    uint32_t next_out = 0u;
    /* Three quarters in, out, then across the end of the slots. */
    for (int round = 0; round < 6; round++) {
        const uint32_t n = UART_RING_SIZE / 4u * 3u;
        for (uint32_t i = 0u; i < n; i++) {
            TEST_ASSERT_TRUE(uart_ring_put(&R, seq(next_in++), 100u));
        }
        TEST_ASSERT_EQUAL_UINT(n, uart_ring_count(&R));
        TEST_ASSERT_EQUAL_UINT(n, drain(out, sizeof out, NULL));
        for (uint32_t i = 0u; i < n; i++) {
            TEST_ASSERT_EQUAL_HEX8(seq(next_out++), out[i]);
        }
    }
    TEST_ASSERT_EQUAL_UINT32(0u, uart_ring_dropped(&R));
}

/* The free-running indices wrap at 2^32: the fill and the slots stay right. */
static void test_uart_ring_index_wrap(void)
{
    R.head = 0xFFFFFFF0u;
    R.tail = 0xFFFFFFF0u;
    uint8_t in[40];
    uint8_t out[40];
    for (uint32_t i = 0u; i < sizeof in; i++) {
        in[i] = seq(i + 3u);
    }
    TEST_ASSERT_EQUAL_UINT(sizeof in, uart_ring_write(&R, in, sizeof in, 5u));
    TEST_ASSERT_EQUAL_UINT(sizeof in, uart_ring_count(&R));
    /* The first read stops at the end of the last slots' stamp block. */
    TEST_ASSERT_EQUAL_UINT(16u, uart_ring_read(&R, out, 25u, NULL));
    TEST_ASSERT_EQUAL_UINT(24u, drain(out + 16, sizeof out - 16u, NULL));
    TEST_ASSERT_EQUAL_UINT8_ARRAY(in, out, sizeof in);
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_count(&R));
    TEST_ASSERT_EQUAL_UINT32(24u, R.head); /* 0xFFFFFFF0 + 40, wrapped */
}

/* Full: put and write refuse, count what they refuse, and every byte that
 * was stored comes out unchanged. */
static void test_uart_ring_full_drops_new_bytes_only(void)
{
    static uint8_t out[UART_RING_SIZE + 16u];
    for (uint32_t i = 0u; i < UART_RING_SIZE; i++) {
        TEST_ASSERT_TRUE(uart_ring_put(&R, seq(i), 1u));
    }
    TEST_ASSERT_EQUAL_UINT(UART_RING_SIZE, uart_ring_count(&R));
    TEST_ASSERT_FALSE(uart_ring_put(&R, 0xEEu, 2u));
    TEST_ASSERT_EQUAL_UINT32(1u, uart_ring_dropped(&R));
    const uint8_t more[5] = {0xEEu, 0xEEu, 0xEEu, 0xEEu, 0xEEu};
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_write(&R, more, sizeof more, 3u));
    TEST_ASSERT_EQUAL_UINT32(6u, uart_ring_dropped(&R));
    TEST_ASSERT_EQUAL_UINT32(UART_RING_SIZE, uart_ring_peak(&R));
    /* Room for 3: a write of 5 stores 3, drops 2. */
    TEST_ASSERT_EQUAL_UINT(3u, uart_ring_read(&R, out, 3u, NULL));
    for (uint32_t i = 0u; i < 3u; i++) {
        TEST_ASSERT_EQUAL_HEX8(seq(i), out[i]);
    }
    const uint8_t tail[5] = {0xC1u, 0xC2u, 0xC3u, 0xC4u, 0xC5u};
    TEST_ASSERT_EQUAL_UINT(3u, uart_ring_write(&R, tail, sizeof tail, 4u));
    TEST_ASSERT_EQUAL_UINT32(8u, uart_ring_dropped(&R));
    TEST_ASSERT_EQUAL_UINT(UART_RING_SIZE, drain(out, sizeof out, NULL));
    for (uint32_t i = 3u; i < UART_RING_SIZE; i++) {
        TEST_ASSERT_EQUAL_HEX8(seq(i), out[i - 3u]);
    }
    TEST_ASSERT_EQUAL_HEX8(0xC1u, out[UART_RING_SIZE - 3u]);
    TEST_ASSERT_EQUAL_HEX8(0xC2u, out[UART_RING_SIZE - 2u]);
    TEST_ASSERT_EQUAL_HEX8(0xC3u, out[UART_RING_SIZE - 1u]);
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_count(&R));
}

static void test_uart_ring_discard_drops_what_waits(void)
{
    uint8_t in[10];
    uint8_t out[10];
    memset(in, 0x11, sizeof in);
    (void)uart_ring_write(&R, in, sizeof in, 1u);
    TEST_ASSERT_EQUAL_UINT(10u, uart_ring_discard(&R));
    TEST_ASSERT_EQUAL_UINT(0u, uart_ring_count(&R));
    TEST_ASSERT_TRUE(uart_ring_put(&R, 0x22u, 2u));
    TEST_ASSERT_EQUAL_UINT(1u, uart_ring_read(&R, out, sizeof out, NULL));
    TEST_ASSERT_EQUAL_HEX8(0x22u, out[0]);
    TEST_ASSERT_EQUAL_UINT32(0u, uart_ring_dropped(&R)); /* discarded is not dropped */
}

/* A read stays within one stamp block and reports that block's stamp: its
 * last byte's time when nothing came after it in the block, a later time
 * otherwise, never an earlier one. */
static void test_uart_ring_arrival_stamps(void)
{
    const uint32_t b = UART_RING_STAMP_BYTES;
    uint8_t out[4u * UART_RING_STAMP_BYTES];
    uint32_t t = 0u;
    /* Byte i arrives at 1000 + 10 i. */
    for (uint32_t i = 0u; i < 3u * b; i++) {
        TEST_ASSERT_TRUE(uart_ring_put(&R, seq(i), 1000u + 10u * i));
    }
    /* The whole first block: its last byte's time. */
    TEST_ASSERT_EQUAL_UINT(b, uart_ring_read(&R, out, b, &t));
    TEST_ASSERT_EQUAL_UINT32(1000u + 10u * (b - 1u), t);
    /* Half of the second block: the block's latest byte, later than the
     * last byte read by the rest of the block. */
    TEST_ASSERT_EQUAL_UINT(b / 2u, uart_ring_read(&R, out, b / 2u, &t));
    TEST_ASSERT_EQUAL_UINT32(1000u + 10u * (2u * b - 1u), t);
    TEST_ASSERT_TRUE(t >= 1000u + 10u * (b + b / 2u - 1u));
    /* The rest of the second block (a read never crosses into the next),
     * then the third. */
    TEST_ASSERT_EQUAL_UINT(b / 2u, uart_ring_read(&R, out, sizeof out, &t));
    TEST_ASSERT_EQUAL_UINT32(1000u + 10u * (2u * b - 1u), t);
    TEST_ASSERT_EQUAL_UINT(b, uart_ring_read(&R, out, sizeof out, &t));
    TEST_ASSERT_EQUAL_UINT32(1000u + 10u * (3u * b - 1u), t);
    /* A chunk written at once carries the chunk's time. */
    TEST_ASSERT_EQUAL_UINT(5u, uart_ring_write(&R, out, 5u, 77777u));
    TEST_ASSERT_EQUAL_UINT(5u, uart_ring_read(&R, out, sizeof out, &t));
    TEST_ASSERT_EQUAL_UINT32(77777u, t);
}

/* Odd-sized writes and reads (fixed seed) against a model: the same bytes
 * in the same order, drops only when the model says the ring was full. */
static void test_uart_ring_random_against_model(void)
{
    static uint8_t in[300];
    static uint8_t out[300];
    uint32_t rng = 0x1234567u;
    uint32_t produced = 0u;  /* sequence numbers stored */
    uint32_t consumed = 0u;
    uint32_t offered = 0u;   /* sequence numbers offered, stored or not */
    uint32_t dropped = 0u;
    for (int round = 0; round < 4000; round++) {
        rng ^= rng << 13;
        rng ^= rng >> 17;
        rng ^= rng << 5;
        const uint32_t w = rng % 300u;
        const uint32_t r = (rng >> 9) % 300u;
        /* Stored bytes carry their sequence number; dropped ones are
         * skipped in it, so the model knows which must come out. */
        const uint32_t room = UART_RING_SIZE - (produced - consumed);
        const uint32_t fit = w < room ? w : room;
        for (uint32_t i = 0u; i < w; i++) {
            in[i] = seq(produced + i);
        }
        TEST_ASSERT_EQUAL_UINT(fit, uart_ring_write(&R, in, w, (uint32_t)round));
        produced += fit;
        offered += w;
        dropped += w - fit;
        const uint32_t avail = produced - consumed;
        const uint32_t take = r < avail ? r : avail;
        TEST_ASSERT_EQUAL_UINT(take, drain(out, r, NULL));
        for (uint32_t i = 0u; i < take; i++) {
            TEST_ASSERT_EQUAL_HEX8(seq(consumed + i), out[i]);
        }
        consumed += take;
        TEST_ASSERT_EQUAL_UINT(produced - consumed, uart_ring_count(&R));
    }
    TEST_ASSERT_EQUAL_UINT32(dropped, uart_ring_dropped(&R));
    TEST_ASSERT_TRUE(dropped > 0u); /* the run did fill the ring */
    TEST_ASSERT_TRUE(offered > 10u * UART_RING_SIZE);
    TEST_ASSERT_EQUAL_UINT32(UART_RING_SIZE, uart_ring_peak(&R));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_uart_ring_empty_reads_nothing);
    RUN_TEST(test_uart_ring_keeps_order_across_the_wrap);
    RUN_TEST(test_uart_ring_index_wrap);
    RUN_TEST(test_uart_ring_full_drops_new_bytes_only);
    RUN_TEST(test_uart_ring_discard_drops_what_waits);
    RUN_TEST(test_uart_ring_arrival_stamps);
    RUN_TEST(test_uart_ring_random_against_model);
    return UNITY_END();
}
