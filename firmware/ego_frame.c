/* ego_frame.c - see ego_frame.h. */
#include "ego_frame.h"

#include <string.h>

/* Byte offsets of the layout table in ego_frame.h. */
enum {
    OFF_VERSION = 1,
    OFF_LENGTH = 2,
    OFF_SCAN = 3,
    OFF_TIME = 7,
    OFF_X = 11,
    OFF_Y = 15,
    OFF_THETA = 19,
    OFF_VX = 23,
    OFF_VY = 27,
    OFF_OMEGA = 31,
    OFF_FLAGS = 35,
    OFF_ITERATIONS = 37,
    OFF_MATCHES = 38,
    OFF_COV = 40, /* xx, xy, xt, yy, yt, tt: 4 bytes each */
    OFF_CRC = 64,
    OFF_V1_CRC = 40
};
_Static_assert(OFF_CRC == 3 + EGO_FRAME_PAYLOAD, "payload ends at the CRC");
_Static_assert(OFF_V1_CRC == 3 + EGO_FRAME_V1_PAYLOAD, "version 1's payload ends at its CRC");
_Static_assert(EGO_FRAME_SIZE <= UINT8_MAX, "fill is a uint8_t");

#define CRC_POLY 0x1021u
#define CRC_INIT 0xFFFFu

uint16_t ego_frame_crc16(const uint8_t *data, size_t len)
{
    /* Bit-serial, MSB first, from the CRC-16/CCITT-FALSE parameters: 8
     * shifts per byte are cheap next to a scan match, and need no table. */
    uint32_t crc = CRC_INIT;
    for (size_t i = 0u; i < len; i++) {
        crc ^= (uint32_t)data[i] << 8;
        for (unsigned bit = 0u; bit < 8u; bit++) {
            crc = (crc & 0x8000u) ? ((crc << 1) ^ CRC_POLY) : (crc << 1);
        }
        crc &= 0xFFFFu;
    }
    return (uint16_t)crc;
}

static void put_u16(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)((v >> 8) & 0xFFu);
}

static void put_u32(uint8_t *p, uint32_t v)
{
    put_u16(p, v & 0xFFFFu);
    put_u16(p + 2, v >> 16);
}

static uint32_t get_u16(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8);
}

static uint32_t get_u32(const uint8_t *p)
{
    return get_u16(p) | (get_u16(p + 2) << 16);
}

/* Two's complement bits back to int32 without the implementation-defined
 * unsigned -> signed conversion. */
static int32_t get_s32(const uint8_t *p)
{
    const uint32_t u = get_u32(p);
    if (u <= (uint32_t)INT32_MAX) {
        return (int32_t)u;
    }
    return -(int32_t)(~u) - 1;
}

size_t ego_frame_encode(uint8_t *out, size_t cap, uint32_t scan, uint32_t time_us,
                        const ego_output_t *o)
{
    if (out == NULL || o == NULL || cap < EGO_FRAME_SIZE) {
        return 0u;
    }
    out[0] = EGO_FRAME_START;
    out[OFF_VERSION] = EGO_FRAME_VERSION;
    out[OFF_LENGTH] = EGO_FRAME_PAYLOAD;
    put_u32(&out[OFF_SCAN], scan);
    put_u32(&out[OFF_TIME], time_us);
    put_u32(&out[OFF_X], (uint32_t)o->pose.x);
    put_u32(&out[OFF_Y], (uint32_t)o->pose.y);
    put_u32(&out[OFF_THETA], o->pose.theta);
    put_u32(&out[OFF_VX], (uint32_t)o->vx);
    put_u32(&out[OFF_VY], (uint32_t)o->vy);
    put_u32(&out[OFF_OMEGA], (uint32_t)o->omega);
    put_u16(&out[OFF_FLAGS], o->flags);
    out[OFF_ITERATIONS] = o->iterations;
    put_u16(&out[OFF_MATCHES], o->matches);
    const fx_q2_30_t cov[6] = {o->cov.xx, o->cov.xy, o->cov.xt, o->cov.yy, o->cov.yt, o->cov.tt};
    for (unsigned k = 0u; k < 6u; k++) {
        put_u32(&out[OFF_COV + 4u * k], (uint32_t)cov[k]);
    }
    /* Everything after the start byte: a corrupted start is caught by the
     * hunt, the rest by the CRC. */
    put_u16(&out[OFF_CRC], ego_frame_crc16(&out[1], OFF_CRC - 1u));
    return EGO_FRAME_SIZE;
}

void ego_frame_decoder_init(ego_frame_decoder_t *d)
{
    memset(d, 0, sizeof *d);
}

size_t ego_frame_pending(const ego_frame_decoder_t *d)
{
    return d->fill;
}

const ego_frame_stats_t *ego_frame_stats(const ego_frame_decoder_t *d)
{
    return &d->stats;
}

/* Rejects the candidate: drops its start byte and whatever follows up to
 * the next start byte, so buf[0] is a start again (or nothing is left). */
static void drop_start(ego_frame_decoder_t *d)
{
    size_t cut = 1u;
    while (cut < d->fill && d->buf[cut] != EGO_FRAME_START) {
        cut++;
    }
    d->stats.bytes_skipped += (uint32_t)cut;
    d->fill = (uint8_t)(d->fill - cut);
    memmove(d->buf, &d->buf[cut], d->fill);
}

/* The bytes of a frame of this version (a version not known: the
 * current one's, for the checks to reject it by). */
static size_t frame_size(uint8_t version)
{
    return (version == EGO_FRAME_V1_VERSION) ? EGO_FRAME_V1_SIZE : EGO_FRAME_SIZE;
}

/* Checks the buffered candidate after a byte was added: true when it is a
 * complete frame with a good CRC; rejected candidates are dropped on the
 * way. */
static bool check_candidate(ego_frame_decoder_t *d)
{
    /* Each pass returns or drops at least one byte: fill bounds it. */
    for (unsigned guard = 0u; guard <= EGO_FRAME_SIZE; guard++) {
        if (d->fill == 0u) {
            return false;
        }
        const uint8_t version = (d->fill > OFF_VERSION) ? d->buf[OFF_VERSION] : EGO_FRAME_VERSION;
        const bool known = version == EGO_FRAME_VERSION || version == EGO_FRAME_V1_VERSION;
        const size_t size = frame_size(version);
        const uint8_t payload = (uint8_t)(size - 5u);
        if (!known || (d->fill > OFF_LENGTH && d->buf[OFF_LENGTH] != payload)) {
            d->stats.length_errors++;
        } else if (d->fill < size) {
            return false;
        } else if (ego_frame_crc16(&d->buf[1], size - 3u) == get_u16(&d->buf[size - 2u])) {
            return true;
        } else {
            d->stats.crc_errors++;
        }
        drop_start(d);
    }
    return false;
}

/* Counts the complete frame at buf[0] and removes it. The buffer can hold
 * more than the frame: a version 2 candidate whose CRC failed may hide a
 * version 1 frame followed by the start of the next one (at most
 * 66 - 1 - 42 = 23 bytes, never a whole frame). Those bytes stay, the
 * ones before the next start byte skipped, and are checked again, so the
 * next frame is still found. */
static void take_frame(ego_frame_decoder_t *d)
{
    const size_t size = frame_size(d->buf[OFF_VERSION]);
    d->stats.frames++;
    d->stats.bytes_framed += (uint32_t)size;
    d->fill = (uint8_t)(d->fill - size);
    memmove(d->buf, &d->buf[size], d->fill);
    if (d->fill > 0u && d->buf[0] != EGO_FRAME_START) {
        drop_start(d);
    }
    /* Rejects a bad rest now; it is too short to be complete. */
    (void)check_candidate(d);
}

static void decode(const uint8_t *b, ego_frame_t *f)
{
    memset(f, 0, sizeof *f);
    f->scan = get_u32(&b[OFF_SCAN]);
    f->time_us = get_u32(&b[OFF_TIME]);
    f->out.pose.x = get_s32(&b[OFF_X]);
    f->out.pose.y = get_s32(&b[OFF_Y]);
    f->out.pose.theta = get_u32(&b[OFF_THETA]);
    f->out.vx = get_s32(&b[OFF_VX]);
    f->out.vy = get_s32(&b[OFF_VY]);
    f->out.omega = get_s32(&b[OFF_OMEGA]);
    f->out.flags = (uint16_t)get_u16(&b[OFF_FLAGS]);
    f->out.iterations = b[OFF_ITERATIONS];
    f->out.matches = (uint16_t)get_u16(&b[OFF_MATCHES]);
    if (b[OFF_VERSION] == EGO_FRAME_V1_VERSION) {
        ego_cov_unknown(&f->out.cov);
        return;
    }
    f->out.cov.xx = get_s32(&b[OFF_COV]);
    f->out.cov.xy = get_s32(&b[OFF_COV + 4u]);
    f->out.cov.xt = get_s32(&b[OFF_COV + 8u]);
    f->out.cov.yy = get_s32(&b[OFF_COV + 12u]);
    f->out.cov.yt = get_s32(&b[OFF_COV + 16u]);
    f->out.cov.tt = get_s32(&b[OFF_COV + 20u]);
}

ego_frame_event_t ego_frame_feed(ego_frame_decoder_t *d, const uint8_t *bytes, size_t len,
                                 size_t *consumed, ego_frame_t *frame)
{
    if (bytes == NULL) {
        len = 0u;
    }
    for (size_t i = 0u; i < len; i++) {
        const uint8_t b = bytes[i];
        d->stats.bytes_in++;
        if (d->fill == 0u && b != EGO_FRAME_START) {
            d->stats.bytes_skipped++; /* hunting */
            continue;
        }
        d->buf[d->fill++] = b;
        if (check_candidate(d)) {
            decode(d->buf, frame);
            take_frame(d);
            *consumed = i + 1u;
            return EGO_FRAME_READY;
        }
    }
    *consumed = len;
    return EGO_FRAME_NEED_MORE;
}

void ego_frame_flush(ego_frame_decoder_t *d)
{
    if (d->fill > 0u) {
        d->stats.truncated++;
        d->stats.bytes_skipped += d->fill;
        d->fill = 0u;
    }
}
