#!/usr/bin/env python3
"""Draw one scan with its moving objects as a PNG (standard library only).

usage: objects_plot.py SCANS TRUTH.objects OURS.csv SCAN OUT.png [--size 720x480] [--view 40x20]

SCANS: `lmsego scans STREAM` output (index unit_mm n v1 .. vn, mm; negative:
no range), a 180-degree LMS scan, value k at k * 180 / (n - 1) degrees with
90 straight ahead. TRUTH.objects: lmsworld --objects. OURS.csv: `lmsego
replay --objects`. Scanner frame, x forward (right in the image), y left
(up). Drawn: the scan's points (grey, over the rest; the scanner black), the truth objects with at least one
return (green: their rectangle and 0.5 s of their velocity), ours (red:
the box centre as a cross, an axis-aligned square of its length, and 0.5 s
of its velocity). --view WxH metres from x = -2, centred on y = 0.
"""
import argparse
import math
import struct
import sys
import zlib

WHITE = (255, 255, 255)
GREY = (110, 110, 110)
LIGHT = (225, 225, 225)
GREEN = (0, 150, 0)
RED = (210, 0, 0)


class Canvas:
    def __init__(self, w, h):
        self.w, self.h = w, h
        self.px = bytearray(WHITE * (w * h))

    def set(self, x, y, c):
        if 0 <= x < self.w and 0 <= y < self.h:
            i = 3 * (y * self.w + x)
            self.px[i:i + 3] = bytes(c)

    def line(self, x0, y0, x1, y1, c):
        x0, y0, x1, y1 = int(round(x0)), int(round(y0)), int(round(x1)), int(round(y1))
        dx, dy = abs(x1 - x0), -abs(y1 - y0)
        sx, sy = (1 if x0 < x1 else -1), (1 if y0 < y1 else -1)
        err = dx + dy
        for _ in range(4 * (self.w + self.h)):
            self.set(x0, y0, c)
            if x0 == x1 and y0 == y1:
                break
            e2 = 2 * err
            if e2 >= dy:
                err += dy
                x0 += sx
            if e2 <= dx:
                err += dx
                y0 += sy

    def dot(self, x, y, c, r=1):
        for i in range(-r, r + 1):
            for j in range(-r, r + 1):
                self.set(int(round(x)) + i, int(round(y)) + j, c)

    def png(self, path):
        raw = b''.join(b'\x00' + bytes(self.px[3 * y * self.w:3 * (y + 1) * self.w])
                       for y in range(self.h))

        def chunk(kind, data):
            body = kind + data
            return struct.pack('>I', len(data)) + body + struct.pack('>I', zlib.crc32(body))

        with open(path, 'wb') as f:
            f.write(b'\x89PNG\r\n\x1a\n')
            f.write(chunk(b'IHDR', struct.pack('>IIBBBBB', self.w, self.h, 8, 2, 0, 0, 0)))
            f.write(chunk(b'IDAT', zlib.compress(raw, 9)))
            f.write(chunk(b'IEND', b''))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('scans')
    ap.add_argument('truth')
    ap.add_argument('ours')
    ap.add_argument('scan', type=int)
    ap.add_argument('out')
    ap.add_argument('--size', default='720x480')
    ap.add_argument('--view', default='36x24')
    a = ap.parse_args()
    w, h = (int(v) for v in a.size.split('x'))
    vw, vh = (float(v) for v in a.view.split('x'))
    scale = min(w / vw, h / vh)
    x_min = -2.0

    def to_px(x, y):
        return (x - x_min) * scale, h / 2 - y * scale

    cv = Canvas(w, h)
    for gx in range(int(x_min), int(x_min + vw) + 1, 5):  # a 5 m grid
        px, _ = to_px(gx, 0)
        cv.line(px, 0, px, h - 1, LIGHT)
    for gy in range(-int(vh / 2) // 5 * 5, int(vh / 2) + 1, 5):
        _, py = to_px(0, gy)
        cv.line(0, py, w - 1, py, LIGHT)
    values = None
    with open(a.scans) as f:
        for line in f:
            v = line.split()
            if int(v[0]) == a.scan:
                values = [int(x) for x in v[3:]]
                break
    if values is None:
        sys.exit(f'objects_plot: no scan {a.scan} in {a.scans}')
    with open(a.truth) as f:
        for line in f:
            if line.startswith('#') or not line.strip():
                continue
            v = line.split()
            if int(v[0]) != a.scan or int(v[9]) == 0:
                continue
            cx, cy, hd, vx, vy, ln, wd = (float(x) for x in v[2:9])
            c, s = math.cos(hd), math.sin(hd)
            corners = [(cx + c * u - s * q, cy + s * u + c * q)
                       for u, q in ((ln / 2, wd / 2), (-ln / 2, wd / 2), (-ln / 2, -wd / 2),
                                    (ln / 2, -wd / 2))]
            for i in range(4):
                cv.line(*to_px(*corners[i]), *to_px(*corners[(i + 1) % 4]), GREEN)
            cv.line(*to_px(cx, cy), *to_px(cx + 0.5 * vx, cy + 0.5 * vy), GREEN)
    with open(a.ours) as f:
        f.readline()
        for line in f:
            v = line.strip().split(',')
            if int(v[0]) != a.scan:
                continue
            cx, cy, ln = float(v[2]), float(v[3]), float(v[4])
            px, py = to_px(cx, cy)
            cv.line(px - 5, py - 5, px + 5, py + 5, RED)
            cv.line(px - 5, py + 5, px + 5, py - 5, RED)
            r = max(ln / 2, 0.3)
            sq = [(cx - r, cy - r), (cx + r, cy - r), (cx + r, cy + r), (cx - r, cy + r)]
            for i in range(4):
                cv.line(*to_px(*sq[i]), *to_px(*sq[(i + 1) % 4]), RED)
            vx, vy = float(v[6]), float(v[7])
            if math.isfinite(vx) and math.isfinite(vy):
                cv.line(px, py, *to_px(cx + 0.5 * vx, cy + 0.5 * vy), RED)
    n = len(values)  # the points last, over the boxes
    for k, mm in enumerate(values):
        if mm <= 0:
            continue
        b = math.radians(k * 180.0 / (n - 1) - 90.0)
        cv.dot(*to_px(mm / 1000 * math.cos(b), mm / 1000 * math.sin(b)), GREY, 1)
    cv.dot(*to_px(0, 0), (0, 0, 0), 3)
    cv.png(a.out)
    return 0


if __name__ == '__main__':
    sys.exit(main())
