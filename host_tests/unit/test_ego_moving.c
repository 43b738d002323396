/* test_ego_moving.c - the moving clusters of a range scan
 * (estimator/ego_moving.h) on scenes cast in doubles.
 *
 * A tiny world of straight walls and moving boxes (host_tests/ref/
 * moving_ref.c casts the rays) and a vehicle whose motion per line is
 * given exactly: the fixed-point pose handed to ego_moving_scan is the
 * truth the world moves the vehicle by. Scans at 75 Hz (13333 us apart),
 * in millimetres, 181 values over 180 degrees (or 720 at 0.25 degree).
 * Checked: boxes and velocities against their double oracle
 * (moving_ref.c: the chord box, the uncut ends, the velocity rule) and
 * velocities against the truth; no object in a static world; the reveal
 * rule; every restart rule; misses, slots and the hold; the slack from the
 * covariance and its cap; capacity and bounds; ids; random input (bounds,
 * the work meter, determinism, reset). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ego_moving.h"
#include "fx_host.h"
#include "moving_ref.h"
#include "test_rng.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* --- the simulated world -------------------------------------------------- */

#define BEAMS 181u
#define FINE_BEAMS 720u /* 0.25 deg: EGO_MAX_BEAMS, a reference decimated 4:1 */
#define DT_US 13333u
#define DT_S ((double)DT_US * 1e-6)
#define T0_US 7000000u /* the first line's time: any */
#define MAX_WALLS 96u
#define MAX_BODIES 24u
#define CAST_MAX_M 80.0 /* farther: no return */
#define PI FX_HOST_PI

/* A box moving at a constant velocity, present while t_on <= t < t_off. */
typedef struct {
    double cx; /* world, at t = 0, m */
    double cy;
    double heading; /* of its length, rad */
    double length;
    double width;
    double vx; /* world, m/s */
    double vy;
    double t_on; /* s */
    double t_off;
} body_t;

typedef struct {
    moving_ref_wall_t wall[MAX_WALLS];
    size_t walls;
    body_t body[MAX_BODIES];
    size_t bodies;
} world_t;

typedef struct {
    ego_moving_t m;
    double x; /* the vehicle in the world, m, rad */
    double y;
    double h;
    double t; /* s since the first line */
    uint32_t time_us;
    unsigned line; /* lines since the first (0) */
    uint16_t range[EGO_MAX_BEAMS];
    ego_range_scan_t scan;
    ego_output_t out;
    ego_moving_object_t obj[EGO_MOVING_MAX_OBJECTS];
    uint8_t n;
} sim_t;

static world_t g_world;
static sim_t g_sim;

static void world_clear(world_t *w)
{
    memset(w, 0, sizeof *w);
}

static void world_wall(world_t *w, double x0, double y0, double x1, double y1)
{
    TEST_ASSERT_TRUE(w->walls < MAX_WALLS);
    w->wall[w->walls++] = (moving_ref_wall_t){x0, y0, x1, y1};
}

/* A box, present all the time; returns its index. */
static size_t world_body(world_t *w, double cx, double cy, double heading, double length,
                         double width, double vx, double vy)
{
    TEST_ASSERT_TRUE(w->bodies < MAX_BODIES);
    w->body[w->bodies] = (body_t){cx, cy, heading, length, width, vx, vy, -1.0, 1e9};
    return w->bodies++;
}

/* A car 4.5 m x 1.8 m whose length lies along its velocity. */
static size_t world_car(world_t *w, double cx, double cy, double vx, double vy)
{
    return world_body(w, cx, cy, atan2(vy, vx), 4.5, 1.8, vx, vy);
}

/* A pedestrian-like body, 0.5 m square. */
static size_t world_walker(world_t *w, double cx, double cy, double vx, double vy)
{
    return world_body(w, cx, cy, atan2(vy, vx), 0.5, 0.5, vx, vy);
}

static bool body_present(const body_t *b, double t)
{
    return t >= b->t_on && t < b->t_off;
}

/* The body's centre in the world at t. */
static void body_at(const body_t *b, double t, double *x, double *y)
{
    *x = b->cx + b->vx * t;
    *y = b->cy + b->vy * t;
}

/* A world point and a world vector in the vehicle's frame, and back. */
static void to_vehicle(const sim_t *s, double wx, double wy, double *x, double *y)
{
    const double dx = wx - s->x;
    const double dy = wy - s->y;
    *x = cos(s->h) * dx + sin(s->h) * dy;
    *y = -sin(s->h) * dx + cos(s->h) * dy;
}

static void vec_to_vehicle(const sim_t *s, double wx, double wy, double *x, double *y)
{
    *x = cos(s->h) * wx + sin(s->h) * wy;
    *y = -sin(s->h) * wx + cos(s->h) * wy;
}

static void to_world(const sim_t *s, double vx, double vy, double *x, double *y)
{
    *x = s->x + cos(s->h) * vx - sin(s->h) * vy;
    *y = s->y + sin(s->h) * vx + cos(s->h) * vy;
}

/* Every beam of the scan cast from the vehicle's pose at s->t, in mm. */
static void sim_cast(sim_t *s, const world_t *w)
{
    static moving_ref_wall_t all[MAX_WALLS + 4u * MAX_BODIES];
    size_t n = 0u;
    for (size_t i = 0u; i < w->walls; i++) {
        all[n++] = w->wall[i];
    }
    for (size_t i = 0u; i < w->bodies; i++) {
        const body_t *b = &w->body[i];
        if (!body_present(b, s->t)) {
            continue;
        }
        double bx;
        double by;
        body_at(b, s->t, &bx, &by);
        moving_ref_box_walls(bx, by, b->heading, b->length, b->width, &all[n]);
        n += 4u;
    }
    double sx;
    double sy;
    to_world(s, fx_q16_16_to_double(s->scan.origin_x), fx_q16_16_to_double(s->scan.origin_y), &sx,
             &sy);
    for (uint16_t k = 0u; k < s->scan.count; k++) {
        const double b = fx_bam32_to_rad(ego_range_bearing(&s->scan, k));
        const double r = moving_ref_cast(all, n, sx, sy, s->h + b, CAST_MAX_M);
        const long mm = lround(r * 1000.0);
        s->range[k] = (uint16_t)((mm > 65535) ? 65535 : mm);
    }
}

/* A line's covariance: var_xy m^2 on x and on y each, var_tt rad^2. */
static ego_cov_t cov_of(double var_xy, double var_tt)
{
    ego_cov_t c;
    memset(&c, 0, sizeof c);
    c.xx = (fx_q2_30_t)lround(var_xy * 1073741824.0);
    c.yy = c.xx;
    c.tt = (fx_q2_30_t)lround(var_tt * 1073741824.0);
    return c;
}

/* sigma 1 mm per axis and 0.1 mrad: a well-measured line. */
static ego_cov_t trusted(void)
{
    return cov_of(1e-6, 1e-8);
}

/* The motion over dt at speed v (m/s, forward) and turn rate omega
 * (rad/s), as the estimator gives it: this scan in the last one's frame. */
static ego_pose_t motion_of(double v, double omega, double dt)
{
    const double th = omega * dt;
    const ego_pose_t p = {fx_bam32_from_rad(th), fx_q16_16_from_double(v * dt * cos(th / 2.0)),
                          fx_q16_16_from_double(v * dt * sin(th / 2.0))};
    return p;
}

static const ego_pose_t STILL = {0u, 0, 0};

/* One line: the vehicle moves by truth (its fixed-point value taken
 * exactly), time by dt_us; the scan is cast and handed over with the
 * motion reported, flags and cov; at most cap objects. */
static uint8_t sim_line_as(sim_t *s, const world_t *w, ego_pose_t truth, ego_pose_t reported,
                           uint32_t dt_us, uint16_t flags, ego_cov_t cov, uint8_t cap)
{
    const double th = (double)(int32_t)truth.theta * (2.0 * PI / 4294967296.0);
    const double mx = fx_q16_16_to_double(truth.x);
    const double my = fx_q16_16_to_double(truth.y);
    s->x += cos(s->h) * mx - sin(s->h) * my;
    s->y += sin(s->h) * mx + cos(s->h) * my;
    s->h += th;
    s->t += (double)dt_us * 1e-6;
    s->time_us += dt_us;
    s->line++;
    sim_cast(s, w);
    memset(&s->out, 0, sizeof s->out);
    s->out.pose = reported;
    s->out.dt_us = dt_us;
    s->out.flags = flags;
    s->out.cov = cov;
    TEST_ASSERT_TRUE(cap <= EGO_MOVING_MAX_OBJECTS);
    s->n = ego_moving_scan(&s->m, &s->scan, s->time_us, &s->out, s->obj, cap);
    TEST_ASSERT_TRUE(s->n <= cap);
    for (uint8_t i = 0u; i < s->n; i++) {
        TEST_ASSERT_TRUE(s->obj[i].id != 0u);
        TEST_ASSERT_TRUE(s->obj[i].points >= EGO_MOVING_MIN_POINTS &&
                         s->obj[i].points <= s->scan.count);
    }
    return s->n;
}

/* A line whose motion is reported exactly. */
static uint8_t sim_line_full(sim_t *s, const world_t *w, ego_pose_t motion, uint32_t dt_us,
                             uint16_t flags, ego_cov_t cov, uint8_t cap)
{
    return sim_line_as(s, w, motion, motion, dt_us, flags, cov, cap);
}

static uint8_t sim_line(sim_t *s, const world_t *w, ego_pose_t motion, uint16_t flags,
                        ego_cov_t cov)
{
    return sim_line_full(s, w, motion, DT_US, flags, cov, EGO_MOVING_MAX_OBJECTS);
}

static ego_cov_t saturated(void)
{
    ego_cov_t c;
    c.xx = c.xy = c.xt = c.yy = c.yt = c.tt = EGO_COV_SATURATED;
    return c;
}

/* A fresh state, the vehicle at the world's origin facing +x, the sensor
 * at (ox, oy) in the vehicle frame with beams values over 180 degrees from
 * -90, and the first line (EGO_FLAG_FIRST, no motion, unknown covariance,
 * as the estimator gives it). */
static void sim_start(sim_t *s, const world_t *w, double ox, double oy, uint16_t beams)
{
    memset(s, 0, sizeof *s);
    ego_moving_reset(&s->m);
    s->time_us = T0_US;
    s->scan.count = beams;
    s->scan.range = s->range;
    s->scan.range_unit_um = 1000u;
    s->scan.origin_x = fx_q16_16_from_double(ox);
    s->scan.origin_y = fx_q16_16_from_double(oy);
    s->scan.first_bearing = EGO_BEARING_Q32(0xC0000000u); /* -90 deg */
    s->scan.bearing_step = (beams == BEAMS) ? UINT64_MAX / 360u : UINT64_MAX / 1440u;
    TEST_ASSERT_TRUE(ego_range_check(&s->scan));
    sim_cast(s, w);
    memset(&s->out, 0, sizeof s->out);
    s->out.flags = EGO_FLAG_FIRST;
    s->out.cov = saturated();
    s->n = ego_moving_scan(&s->m, &s->scan, s->time_us, &s->out, s->obj, EGO_MOVING_MAX_OBJECTS);
    TEST_ASSERT_EQUAL_UINT(0u, s->n);
}

/* The first line after a start whose reference is old enough
 * (EGO_MOVING_REF_MIN_US): no object can be seen before it. */
static unsigned first_eligible_line(void)
{
    return (EGO_MOVING_REF_MIN_US + DT_US - 1u) / DT_US;
}

/* The distance from the object's centre to the body's (vehicle frame). */
static double distance_to_body(const sim_t *s, const body_t *b, const ego_moving_object_t *o)
{
    double bx;
    double by;
    double vx;
    double vy;
    body_at(b, s->t, &bx, &by);
    to_vehicle(s, bx, by, &vx, &vy);
    return hypot(vx - o->cx_cm / 100.0, vy - o->cy_cm / 100.0);
}

/* The present body whose centre is nearest the object's, within max_m
 * (a car's visible sides' box lies within its half diagonal, 2.4 m); -1
 * when none. */
static int body_of(const sim_t *s, const world_t *w, const ego_moving_object_t *o, double max_m)
{
    int best = -1;
    double best_d = max_m;
    for (size_t i = 0u; i < w->bodies; i++) {
        if (!body_present(&w->body[i], s->t)) {
            continue;
        }
        const double d = distance_to_body(s, &w->body[i], o);
        if (d <= best_d) {
            best_d = d;
            best = (int)i;
        }
    }
    return best;
}

/* The object of the line on the body, NULL when none. */
static const ego_moving_object_t *object_on(const sim_t *s, const world_t *w, size_t body)
{
    for (uint8_t i = 0u; i < s->n; i++) {
        if (body_of(s, w, &s->obj[i], 3.0) == (int)body) {
            return &s->obj[i];
        }
    }
    return NULL;
}

/* --- the box against its oracle ------------------------------------------- */

/* The box is computed in Q16.16 from the same ranges and bearings and
 * given in whole cm: rounding to cm is 0.5 cm, and Q16.16 points (15 um),
 * Q2.30 sines (1e-9) and the Q2.30 chord direction (1e-5 rad over a chord
 * of 0.1 m or more: 0.2 mm over 16 m) add under 1 mm; the oracle's value
 * rounded to cm then differs by at most 1 cm. */
#define BOX_TOL_CM 1

static long cm(double m)
{
    return lround(m * 100.0);
}

/* The oracle's box of the scan's segment with the object's point count
 * whose centre is nearest the object's: each field within BOX_TOL_CM.
 * Returns that segment's first beam. */
static uint16_t check_box(const sim_t *s, const ego_moving_object_t *o)
{
    static uint16_t from[EGO_MAX_BEAMS];
    static uint16_t to[EGO_MAX_BEAMS];
    const size_t n = moving_ref_segments(&s->scan, from, to, EGO_MAX_BEAMS);
    moving_ref_box_t best = {0.0, 0.0, 0.0, 0.0};
    double best_d = INFINITY;
    uint16_t best_from = 0u;
    for (size_t i = 0u; i < n; i++) {
        if ((uint32_t)to[i] - from[i] != o->points) {
            continue;
        }
        moving_ref_box_t b;
        moving_ref_chord_box(&s->scan, from[i], to[i], &b);
        const double d = hypot(b.cx - o->cx_cm / 100.0, b.cy - o->cy_cm / 100.0);
        if (d < best_d) {
            best_d = d;
            best = b;
            best_from = from[i];
        }
    }
    char msg[200];
    snprintf(msg, sizeof msg,
             "t %.3f s: object %u at (%d, %d) cm, %u points: no segment of as many", s->t,
             (unsigned)o->id, o->cx_cm, o->cy_cm, (unsigned)o->points);
    TEST_ASSERT_TRUE_MESSAGE(isfinite(best_d), msg);
    snprintf(msg, sizeof msg,
             "t %.3f s: object %u (%d, %d) %u x %u cm: oracle (%ld, %ld) %ld x %ld cm", s->t,
             (unsigned)o->id, o->cx_cm, o->cy_cm, (unsigned)o->length_cm, (unsigned)o->width_cm,
             cm(best.cx), cm(best.cy), cm(best.length), cm(best.width));
    TEST_ASSERT_INT_WITHIN_MESSAGE(BOX_TOL_CM, cm(best.cx), o->cx_cm, msg);
    TEST_ASSERT_INT_WITHIN_MESSAGE(BOX_TOL_CM, cm(best.cy), o->cy_cm, msg);
    TEST_ASSERT_INT_WITHIN_MESSAGE(BOX_TOL_CM, cm(best.length), o->length_cm, msg);
    TEST_ASSERT_INT_WITHIN_MESSAGE(BOX_TOL_CM, cm(best.width), o->width_cm, msg);
    return best_from;
}

/* The scan's segment (at least EGO_MOVING_MIN_POINTS points) whose box
 * centre is nearest the body's centre, within 3 m; false when none. */
static bool segment_of_body(const sim_t *s, const body_t *b, uint16_t *seg_from, uint16_t *seg_to)
{
    static uint16_t from[EGO_MAX_BEAMS];
    static uint16_t to[EGO_MAX_BEAMS];
    const size_t n = moving_ref_segments(&s->scan, from, to, EGO_MAX_BEAMS);
    double bx;
    double by;
    double vx;
    double vy;
    body_at(b, s->t, &bx, &by);
    to_vehicle(s, bx, by, &vx, &vy);
    double best_d = 3.0;
    bool found = false;
    for (size_t i = 0u; i < n; i++) {
        if ((uint32_t)to[i] - from[i] < EGO_MOVING_MIN_POINTS) {
            continue;
        }
        moving_ref_box_t box;
        moving_ref_chord_box(&s->scan, from[i], to[i], &box);
        const double d = hypot(box.cx - vx, box.cy - vy);
        if (d < best_d) {
            best_d = d;
            *seg_from = from[i];
            *seg_to = to[i];
            found = true;
        }
    }
    return found;
}

/* The oracle on its own, on a cluster whose box is known: three points of
 * a flat V (chord from (10, 0) to (10, 2), the middle point 0.5 m beyond
 * it at (10.5, 1)), placed through a bearing table. */
static void test_moving_ref_chord_box_of_known_points(void)
{
    static const double px[3] = {10.0, 10.5, 10.0};
    static const double py[3] = {0.0, 1.0, 2.0};
    fx_bam32_t bearing[3];
    uint16_t range[3];
    for (unsigned i = 0u; i < 3u; i++) {
        bearing[i] = fx_bam32_from_rad(atan2(py[i], px[i]));
        range[i] = (uint16_t)lround(hypot(px[i], py[i]) * 1000.0);
    }
    const ego_range_scan_t scan = {3u, range, 1000u, 0, 0, 0u, 0u, bearing, 0u, 0u, 0u};
    TEST_ASSERT_TRUE(ego_range_check(&scan));
    moving_ref_box_t b;
    moving_ref_chord_box(&scan, 0u, 3u, &b);
    /* Along the chord (the y axis) 0..2 m, across it (its left is -x)
     * -0.5..0 m: centre (10.25, 1), 2 m x 0.5 m (to the mm rounding). */
    TEST_ASSERT_INT_WITHIN(1, 1025, cm(b.cx));
    TEST_ASSERT_INT_WITHIN(1, 100, cm(b.cy));
    TEST_ASSERT_INT_WITHIN(1, 200, cm(b.length));
    TEST_ASSERT_INT_WITHIN(1, 50, cm(b.width));
    uint16_t from[4];
    uint16_t to[4];
    TEST_ASSERT_EQUAL_UINT(1u, moving_ref_segments(&scan, from, to, 4u));
    TEST_ASSERT_EQUAL_UINT(0u, from[0]);
    TEST_ASSERT_EQUAL_UINT(3u, to[0]);
    /* Both ends are the field's edges: not the body's own (cut). */
    moving_ref_marks_t m;
    moving_ref_marks(&scan, 0u, 3u, &m);
    TEST_ASSERT_FALSE(m.uncut[1]);
    TEST_ASSERT_FALSE(m.uncut[2]);
}

/* --- following one body: box, velocity oracle, truth ----------------------- */

/* The velocity against its oracle, in cm/s: the output's rounding (0.5)
 * against the oracle's rounded value (0.5); Q16.16 marks (15 um) and the
 * anchor carried through the chained Q16.16 motions (1.5e-5 m a line over
 * some 23 lines: 0.4 mm) over an age of 0.1 s or more: 0.4 cm/s; the
 * velocity's own rotation per line and the quarter steps' truncation add
 * under 0.1 cm/s. */
#define VEL_ORACLE_TOL_CMS 2

typedef enum {
    TRUTH_NONE,  /* the velocity against the oracle only */
    TRUTH_ALONG, /* and its component along the body's path against the truth */
    TRUTH_FULL   /* and the whole vector against the truth */
} truth_t;

typedef struct {
    size_t body;
    bool in_view_from_start; /* so confirmed at the earliest line */
    truth_t truth;
    double truth_tol; /* m/s */
    unsigned reports;
    unsigned first_line;
    double first_s;
    uint16_t id;
    unsigned id_changes;
    unsigned others;    /* objects on no body of the world */
    double worst_truth; /* m/s */
    unsigned truth_checked;
    unsigned oracle_checked;
    unsigned both_cut; /* reports whose two ends were cut */
    moving_ref_velocity_t vel;
    moving_ref_marks_t hist[3]; /* the body's marks on the last three lines, world frame */
    bool hist_ok[3];
} follow_t;

static void follow_init(follow_t *f, size_t body, truth_t truth, double tol)
{
    memset(f, 0, sizeof *f);
    f->body = body;
    f->in_view_from_start = true;
    f->truth = truth;
    f->truth_tol = tol;
}

/* The truth is compared from 0.3 s after the first report on: by then the
 * first measurement (which sets the velocity outright, over the shortest
 * window, 0.1 s) has been followed by a whole window of quarter steps.
 * Each test gives its tolerance's reason. */
#define VEL_SETTLE_S 0.3

static void marks_to_world(const sim_t *s, moving_ref_marks_t *m)
{
    for (unsigned i = 0u; i < 3u; i++) {
        double x;
        double y;
        to_world(s, m->x[i], m->y[i], &x, &y);
        m->x[i] = x;
        m->y[i] = y;
    }
}

/* One line of a run that started with sim_start and goes on with lines
 * DT_US apart, all measured: checks the followed body's object (its box
 * against the oracle's box of the body's segment, its velocity against
 * the oracle's rule fed with that segment's marks on every line it is
 * reported, and against the truth). The oracle's track starts two lines
 * before the first report (a track is confirmed on its third sighting;
 * the body is a moving cluster on consecutive lines in these scenes, and
 * for one in view from the start that is asserted: confirmed on the
 * third line with an old enough reference). */
static void follow_line(follow_t *f, const sim_t *s, const world_t *w)
{
    const body_t *b = &w->body[f->body];
    const unsigned slot = s->line % 3u;
    uint16_t seg_from = 0u;
    uint16_t seg_to = 0u;
    f->hist_ok[slot] = segment_of_body(s, b, &seg_from, &seg_to);
    if (f->hist_ok[slot]) {
        moving_ref_marks(&s->scan, seg_from, seg_to, &f->hist[slot]);
        marks_to_world(s, &f->hist[slot]);
    }
    if (f->reports > 0u) {
        moving_ref_velocity_age(&f->vel, DT_US);
    }
    for (uint8_t i = 0u; i < s->n; i++) {
        const ego_moving_object_t *o = &s->obj[i];
        const int on = body_of(s, w, o, 3.0);
        if (on < 0) {
            f->others++;
        }
        if (on != (int)f->body) {
            continue;
        }
        char msg[160];
        snprintf(msg, sizeof msg, "t %.3f s: the body's object is not its segment", s->t);
        TEST_ASSERT_TRUE_MESSAGE(f->hist_ok[slot] && check_box(s, o) == seg_from, msg);
        if (f->reports == 0u) {
            f->first_line = s->line;
            f->first_s = s->t;
            f->id = o->id;
            const unsigned l2 = (s->line + 1u) % 3u;
            const unsigned l1 = (s->line + 2u) % 3u;
            if (f->in_view_from_start) {
                TEST_ASSERT_EQUAL_UINT_MESSAGE(first_eligible_line() + 2u, s->line,
                                               "not confirmed at the earliest line");
            }
            TEST_ASSERT_TRUE(f->hist_ok[l2] && f->hist_ok[l1]);
            moving_ref_velocity_start(&f->vel, &f->hist[l2]);
            moving_ref_velocity_age(&f->vel, DT_US);
            moving_ref_velocity_seen(&f->vel, &f->hist[l1]);
            moving_ref_velocity_age(&f->vel, DT_US);
        }
        moving_ref_velocity_seen(&f->vel, &f->hist[slot]);
        f->reports++;
        f->id_changes += (o->id != f->id) ? 1u : 0u;
        f->both_cut += (!f->hist[slot].uncut[1] && !f->hist[slot].uncut[2]) ? 1u : 0u;
        snprintf(msg, sizeof msg, "t %.3f s: velocity known %d", s->t, (int)f->vel.known);
        TEST_ASSERT_EQUAL_INT_MESSAGE(f->vel.known, o->vx_cms != EGO_MOVING_UNKNOWN, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(f->vel.known, o->vy_cms != EGO_MOVING_UNKNOWN, msg);
        if (!f->vel.known) {
            continue;
        }
        double ox;
        double oy;
        vec_to_vehicle(s, f->vel.vx, f->vel.vy, &ox, &oy);
        snprintf(msg, sizeof msg, "t %.3f s: velocity (%d, %d) cm/s, oracle (%.1f, %.1f)", s->t,
                 o->vx_cms, o->vy_cms, ox * 100.0, oy * 100.0);
        TEST_ASSERT_INT_WITHIN_MESSAGE(VEL_ORACLE_TOL_CMS, cm(ox), o->vx_cms, msg);
        TEST_ASSERT_INT_WITHIN_MESSAGE(VEL_ORACLE_TOL_CMS, cm(oy), o->vy_cms, msg);
        f->oracle_checked++;
        if (f->truth == TRUTH_NONE || s->t < f->first_s + VEL_SETTLE_S) {
            continue;
        }
        double tx;
        double ty;
        vec_to_vehicle(s, b->vx, b->vy, &tx, &ty);
        const double ex = o->vx_cms / 100.0 - tx;
        const double ey = o->vy_cms / 100.0 - ty;
        double e = hypot(ex, ey);
        if (f->truth == TRUTH_ALONG) {
            const double speed = hypot(tx, ty);
            e = fabs((ex * tx + ey * ty) / speed);
        }
        f->worst_truth = fmax(f->worst_truth, e);
        f->truth_checked++;
        snprintf(msg, sizeof msg, "t %.3f s: velocity (%d, %d) cm/s, truth (%.1f, %.1f)", s->t,
                 o->vx_cms, o->vy_cms, tx * 100.0, ty * 100.0);
        TEST_ASSERT_TRUE_MESSAGE(e <= f->truth_tol, msg);
    }
}

/* --- 1. a car's box and velocity ------------------------------------------ */

/* Vehicle standing; a car 12 m ahead crossing right to left at 10 m/s, a
 * wall 40 m away behind it (beyond EGO_MOVING_MAX_RANGE: never a segment,
 * but a return beyond the car's ends).
 *
 * Velocity along the path within 0.6 m/s once the track is 0.3 s old: an
 * end is the last beam on the car, up to one beam spacing (1 deg: 0.21 m
 * at 12 m) short of its corner along the side, a sawtooth of period 0.02 s
 * at 10 m/s; one measurement over the 0.1-0.3 s window is off by at most
 * 0.21 m over its age (1 m/s at 0.2 s), the two ends' sawtooths are out of
 * phase and the quarter steps average four or more windows. Across the
 * path no truth bound is asserted: there an end jumps between the side and
 * a front or back face seen edge-on (up to the car's 1.8 m width within one
 * beam), which only the oracle follows. */
static void test_ego_moving_crossing_car_box_and_velocity(void)
{
    world_clear(&g_world);
    const size_t car = world_car(&g_world, 12.0, -7.0, 0.0, 10.0);
    world_wall(&g_world, 40.0, -60.0, 40.0, 60.0);
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    follow_t f;
    follow_init(&f, car, TRUTH_ALONG, 0.6);
    for (unsigned k = 0u; k < 80u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        follow_line(&f, &g_sim, &g_world);
    }
    /* Reported on every line from its confirmation on (it is always in
     * view and always moving), as one object with one id. */
    TEST_ASSERT_EQUAL_UINT(80u - f.first_line + 1u, f.reports);
    TEST_ASSERT_EQUAL_UINT(0u, f.others);
    TEST_ASSERT_EQUAL_UINT(0u, f.id_changes);
    TEST_ASSERT_TRUE(f.truth_checked > 30u);
}

/* The vehicle drives at 8 m/s turning at 0.05 rad/s, its sensor 1.2 m
 * ahead of its origin and 0.1 m left; a car in the next lane overtakes at
 * 14 m/s, coming into the field from beside the vehicle (for its first
 * 0.6 s its front end is the field's last beam: cut). At 181 values the
 * car's far end, once ahead, is the last beam on its side, seen ever more
 * edge-on as it pulls away: that end slides back along the side (the box
 * shortens from 4.5 to 3 m within 0.4 s), so the velocity only follows
 * the oracle. At 720 values (0.25 deg) the side is sampled every 3-5 cm
 * and the end stays near its corner: within 0.6 m/s of the truth once
 * 0.3 s old (the sawtooth of the crossing car's, a quarter of it, plus
 * what remains of the slide and of the centre's slide while cut). */
static void test_ego_moving_overtaking_car_from_moving_vehicle(void)
{
    static const uint16_t beams[2] = {BEAMS, FINE_BEAMS};
    for (unsigned r = 0u; r < 2u; r++) {
        world_clear(&g_world);
        const size_t car = world_car(&g_world, 0.0, 3.5, 14.0, 0.0);
        sim_start(&g_sim, &g_world, 1.2, 0.1, beams[r]);
        follow_t f;
        follow_init(&f, car, (beams[r] == FINE_BEAMS) ? TRUTH_FULL : TRUTH_NONE, 0.6);
        for (unsigned k = 0u; k < 120u; k++) {
            sim_line(&g_sim, &g_world, motion_of(8.0, 0.05, DT_S), 0u, trusted());
            follow_line(&f, &g_sim, &g_world);
        }
        TEST_ASSERT_EQUAL_UINT(120u - f.first_line + 1u, f.reports);
        TEST_ASSERT_EQUAL_UINT(0u, f.others);
        TEST_ASSERT_EQUAL_UINT(0u, f.id_changes);
        TEST_ASSERT_TRUE(f.oracle_checked > 80u);
        TEST_ASSERT_TRUE(beams[r] == BEAMS || f.truth_checked > 60u);
    }
}

/* A car crossing 12 m ahead at 10 m/s behind a fence 8 m ahead with a
 * 2 m opening: seen through it (no return beyond), its ends are cut by
 * the fence's edges (the beams outside its segment are nearer) while it
 * fills the opening (2.8 m wide at the car: for some 0.17 s), so its
 * velocity comes from its box centre then, from its own ends on the way
 * in and out: the oracle's rule, followed to its rounding. */
static void test_ego_moving_car_through_a_gap_follows_the_rule(void)
{
    world_clear(&g_world);
    world_wall(&g_world, 8.0, -20.0, 8.0, -1.0);
    world_wall(&g_world, 8.0, 1.0, 8.0, 20.0);
    const size_t car = world_car(&g_world, 12.0, -8.0, 0.0, 10.0);
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    follow_t f;
    follow_init(&f, car, TRUTH_NONE, 0.0);
    f.in_view_from_start = false;
    for (unsigned k = 0u; k < 110u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        follow_line(&f, &g_sim, &g_world);
    }
    TEST_ASSERT_EQUAL_UINT(0u, f.others);
    TEST_ASSERT_EQUAL_UINT(0u, f.id_changes);
    TEST_ASSERT_TRUE(f.oracle_checked >= 12u);
    TEST_ASSERT_TRUE(f.both_cut >= 6u);
}

/* --- 2. a static world ------------------------------------------------------ */

/* A street: building fronts with doorways on both sides, posts on the
 * kerbs, parked cars, a wall across its end. */
static void build_street(world_t *w)
{
    world_clear(w);
    for (int i = 0; i < 10; i++) {
        const double xl = -20.0 + 14.0 * i;
        world_wall(w, xl, 7.0, xl + 12.0, 7.0);
        const double xr = -20.0 + 18.0 * i;
        const double yr = (i % 2 == 0) ? -7.0 : -7.6;
        world_wall(w, xr, yr, xr + 15.0, yr);
        world_wall(w, xr + 15.0, yr, xr + 15.0, -9.0);
    }
    world_wall(w, 75.0, -12.0, 75.0, 12.0);
    for (int i = 0; i < 8; i++) {
        world_body(w, -5.0 + 9.0 * i, (i % 2 == 0) ? 5.2 : -5.2, 0.0, 0.3, 0.3, 0.0, 0.0);
    }
    world_body(w, 18.0, -5.6, 0.0, 4.5, 1.8, 0.0, 0.0);
    world_body(w, 33.0, 5.6, 0.1, 4.5, 1.8, 0.0, 0.0);
    world_body(w, 52.0, -5.5, 0.0, 6.0, 2.2, 0.0, 0.0);
}

/* With the ego-motion exact, no point of a static world is evidence:
 * nothing is ever reported, driving (weaving at up to 0.3 rad/s, so the
 * posts hide and reveal the fronts behind them), then standing, then
 * driving on; turning in place, driving, turning at speed; and standing
 * from the start. */
static void test_ego_moving_static_world_reports_nothing(void)
{
    build_street(&g_world);
    sim_start(&g_sim, &g_world, 1.0, 0.0, BEAMS);
    for (unsigned k = 0u; k < 375u; k++) {
        const double t = g_sim.t;
        const bool standing = t >= 2.5 && t < 3.5;
        const ego_pose_t motion =
            standing ? STILL : motion_of(10.0, 0.3 * sin(2.0 * PI * t / 2.0), DT_S);
        char msg[80];
        snprintf(msg, sizeof msg, "t %.3f s", g_sim.t + DT_S);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, sim_line(&g_sim, &g_world, motion, 0u, trusted()), msg);
    }
    TEST_ASSERT_TRUE(g_sim.x > 35.0); /* it did drive past the posts */
    /* Turning in place by 0.5 rad, then driving straight, then turning at
     * speed the other way: motions that do not commute, so the references'
     * chained poses must compose in order. */
    sim_start(&g_sim, &g_world, 1.0, 0.0, BEAMS);
    for (unsigned k = 0u; k < 150u; k++) {
        const ego_pose_t motion = (k < 19u)   ? motion_of(0.0, 2.0, DT_S)
                                  : (k < 60u) ? motion_of(10.0, 0.0, DT_S)
                                              : motion_of(6.0, -1.0, DT_S);
        char msg[80];
        snprintf(msg, sizeof msg, "t %.3f s", g_sim.t + DT_S);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, sim_line(&g_sim, &g_world, motion, 0u, trusted()), msg);
    }
    sim_start(&g_sim, &g_world, 1.0, 0.0, BEAMS);
    for (unsigned k = 0u; k < 150u; k++) {
        TEST_ASSERT_EQUAL_UINT(0u, sim_line(&g_sim, &g_world, STILL, 0u, trusted()));
    }
}

/* --- 3. the reveal rule --------------------------------------------------- */

/* A walker 0.5 m square crossing at 1.5 m/s 2.5 m in front of an 8 m wall
 * (5 m ahead), vehicle standing. Against the 0.2-0.3 s old reference it
 * has moved 0.3-0.45 m: 7-10 degrees, so 7-10 beams (0.6-0.9 m) of wall
 * are revealed where the reference saw the walker 2.5 m in front: "left
 * behind" evidence (at least EGO_MOVING_EVIDENCE_MIN of the wall's
 * segment) but for the reveal exception (the walker's points lie within 8
 * beams of each vanished point, nearer than half its 2.5 m). So the
 * walker is found and the wall never is. Control: when the walker
 * vanishes (nothing near its last place) the same revealed wall is
 * evidence, and the wall is reported. */
static void test_ego_moving_walker_before_wall_reveals_no_body(void)
{
    for (unsigned vanish = 0u; vanish < 2u; vanish++) {
        world_clear(&g_world);
        world_wall(&g_world, 5.0, -4.0, 5.0, 4.0);
        const size_t walker = world_walker(&g_world, 2.5, -1.5, 0.0, 1.5);
        if (vanish != 0u) {
            g_world.body[walker].t_off = 1.0;
        }
        sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
        unsigned walker_reports = 0u;
        unsigned wall_reports = 0u;
        for (unsigned k = 0u; k < 150u; k++) {
            sim_line(&g_sim, &g_world, STILL, 0u, trusted());
            for (uint8_t i = 0u; i < g_sim.n; i++) {
                const ego_moving_object_t *o = &g_sim.obj[i];
                check_box(&g_sim, o);
                if (body_of(&g_sim, &g_world, o, 0.6) == (int)walker) {
                    walker_reports++;
                    continue;
                }
                char msg[120];
                snprintf(msg, sizeof msg, "t %.3f s: object at (%d, %d) cm, %u x %u cm", g_sim.t,
                         o->cx_cm, o->cy_cm, (unsigned)o->length_cm, (unsigned)o->width_cm);
                /* Anything else is the wall (its box lies on x = 5 m). */
                TEST_ASSERT_INT_WITHIN_MESSAGE(10, 500, o->cx_cm, msg);
                TEST_ASSERT_TRUE_MESSAGE(vanish != 0u && g_sim.t >= 1.0, msg);
                wall_reports++;
            }
        }
        if (vanish == 0u) {
            /* From its confirmation (0.24 s) to the end (2 s), on most
             * lines: a small body gives evidence only with its front. */
            TEST_ASSERT_TRUE(walker_reports >= 100u);
        } else {
            TEST_ASSERT_TRUE(walker_reports >= 40u);
            TEST_ASSERT_TRUE(wall_reports >= 1u);
        }
    }
}

/* --- 4. restarts ------------------------------------------------------------ */

/* The restart scene, vehicle standing: walker W1 (right of centre, gone
 * at 0.45 s) takes the first track, walker W2 (left, the whole run) and a
 * car crossing 12 m ahead at 10 m/s (from 0.5 s) later ones. Runs 90
 * lines (1.2 s) and returns the car's and W2's ids then: the car's is not
 * among the first two. */
typedef struct {
    size_t car;
    size_t w2;
    uint16_t car_id;
    uint16_t w2_id;
} restart_scene_t;

static void restart_scene(restart_scene_t *r)
{
    world_clear(&g_world);
    const size_t w1 = world_walker(&g_world, 6.0, 2.0, 0.0, 1.5);
    g_world.body[w1].t_off = 0.45;
    r->w2 = world_walker(&g_world, 5.0, 6.0, 0.0, 1.5);
    r->car = world_car(&g_world, 12.0, -22.0, 0.0, 10.0);
    g_world.body[r->car].t_on = 0.5;
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    bool w1_seen = false;
    for (unsigned k = 0u; k < 90u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        const ego_moving_object_t *o = object_on(&g_sim, &g_world, w1);
        w1_seen = w1_seen || o != NULL;
    }
    const ego_moving_object_t *car = object_on(&g_sim, &g_world, r->car);
    const ego_moving_object_t *w2 = object_on(&g_sim, &g_world, r->w2);
    TEST_ASSERT_TRUE(w1_seen && car != NULL && w2 != NULL);
    r->car_id = car->id;
    r->w2_id = w2->id;
    TEST_ASSERT_TRUE(r->car_id > 2u);
}

/* Lines within this time of a restart report nothing new: the reference
 * must be EGO_MOVING_REF_MIN_US old and a track is confirmed on its third
 * sighting. */
#define QUIET_US (EGO_MOVING_REF_MIN_US + 2u * DT_US)

typedef enum {
    LINE_FLAGS,  /* flags on a trusted line */
    LINE_COV_XX, /* flags 0, cov.xx saturated */
    LINE_COV_YY,
    LINE_COV_TT,
    LINE_DT_ZERO, /* the same time again */
    LINE_DT_LONG, /* EGO_MOVING_MAX_DT_US + 1 */
    LINE_DT_MAX   /* EGO_MOVING_MAX_DT_US exactly: no restart */
} line_kind_t;

/* The scene, then the special line; returns its count. */
static uint8_t restart_line(restart_scene_t *r, line_kind_t kind, uint16_t flags)
{
    restart_scene(r);
    ego_cov_t cov = trusted();
    uint32_t dt = DT_US;
    switch (kind) {
    case LINE_COV_XX:
        cov.xx = EGO_COV_SATURATED;
        break;
    case LINE_COV_YY:
        cov.yy = EGO_COV_SATURATED;
        break;
    case LINE_COV_TT:
        cov.tt = EGO_COV_SATURATED;
        break;
    case LINE_DT_ZERO:
        dt = 0u;
        break;
    case LINE_DT_LONG:
        dt = EGO_MOVING_MAX_DT_US + 1u;
        break;
    case LINE_DT_MAX:
        dt = EGO_MOVING_MAX_DT_US;
        break;
    case LINE_FLAGS:
    default:
        break;
    }
    return sim_line_full(&g_sim, &g_world, STILL, dt, flags, cov, EGO_MOVING_MAX_OBJECTS);
}

/* Everything starts over (ego_moving.h): a line without a measured motion
 * (first, predicted, recovering, recovered), an interval of 0 or over
 * EGO_MOVING_MAX_DT_US. Nothing on that line nor
 * within QUIET_US after it (no track survives to be held); then the car
 * and W2 come back on fresh tracks whose ids start from 1 again. */
static void assert_everything_starts_over(line_kind_t kind, uint16_t flags, const char *what)
{
    restart_scene_t r;
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, restart_line(&r, kind, flags), what);
    const uint32_t t0 = g_sim.time_us;
    bool car_back = false;
    for (unsigned k = 0u; k < 75u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        char msg[120];
        snprintf(msg, sizeof msg, "%s: %u us after", what, (unsigned)(g_sim.time_us - t0));
        if (g_sim.time_us - t0 < QUIET_US) {
            TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, g_sim.n, msg);
        }
        for (uint8_t i = 0u; i < g_sim.n; i++) {
            TEST_ASSERT_TRUE_MESSAGE(g_sim.obj[i].id <= 2u, msg);
        }
        car_back = car_back || object_on(&g_sim, &g_world, r.car) != NULL;
    }
    TEST_ASSERT_TRUE_MESSAGE(car_back, what);
}

static void test_ego_moving_unmeasured_line_starts_everything_over(void)
{
    assert_everything_starts_over(LINE_FLAGS, EGO_FLAG_FIRST, "first");
    assert_everything_starts_over(LINE_FLAGS, EGO_FLAG_PREDICTED, "predicted");
    assert_everything_starts_over(LINE_FLAGS, EGO_FLAG_RECOVERING, "recovering");
    assert_everything_starts_over(LINE_FLAGS, EGO_FLAG_RECOVERED, "recovered");
    assert_everything_starts_over(LINE_FLAGS, EGO_FLAG_PREDICTED | EGO_FLAG_TOO_FEW_POINTS,
                                  "predicted, too few points");
}

static void test_ego_moving_bad_interval_starts_everything_over(void)
{
    assert_everything_starts_over(LINE_DT_ZERO, 0u, "interval 0");
    assert_everything_starts_over(LINE_DT_LONG, 0u, "interval over the maximum");
}

/* An interval of exactly EGO_MOVING_MAX_DT_US is no restart: the tracks
 * were predicted over it and the car and W2 are reported on that very
 * line under their old ids. */
static void test_ego_moving_longest_interval_keeps_tracks(void)
{
    restart_scene_t r;
    restart_line(&r, LINE_DT_MAX, 0u);
    const ego_moving_object_t *car = object_on(&g_sim, &g_world, r.car);
    const ego_moving_object_t *w2 = object_on(&g_sim, &g_world, r.w2);
    TEST_ASSERT_NOT_NULL(car);
    TEST_ASSERT_NOT_NULL(w2);
    TEST_ASSERT_EQUAL_UINT(r.car_id, car->id);
    TEST_ASSERT_EQUAL_UINT(r.w2_id, w2->id);
}

/* A line whose motion has no covariance to trust (suspect, on objects, a
 * saturated variance, an aperture line while standing) starts the
 * references over; the tracks go on. W2 (a walker: never
 * held) is not reported within QUIET_US, loses its track (missed more
 * than EGO_MOVING_MAX_MISSES lines) and comes back under a new id, after
 * the ones already given (ids were not restarted). The car is a vehicle
 * whose velocity came from its ends: the hold keeps it on its own
 * segment, under its id, on every line. */
static void assert_references_start_over(line_kind_t kind, uint16_t flags, const char *what)
{
    restart_scene_t r;
    restart_line(&r, kind, flags);
    const uint32_t t0 = g_sim.time_us;
    const ego_moving_object_t *car = object_on(&g_sim, &g_world, r.car);
    TEST_ASSERT_NOT_NULL_MESSAGE(car, what);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(r.car_id, car->id, what);
    TEST_ASSERT_NULL_MESSAGE(object_on(&g_sim, &g_world, r.w2), what);
    uint16_t w2_new = 0u;
    for (unsigned k = 0u; k < 60u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        char msg[120];
        snprintf(msg, sizeof msg, "%s: %u us after", what, (unsigned)(g_sim.time_us - t0));
        car = object_on(&g_sim, &g_world, r.car);
        TEST_ASSERT_NOT_NULL_MESSAGE(car, msg);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(r.car_id, car->id, msg);
        const ego_moving_object_t *w2 = object_on(&g_sim, &g_world, r.w2);
        if (g_sim.time_us - t0 < QUIET_US) {
            TEST_ASSERT_NULL_MESSAGE(w2, msg);
        } else if (w2 != NULL && w2_new == 0u) {
            w2_new = w2->id;
        }
    }
    TEST_ASSERT_TRUE_MESSAGE(w2_new > r.car_id, what);
}

static void test_ego_moving_untrusted_motion_restarts_references_only(void)
{
    assert_references_start_over(LINE_FLAGS, EGO_FLAG_SUSPECT, "suspect");
    assert_references_start_over(LINE_FLAGS, EGO_FLAG_ON_OBJECTS, "on objects");
    /* Standing (below EGO_MOVING_START_SPEED) along a corridor: the speed
     * along it is the prediction's, and the vehicle may be starting off. */
    assert_references_start_over(LINE_FLAGS, EGO_FLAG_APERTURE, "aperture while standing");
}

static void test_ego_moving_saturated_variance_restarts_references_only(void)
{
    assert_references_start_over(LINE_COV_XX, 0u, "cov.xx saturated");
    assert_references_start_over(LINE_COV_YY, 0u, "cov.yy saturated");
    assert_references_start_over(LINE_COV_TT, 0u, "cov.tt saturated");
}

/* --- tracks: misses, slots, the hold ----------------------------------------- */

/* A car crossing 12 m ahead at 10 m/s that vanishes for `gap` lines
 * (nothing behind it: no segment there) from line 45 on: body 0 before,
 * body GAP_CAR_BACK after. Returns the car's id before the gap and sets
 * *after to its id on the first line it is back (0: not reported then). */
#define GAP_CAR_BACK 1u

static uint16_t car_with_gap(unsigned gap, uint16_t *after)
{
    world_clear(&g_world);
    const size_t a = world_car(&g_world, 12.0, -12.0, 0.0, 10.0);
    const size_t b = world_car(&g_world, 12.0, -12.0, 0.0, 10.0);
    TEST_ASSERT_EQUAL_UINT(GAP_CAR_BACK, b);
    const double t_gap = 45.0 * DT_S - DT_S / 2.0;
    g_world.body[a].t_off = t_gap;
    g_world.body[b].t_on = t_gap + gap * DT_S;
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    uint16_t before = 0u;
    *after = 0u;
    for (unsigned k = 1u; k <= 45u + gap; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        if (k < 45u) {
            const ego_moving_object_t *o = object_on(&g_sim, &g_world, a);
            TEST_ASSERT_TRUE(k < first_eligible_line() + 2u || o != NULL);
            before = (o != NULL) ? o->id : before;
        } else if (k < 45u + gap) {
            TEST_ASSERT_EQUAL_UINT(0u, g_sim.n);
        } else {
            const ego_moving_object_t *o = object_on(&g_sim, &g_world, b);
            *after = (o != NULL) ? o->id : 0u;
        }
    }
    return before;
}

/* A track missed EGO_MOVING_MAX_MISSES (8) lines in a row is dropped:
 * after 7 lines out of view the car is reported at once under its id;
 * after 9 its track is gone (a new one is confirmed on its third
 * sighting: nothing on the first line back, then a new id). Exactly 8 is
 * left out: the code keeps the track through 8 misses (drops it on the
 * 9th), which "missed 8 scans in a row is dropped" may or may not mean. */
static void test_ego_moving_track_survives_short_gaps_only(void)
{
    uint16_t after = 0u;
    const uint16_t id = car_with_gap(7u, &after);
    TEST_ASSERT_TRUE(id != 0u);
    TEST_ASSERT_EQUAL_UINT(id, after);
    const uint16_t id9 = car_with_gap(EGO_MOVING_MAX_MISSES + 1u, &after);
    TEST_ASSERT_EQUAL_UINT(id, id9);
    TEST_ASSERT_EQUAL_UINT(0u, after);
    const ego_moving_object_t *o = NULL;
    for (unsigned k = 0u; k < 2u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        o = object_on(&g_sim, &g_world, GAP_CAR_BACK);
    }
    TEST_ASSERT_NOT_NULL(o);
    TEST_ASSERT_TRUE(o->id != id);
}

/* A cluster that finds no free track takes the slot of the track missed
 * longest; it is dropped only when every track was seen. Eight walkers
 * hold all the tracks (all reported on line 44); on line 45 they are
 * gone and a ninth appears far from all of them: no track was seen, so it
 * takes a slot on its first line and is confirmed on its third (line 47). */
static void test_ego_moving_new_body_takes_a_missed_slot(void)
{
    world_clear(&g_world);
    const double t_swap = 45.0 * DT_S - DT_S / 2.0;
    for (unsigned i = 0u; i < EGO_MOVING_TRACKS; i++) {
        const double b = (-75.0 + 10.0 * i) * PI / 180.0;
        const double r = (i % 2u == 0u) ? 6.0 : 7.5;
        const size_t w = world_body(&g_world, r * cos(b), r * sin(b), b + PI / 2.0, 0.6, 0.6,
                                    -2.0 * sin(b), 2.0 * cos(b));
        g_world.body[w].t_off = t_swap;
    }
    const size_t ninth = world_walker(&g_world, 5.0, 4.0, 0.0, 1.5);
    g_world.body[ninth].t_on = t_swap;
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    unsigned first = 0u;
    for (unsigned k = 1u; k <= 60u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        if (k == 44u) {
            TEST_ASSERT_EQUAL_UINT(EGO_MOVING_TRACKS, g_sim.n);
        }
        if (first == 0u && object_on(&g_sim, &g_world, ninth) != NULL) {
            first = k;
        }
    }
    TEST_ASSERT_EQUAL_UINT(47u, first);
}

/* The hold lasts at most EGO_MOVING_MAX_HELD lines in a row: once the car
 * is confirmed with a velocity from its ends, every line is suspect (the
 * references start over each time: no evidence at all). The car is held
 * on its own segment, reported under its id, on exactly 150 lines. */
static void test_ego_moving_hold_lasts_at_most_max_held(void)
{
    world_clear(&g_world);
    const size_t car = world_car(&g_world, 12.0, -13.0, 0.0, 10.0);
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    for (unsigned k = 0u; k < 40u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
    }
    const ego_moving_object_t *o = object_on(&g_sim, &g_world, car);
    TEST_ASSERT_NOT_NULL(o);
    TEST_ASSERT_TRUE(o->vy_cms > 500); /* known, well above the hold's 0.5 m/s */
    const uint16_t id = o->id;
    unsigned held = 0u;
    for (unsigned k = 1u; k <= EGO_MOVING_MAX_HELD + 20u; k++) {
        sim_line(&g_sim, &g_world, STILL, EGO_FLAG_SUSPECT, trusted());
        o = object_on(&g_sim, &g_world, car);
        if (k <= EGO_MOVING_MAX_HELD) {
            char msg[40];
            snprintf(msg, sizeof msg, "held line %u", k);
            TEST_ASSERT_NOT_NULL_MESSAGE(o, msg);
            TEST_ASSERT_EQUAL_UINT_MESSAGE(id, o->id, msg);
            held++;
        } else {
            TEST_ASSERT_EQUAL_UINT(0u, g_sim.n);
        }
    }
    TEST_ASSERT_EQUAL_UINT(EGO_MOVING_MAX_HELD, held);
}

/* --- 5. the slack ------------------------------------------------------------ */

/* Vehicle standing or driving ahead at `speed` m/s (its motion measured
 * exactly, with the given covariance and flags on every line); a walker
 * 4.5 m ahead on the left crossing at 1.5 m/s, a car 12 m ahead on the
 * right crossing at 10 m/s, for 1.5 s. Counts each one's reports. */
static void slack_run(ego_cov_t cov, uint16_t flags, double speed, unsigned *walker_reports,
                      unsigned *car_reports)
{
    const ego_pose_t motion = {0u, fx_q16_16_from_double(speed * DT_S), 0};
    world_clear(&g_world);
    const size_t walker = world_walker(&g_world, 4.5, 1.0, 0.0, 1.5);
    const size_t car = world_car(&g_world, 12.0, -20.0, 0.0, 10.0);
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    *walker_reports = 0u;
    *car_reports = 0u;
    for (unsigned k = 0u; k < 112u; k++) {
        sim_line(&g_sim, &g_world, motion, flags, cov);
        *walker_reports += (object_on(&g_sim, &g_world, walker) != NULL) ? 1u : 0u;
        *car_reports += (object_on(&g_sim, &g_world, car) != NULL) ? 1u : 0u;
    }
}

/* Every margin widens by twice the chained motion's deviation,
 * sqrt(sum var_xy) + r sqrt(sum var_theta), against a reference 0.2-0.32 s
 * (16-24 lines) old. The walker moves 0.3-0.48 m in that time, the car
 * 2-3.2 m.
 *  - trusted lines (sigma 1 mm): both found;
 *  - sigma 5 cm per axis a line (var_xy 5e-3 m^2): the margins widen by
 *    2 sqrt(16 .. 24 x 5e-3) = 0.57-0.69 m: every point of the walker has
 *    one of its reference points within the near margin (0.77 m or more):
 *    never found; the car still is;
 *  - the same on aperture lines, driving at 1.5 m/s (standing, an
 *    aperture line starts the references over): var_xy counts for
 *    nothing there, the walker is found again;
 *  - aperture lines with sigma 12.5 mrad a line: 2 r sqrt(16 .. 24) x
 *    0.0125 = 0.10-0.12 r: 0.45-0.55 m at the walker's 4.5 m (not
 *    found), 1.2-1.5 m at the car's 12 m (which moved farther: found). */
static void test_ego_moving_slack_hides_slow_bodies_only(void)
{
    unsigned walker = 0u;
    unsigned car = 0u;
    slack_run(trusted(), 0u, 0.0, &walker, &car);
    TEST_ASSERT_TRUE(walker >= 40u);
    TEST_ASSERT_TRUE(car >= 40u);
    slack_run(cov_of(2.5e-3, 1e-8), 0u, 0.0, &walker, &car);
    TEST_ASSERT_EQUAL_UINT(0u, walker);
    TEST_ASSERT_TRUE(car >= 40u);
    slack_run(cov_of(2.5e-3, 1e-8), EGO_FLAG_APERTURE, 1.5, &walker, &car);
    TEST_ASSERT_TRUE(walker >= 40u);
    TEST_ASSERT_TRUE(car >= 40u);
    slack_run(cov_of(2.5e-3, 1.5625e-4), EGO_FLAG_APERTURE, 1.5, &walker, &car);
    TEST_ASSERT_EQUAL_UINT(0u, walker);
    TEST_ASSERT_TRUE(car >= 20u);
}

/* A board 1 m wide, 0.2 m deep appears (at 0.5 s, standing) 6 m ahead,
 * its face gap_m in front of a wall; returns its reports (and asserts
 * nothing else is reported). Against the references before it, it
 * stands where they saw the wall gap_m beyond it: evidence ("entered")
 * when gap_m is beyond the near margin (0.2 m) and the free margin
 * (0.3 m), each widened by the slack. */
static unsigned appearing_board_reports(ego_cov_t cov, double gap_m)
{
    world_clear(&g_world);
    world_wall(&g_world, 5.9 + gap_m, -3.0, 5.9 + gap_m, 3.0);
    const size_t board = world_body(&g_world, 6.0, 0.0, 0.0, 0.2, 1.0, 0.0, 0.0);
    g_world.body[board].t_on = 0.5;
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    unsigned reports = 0u;
    for (unsigned k = 0u; k < 75u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, cov);
        const unsigned on_board = (object_on(&g_sim, &g_world, board) != NULL) ? 1u : 0u;
        TEST_ASSERT_EQUAL_UINT(on_board, g_sim.n); /* nothing else */
        reports += on_board;
    }
    return reports;
}

/* 1.3 m in front of the wall (its own segment) the board is found on
 * trusted lines. With sigma^2 1.125e-2 m^2 per axis a line the slack is
 * twice sqrt(16 .. 24 x 2.25e-2) = 1.2-1.47 m: the wall lies within the
 * widened near margin (1.4-1.67 m) and not 0.3 + 1.2 m beyond: no
 * evidence. Were the slack the deviation alone (0.6-0.73 m) it would be.
 * And without slack, 0.25 m in front of the wall (one segment with it)
 * the board is beyond the near margin (0.2 m) but not beyond the free
 * margin (0.3 m): no evidence either. */
static void test_ego_moving_margins_widen_by_twice_the_deviation(void)
{
    TEST_ASSERT_TRUE(appearing_board_reports(trusted(), 1.3) >= 5u);
    TEST_ASSERT_EQUAL_UINT(0u, appearing_board_reports(cov_of(1.125e-2, 1e-8), 1.3));
    TEST_ASSERT_EQUAL_UINT(0u, appearing_board_reports(trusted(), 0.25));
}

/* The slack is at most EGO_MOVING_MAX_SLACK (2 m): with sigma 1.2 m per
 * axis a line (1.5 m^2, below saturation) uncapped margins would widen by
 * 2 sqrt(16 x 3) = 14 m and more; capped, a car crossing 20 m ahead at
 * 30 m/s (6-9 m per reference age, into free space) is still found. */
static void test_ego_moving_slack_is_capped(void)
{
    world_clear(&g_world);
    const size_t car = world_car(&g_world, 20.0, -25.0, 0.0, 30.0);
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    const ego_cov_t cov = cov_of(1.5, 1e-8);
    TEST_ASSERT_TRUE(cov.xx < EGO_COV_SATURATED);
    unsigned car_reports = 0u;
    for (unsigned k = 0u; k < 75u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, cov);
        car_reports += (object_on(&g_sim, &g_world, car) != NULL) ? 1u : 0u;
    }
    TEST_ASSERT_TRUE(car_reports >= 20u);
}

/* The slack exists for the motion's error (ego_moving.h): a static world
 * moved against a reference by an error within the chained motion's
 * stated deviation is no evidence. Posts 0.3 m square 5 m around the
 * vehicle (standing), a wall 12 m ahead; every line states sigma 15 cm
 * per axis; one line's reported motion is 0.5 m off sideways. Against the
 * references before it the posts now stand 0.5 m aside, while the
 * margins are 2 sqrt(16 .. 24 x 0.045) = 1.7-2 m wider (capped at 2 m):
 * within the near margin of its own reference points, no post point is
 * evidence: nothing is reported. */
static void test_ego_moving_motion_error_within_slack_reports_nothing(void)
{
    world_clear(&g_world);
    world_wall(&g_world, 12.0, -30.0, 12.0, 30.0);
    for (int i = -3; i <= 3; i++) {
        const double b = 20.0 * i * PI / 180.0;
        world_body(&g_world, 5.0 * cos(b), 5.0 * sin(b), b, 0.3, 0.3, 0.0, 0.0);
    }
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    const ego_cov_t cov = cov_of(0.0225, 1e-8);
    const ego_pose_t off = {0u, 0, FX_Q16_16_C(0.5)};
    for (unsigned k = 0u; k < 75u; k++) {
        const ego_pose_t reported = (k == 37u) ? off : STILL;
        char msg[80];
        snprintf(msg, sizeof msg, "t %.3f s", g_sim.t + DT_S);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(
            0u,
            sim_line_as(&g_sim, &g_world, STILL, reported, DT_US, 0u, cov, EGO_MOVING_MAX_OBJECTS),
            msg);
    }
}

/* --- 6. capacity and bounds -------------------------------------------------- */

#define GUARD 0xA5u
#define BIG_CAP 255u

static bool same_object(const ego_moving_object_t *a, const ego_moving_object_t *b)
{
    return a->id == b->id && a->points == b->points && a->cx_cm == b->cx_cm &&
           a->cy_cm == b->cy_cm && a->length_cm == b->length_cm && a->width_cm == b->width_cm &&
           a->vx_cms == b->vx_cms && a->vy_cms == b->vy_cms;
}

/* Twenty bodies 0.6 m square in an arc 6 and 7.5 m away (alternately:
 * neighbours never join one segment), each crossing at 2 m/s: more moving
 * clusters than EGO_MOVING_CLUSTERS, more bodies than EGO_MOVING_TRACKS.
 * Four states see the same lines with caps 8, 3, 0 and 255: each returns
 * at most its cap and at most EGO_MOVING_MAX_OBJECTS, the same objects
 * (the cap only cuts the list), unique non-zero ids, points within the
 * scan, and writes nothing past what it returns. */
static void test_ego_moving_capacity_and_bounds(void)
{
    static ego_moving_t m3;
    static ego_moving_t m0;
    static ego_moving_t mbig;
    static ego_moving_object_t o3[3 + 1];
    static ego_moving_object_t o0[1];
    static ego_moving_object_t obig[BIG_CAP + 1u];
    world_clear(&g_world);
    for (unsigned i = 0u; i < 20u; i++) {
        const double b = (-80.0 + 8.42 * i) * PI / 180.0;
        const double r = (i % 2u == 0u) ? 6.0 : 7.5;
        world_body(&g_world, r * cos(b), r * sin(b), b + PI / 2.0, 0.6, 0.6, -2.0 * sin(b),
                   2.0 * cos(b));
    }
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    ego_moving_reset(&m3);
    ego_moving_reset(&m0);
    ego_moving_reset(&mbig);
    /* The same first line. */
    TEST_ASSERT_EQUAL_UINT(0u,
                           ego_moving_scan(&m3, &g_sim.scan, g_sim.time_us, &g_sim.out, o3, 3u));
    TEST_ASSERT_EQUAL_UINT(0u,
                           ego_moving_scan(&m0, &g_sim.scan, g_sim.time_us, &g_sim.out, o0, 0u));
    TEST_ASSERT_EQUAL_UINT(
        0u, ego_moving_scan(&mbig, &g_sim.scan, g_sim.time_us, &g_sim.out, obig, BIG_CAP));
    uint8_t most = 0u;
    for (unsigned k = 0u; k < 75u; k++) {
        const uint8_t n = sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        most = (n > most) ? n : most;
        for (uint8_t i = 0u; i < n; i++) {
            for (uint8_t j = 0u; j < i; j++) {
                TEST_ASSERT_TRUE(g_sim.obj[i].id != g_sim.obj[j].id);
            }
        }
        memset(o3, GUARD, sizeof o3);
        memset(o0, GUARD, sizeof o0);
        memset(obig, GUARD, sizeof obig);
        const uint8_t n3 = ego_moving_scan(&m3, &g_sim.scan, g_sim.time_us, &g_sim.out, o3, 3u);
        const uint8_t n0 = ego_moving_scan(&m0, &g_sim.scan, g_sim.time_us, &g_sim.out, o0, 0u);
        const uint8_t nbig =
            ego_moving_scan(&mbig, &g_sim.scan, g_sim.time_us, &g_sim.out, obig, BIG_CAP);
        TEST_ASSERT_EQUAL_UINT((n < 3u) ? n : 3u, n3);
        TEST_ASSERT_EQUAL_UINT(0u, n0);
        TEST_ASSERT_EQUAL_UINT(n, nbig);
        for (uint8_t i = 0u; i < n3; i++) {
            bool found = false;
            for (uint8_t j = 0u; j < n && !found; j++) {
                found = same_object(&o3[i], &g_sim.obj[j]);
            }
            TEST_ASSERT_TRUE(found);
        }
        if (n > 0u) {
            TEST_ASSERT_EQUAL_MEMORY(g_sim.obj, obig, n * sizeof obig[0]);
        }
        const uint8_t *g3 = (const uint8_t *)&o3[n3];
        const uint8_t *gbig = (const uint8_t *)&obig[nbig];
        for (size_t b = 0u; b < sizeof o3[0]; b++) {
            TEST_ASSERT_EQUAL_HEX8(GUARD, g3[b]);
            TEST_ASSERT_EQUAL_HEX8(GUARD, gbig[b]);
            TEST_ASSERT_EQUAL_HEX8(GUARD, ((const uint8_t *)o0)[b]);
        }
    }
    TEST_ASSERT_EQUAL_UINT(EGO_MOVING_MAX_OBJECTS, most);
}

/* --- 7. random input ---------------------------------------------------------- */

static uint64_t rng_state = 20261204u;

static uint64_t rng(void)
{
    return test_rng_next(&rng_state);
}

/* Uniform in [0, n) (n > 0). */
static uint32_t rng_below(uint32_t n)
{
    return (uint32_t)(rng() % n);
}

typedef struct {
    uint16_t range[EGO_MAX_BEAMS];
    fx_bam32_t bearing[EGO_MAX_BEAMS];
    ego_range_scan_t scan;
    ego_output_t out;
    uint32_t time_us;
    uint8_t cap;
} random_line_t;

static void random_bearings(random_line_t *l)
{
    ego_range_scan_t *s = &l->scan;
    const uint32_t steps = (s->count > 1u) ? (uint32_t)s->count - 1u : 1u;
    if (rng_below(2u) == 0u) {
        /* Uniform: any first bearing, a step within (0, half a turn) whose
         * steps span at most one turn. */
        s->bearing = NULL;
        s->first_bearing = rng();
        uint64_t limit = UINT64_MAX / steps;
        limit = (limit >= ((uint64_t)1 << 63)) ? ((uint64_t)1 << 63) - 1u : limit;
        const unsigned shift = rng_below(40u);
        s->bearing_step = 1u + (rng() % limit >> shift);
        return;
    }
    /* A table: increasing steps in (0, half a turn), at most one turn in
     * all, drawn around a random mean. */
    s->bearing = l->bearing;
    const uint32_t mean_max = (uint32_t)(0xFFFFFFFFu / steps);
    const uint32_t mean = 1u + rng_below(mean_max);
    uint64_t sweep = 0u;
    l->bearing[0] = (fx_bam32_t)rng();
    for (uint16_t k = 1u; k < s->count; k++) {
        uint64_t step = 1u + rng_below(mean);
        step = (step >= 0x80000000u) ? 0x7FFFFFFFu : step;
        step = (sweep + step > 0xFFFFFFFFu) ? 1u : step;
        sweep += step;
        l->bearing[k] = l->bearing[k - 1u] + (fx_bam32_t)step;
    }
}

static void random_ranges(random_line_t *l)
{
    const uint32_t mode = rng_below(3u);
    uint32_t r = rng_below(65536u);
    for (uint16_t k = 0u; k < l->scan.count; k++) {
        const uint32_t pick = rng_below(100u);
        if (mode == 0u) {
            /* Anything. */
            r = rng_below(65536u);
        } else if (pick < 3u) {
            /* A jump in a smooth profile: segments and clusters. */
            r = rng_below(65536u);
        } else {
            const int32_t step = (int32_t)rng_below(401u) - 200;
            const int32_t next = (int32_t)r + step * (int32_t)mode;
            r = (uint32_t)((next < 1) ? 1 : (next > 65535) ? 65535 : next);
        }
        l->range[k] = (pick < 8u) ? 0u : (pick < 11u) ? 65535u : (uint16_t)r;
    }
}

static fx_q2_30_t random_variance(void)
{
    const uint32_t pick = rng_below(10u);
    return (pick == 0u)  ? EGO_COV_SATURATED
           : (pick < 6u) ? (fx_q2_30_t)rng_below(4096u)
                         : (fx_q2_30_t)rng_below((uint32_t)EGO_COV_SATURATED);
}

static void random_line(random_line_t *l, uint32_t last_time_us)
{
    static const uint32_t units[7] = {1u, 7u, 250u, 1000u, 10000u, 123457u, 500000u};
    memset(&l->scan, 0, sizeof l->scan);
    const uint32_t size = rng_below(4u);
    l->scan.count = (uint16_t)((size == 0u) ? rng_below(5u) : rng_below(EGO_MAX_BEAMS + 1u));
    l->scan.range = l->range;
    l->scan.range_unit_um = (rng_below(4u) == 0u) ? 1u + rng_below(500000u) : units[rng_below(7u)];
    l->scan.origin_x = (fx_q16_16_t)((int32_t)rng_below(20u * 65536u + 1u) - 10 * 65536);
    l->scan.origin_y = (fx_q16_16_t)((int32_t)rng_below(20u * 65536u + 1u) - 10 * 65536);
    random_bearings(l);
    random_ranges(l);
    memset(&l->out, 0, sizeof l->out);
    const uint32_t pose = rng_below(4u);
    l->out.pose.theta =
        (pose == 0u) ? (fx_bam32_t)rng() : (fx_bam32_t)((int32_t)rng_below(2000001u) - 1000000);
    l->out.pose.x =
        (pose == 0u) ? (fx_q16_16_t)rng() : (fx_q16_16_t)((int32_t)rng_below(131073u) - 65536);
    l->out.pose.y =
        (pose == 0u) ? (fx_q16_16_t)rng() : (fx_q16_16_t)((int32_t)rng_below(131073u) - 65536);
    l->out.flags = (rng_below(4u) == 0u) ? (uint16_t)rng() : 0u;
    l->out.cov.xx = random_variance();
    l->out.cov.yy = random_variance();
    l->out.cov.tt = random_variance();
    l->out.cov.xy = (fx_q2_30_t)rng();
    const uint32_t gap = rng_below(20u);
    l->time_us = last_time_us + ((gap == 0u)   ? 0u
                                 : (gap == 1u) ? EGO_MOVING_MAX_DT_US + rng_below(5000000u)
                                 : (gap == 2u) ? (uint32_t)rng()
                                 : (gap == 3u) ? rng_below(EGO_MOVING_MAX_DT_US + 1u)
                                               : 8000u + rng_below(20000u));
    l->out.dt_us = l->time_us - last_time_us;
    l->cap = (uint8_t)rng_below(BIG_CAP + 1u);
}

/* A coherent run: one sensor (random count, unit and bearings) looking at
 * a fixed random profile within 35 m, crossed by blobs a few beams wide
 * that move a beam or so per line, with small random motions and mostly
 * measured lines: tracks form and objects are reported. */
typedef struct {
    uint16_t base[EGO_MAX_BEAMS];
    int32_t blob_at[4]; /* first beam, 1/16 beam */
    int32_t blob_speed[4];
    uint16_t blob_width[4];
    uint16_t blob_depth[4]; /* in units, in front of the profile */
} coherent_t;

static coherent_t g_coherent;

static void coherent_start(random_line_t *l)
{
    static const uint32_t units[3] = {250u, 1000u, 10000u};
    memset(&l->scan, 0, sizeof l->scan);
    l->scan.count = (uint16_t)(60u + rng_below(EGO_MAX_BEAMS - 60u + 1u));
    l->scan.range = l->range;
    l->scan.range_unit_um = units[rng_below(3u)];
    random_bearings(l);
    const uint32_t far = 30000000u / l->scan.range_unit_um; /* 30 m */
    const uint32_t top = (far > 65535u) ? 65535u : far;
    uint32_t r = top / 2u;
    for (uint16_t k = 0u; k < l->scan.count; k++) {
        const int32_t next =
            (int32_t)r + (int32_t)rng_below(top / 50u + 1u) - (int32_t)(top / 100u);
        r = (uint32_t)((next < (int32_t)(top / 3u)) ? (int32_t)(top / 3u)
                       : (next > (int32_t)top)      ? (int32_t)top
                                                    : next);
        g_coherent.base[k] = (rng_below(50u) == 0u) ? 0u : (uint16_t)r;
    }
    for (unsigned i = 0u; i < 4u; i++) {
        g_coherent.blob_at[i] = (int32_t)rng_below((uint32_t)l->scan.count * 16u);
        g_coherent.blob_speed[i] = (int32_t)rng_below(65u) - 32;
        g_coherent.blob_width[i] = (uint16_t)(3u + rng_below(10u));
        g_coherent.blob_depth[i] = (uint16_t)(top / 10u + rng_below(top / 5u));
    }
}

static void coherent_line(random_line_t *l, uint32_t last_time_us)
{
    memcpy(l->range, g_coherent.base, sizeof l->range);
    for (unsigned i = 0u; i < 4u; i++) {
        g_coherent.blob_at[i] += g_coherent.blob_speed[i];
        const int32_t at = g_coherent.blob_at[i] / 16;
        for (int32_t k = at; k < at + (int32_t)g_coherent.blob_width[i]; k++) {
            if (k >= 0 && k < (int32_t)l->scan.count && l->range[k] > g_coherent.blob_depth[i]) {
                l->range[k] = (uint16_t)(l->range[k] - g_coherent.blob_depth[i]);
            }
        }
    }
    memset(&l->out, 0, sizeof l->out);
    l->out.pose.theta = (fx_bam32_t)((int32_t)rng_below(200001u) - 100000);
    l->out.pose.x = (fx_q16_16_t)((int32_t)rng_below(6554u) - 3277);
    l->out.pose.y = (fx_q16_16_t)((int32_t)rng_below(6554u) - 3277);
    l->out.flags = (rng_below(30u) == 0u) ? (uint16_t)rng() : 0u;
    l->out.cov.xx = (fx_q2_30_t)rng_below(2000u);
    l->out.cov.yy = (fx_q2_30_t)rng_below(2000u);
    l->out.cov.tt = (fx_q2_30_t)rng_below(20u);
    l->time_us = last_time_us + 11000u + rng_below(5000u);
    l->out.dt_us = l->time_us - last_time_us;
    l->cap = (uint8_t)rng_below(EGO_MOVING_MAX_OBJECTS + 2u);
}

/* The documented ranges of one object of a line. */
static void check_random_object(const random_line_t *l, const ego_moving_object_t *o)
{
    TEST_ASSERT_TRUE(o->id != 0u);
    TEST_ASSERT_TRUE(o->points >= EGO_MOVING_MIN_POINTS && o->points <= l->scan.count);
    /* Both velocity components known or neither (a known one is never
     * the marker). */
    TEST_ASSERT_EQUAL_INT(o->vx_cms == EGO_MOVING_UNKNOWN, o->vy_cms == EGO_MOVING_UNKNOWN);
    /* Every point lies within 35 m of the sensor: the box's centre within
     * 35 sqrt(2) m (its extent along and across any axes lies within
     * +-35 m), its sides at most 70 m (1 cm for roundings). */
    const double dx = o->cx_cm / 100.0 - fx_q16_16_to_double(l->scan.origin_x);
    const double dy = o->cy_cm / 100.0 - fx_q16_16_to_double(l->scan.origin_y);
    TEST_ASSERT_TRUE(hypot(dx, dy) <= 35.0 * sqrt(2.0) + 0.02);
    TEST_ASSERT_TRUE(o->length_cm <= 7001u);
    TEST_ASSERT_TRUE(o->width_cm <= 7001u);
}

/* 600 random lines (six runs of 100): wild runs (each line anything:
 * counts 0 .. EGO_MAX_BEAMS, ranges of 0 and 65535 among smooth and wild
 * ones, any unit, uniform bearings and tables that pass ego_range_check,
 * random poses, flags, variances (some saturated), intervals (some 0,
 * over the maximum, wrapping), caps 0..255) and coherent runs (above).
 * Every return within its cap and EGO_MOVING_MAX_OBJECTS, every object
 * within its documented ranges, nothing written past the return; a second
 * fresh state and a used state after ego_moving_reset give the same
 * bytes. */
static void test_ego_moving_random_input(void)
{
    static random_line_t l;
    static ego_moving_t a;
    static ego_moving_t b;
    static ego_moving_t c;
    static ego_moving_object_t oa[BIG_CAP + 1u];
    static ego_moving_object_t ob[BIG_CAP + 1u];
    static ego_moving_object_t oc[BIG_CAP + 1u];
    unsigned reported = 0u;
    unsigned lines = 0u;
    for (unsigned run = 0u; run < 6u; run++) {
        const bool coherent = (run % 2u) == 1u;
        /* c: used by a run of its own first. */
        ego_moving_reset(&c);
        uint32_t t = (uint32_t)rng();
        for (unsigned k = 0u; k < 30u; k++) {
            random_line(&l, t);
            t = l.time_us;
            ego_moving_scan(&c, &l.scan, l.time_us, &l.out, oc, l.cap);
        }
        ego_moving_reset(&a);
        ego_moving_reset(&b);
        ego_moving_reset(&c);
        t = (uint32_t)rng();
        if (coherent) {
            coherent_start(&l);
        }
        for (unsigned k = 0u; k < 100u; k++) {
            if (coherent) {
                coherent_line(&l, t);
            } else {
                random_line(&l, t);
            }
            t = l.time_us;
            TEST_ASSERT_TRUE(ego_range_check(&l.scan));
            memset(oa, GUARD, sizeof oa);
            memset(ob, GUARD, sizeof ob);
            memset(oc, GUARD, sizeof oc);
            const uint8_t na = ego_moving_scan(&a, &l.scan, l.time_us, &l.out, oa, l.cap);
            const uint8_t nb = ego_moving_scan(&b, &l.scan, l.time_us, &l.out, ob, l.cap);
            const uint8_t nc = ego_moving_scan(&c, &l.scan, l.time_us, &l.out, oc, l.cap);
            TEST_ASSERT_TRUE(na <= l.cap && na <= EGO_MOVING_MAX_OBJECTS);
            /* The work meter (ego_moving.h): evidence tests stop at
             * EGO_MOVING_UNITS_PER_BEAM a beam (the last may cross by 53),
             * plus a unit per point of each box: the clusters' (disjoint
             * segments) and the hold's candidates (at most two segments
             * for each track). */
            TEST_ASSERT_TRUE(a.units <= (uint32_t)l.scan.count * (EGO_MOVING_UNITS_PER_BEAM + 1u +
                                                                  2u * EGO_MOVING_TRACKS) +
                                            53u);
            TEST_ASSERT_EQUAL_UINT(na, nb);
            TEST_ASSERT_EQUAL_UINT(na, nc);
            TEST_ASSERT_EQUAL_MEMORY(oa, ob, sizeof oa);
            TEST_ASSERT_EQUAL_MEMORY(oa, oc, sizeof oa);
            for (uint8_t i = 0u; i < na; i++) {
                check_random_object(&l, &oa[i]);
                for (uint8_t j = 0u; j < i; j++) {
                    TEST_ASSERT_TRUE(oa[i].id != oa[j].id);
                }
            }
            for (size_t i = (size_t)na * sizeof oa[0]; i < sizeof oa; i++) {
                TEST_ASSERT_EQUAL_HEX8(GUARD, ((const uint8_t *)oa)[i]);
            }
            reported += na;
            lines++;
        }
    }
    TEST_ASSERT_EQUAL_UINT(600u, lines);
    /* The fields above were checked on real objects. */
    TEST_ASSERT_TRUE(reported > 0u);
}

/* --- 8. ids ------------------------------------------------------------------- */

/* A car crossing on the right and a walker on the left, for 2 s: each is
 * reported under one id all along (from its confirmation to the end, on
 * every line for the car), the two ids are the first two (1 and 2). */
static void test_ego_moving_ids_stay_with_their_bodies(void)
{
    world_clear(&g_world);
    const size_t car = world_car(&g_world, 12.0, -24.0, 0.0, 10.0);
    const size_t walker = world_walker(&g_world, 5.0, 2.0, 0.0, 1.5);
    sim_start(&g_sim, &g_world, 0.0, 0.0, BEAMS);
    uint16_t id[2] = {0u, 0u};
    unsigned car_reports = 0u;
    unsigned first_car_line = 0u;
    for (unsigned k = 0u; k < 150u; k++) {
        sim_line(&g_sim, &g_world, STILL, 0u, trusted());
        const size_t which[2] = {car, walker};
        for (unsigned b = 0u; b < 2u; b++) {
            const ego_moving_object_t *o = object_on(&g_sim, &g_world, which[b]);
            if (o == NULL) {
                continue;
            }
            if (id[b] == 0u) {
                id[b] = o->id;
                first_car_line = (b == 0u) ? g_sim.line : first_car_line;
            }
            TEST_ASSERT_EQUAL_UINT(id[b], o->id);
            car_reports += (b == 0u) ? 1u : 0u;
        }
        TEST_ASSERT_EQUAL_UINT(g_sim.n, (object_on(&g_sim, &g_world, car) != NULL) +
                                            (object_on(&g_sim, &g_world, walker) != NULL));
    }
    TEST_ASSERT_EQUAL_UINT(150u - first_car_line + 1u, car_reports);
    TEST_ASSERT_TRUE((id[0] == 1u && id[1] == 2u) || (id[0] == 2u && id[1] == 1u));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_moving_ref_chord_box_of_known_points);
    RUN_TEST(test_ego_moving_crossing_car_box_and_velocity);
    RUN_TEST(test_ego_moving_overtaking_car_from_moving_vehicle);
    RUN_TEST(test_ego_moving_car_through_a_gap_follows_the_rule);
    RUN_TEST(test_ego_moving_static_world_reports_nothing);
    RUN_TEST(test_ego_moving_walker_before_wall_reveals_no_body);
    RUN_TEST(test_ego_moving_unmeasured_line_starts_everything_over);
    RUN_TEST(test_ego_moving_bad_interval_starts_everything_over);
    RUN_TEST(test_ego_moving_saturated_variance_restarts_references_only);
    RUN_TEST(test_ego_moving_longest_interval_keeps_tracks);
    RUN_TEST(test_ego_moving_untrusted_motion_restarts_references_only);
    RUN_TEST(test_ego_moving_track_survives_short_gaps_only);
    RUN_TEST(test_ego_moving_new_body_takes_a_missed_slot);
    RUN_TEST(test_ego_moving_hold_lasts_at_most_max_held);
    RUN_TEST(test_ego_moving_slack_hides_slow_bodies_only);
    RUN_TEST(test_ego_moving_margins_widen_by_twice_the_deviation);
    RUN_TEST(test_ego_moving_slack_is_capped);
    RUN_TEST(test_ego_moving_motion_error_within_slack_reports_nothing);
    RUN_TEST(test_ego_moving_capacity_and_bounds);
    RUN_TEST(test_ego_moving_random_input);
    RUN_TEST(test_ego_moving_ids_stay_with_their_bodies);
    return UNITY_END();
}
