/* world_scenario.c - see world_scenario.h; the numbers are explained in
 * docs/synthetic-worlds.md.
 *
 * The campus: a ring road (a 200 m x 70 m rounded rectangle, corner
 * radius 17 m, driven counter-clockwise in the right-hand lane; the
 * oncoming lane is 3.5 m to the left) with the corridor stretch on its
 * bottom edge, buildings, a rotunda and a parking lot inside it, and a
 * plaza with a round fountain north of it. Nothing stands within 4 m of
 * the lane centre on the outside or 7.5 m on the inside.
 *
 * The other maps: the corridor, a round plaza (plaza), a bare 72-gon
 * (ring), a corridor with sparse posts (sparse) and a highway lined with
 * buildings (highway); sparse and highway place things irregularly from a
 * fixed splitmix64 state, one draw per statement. The busy streets
 * (traffic, platoon, overtake, crossing, pedestrians, stopgo) do the same
 * for their buildings, posts and parked cars, and add vehicles and
 * pedestrians whose motions are closed forms of time.
 */
#include "world_scenario.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "world_path.h"

/* Time k period + dt, s; exactly k * period at dt = 0. */
static double scene_time(unsigned k, double period, double dt)
{
    return (double)k * period + dt;
}

/* ------------------------------------------------------------------ */
/* Building outlines with recessed facades. */

enum { EDGE_S = 1, EDGE_E = 2, EDGE_N = 4, EDGE_W = 8 };

#define POLY_MAX_POINTS 512u

typedef struct {
    double xy[2u * POLY_MAX_POINTS];
    size_t n;
} poly_t;

static void poly_add(poly_t *p, double x, double y)
{
    if (p->n < POLY_MAX_POINTS) {
        p->xy[2u * p->n] = x;
        p->xy[2u * p->n + 1u] = y;
        p->n++;
    }
}

/* The edge from a towards b (b itself is the next edge's first point). A
 * notched edge gets recesses notch_w wide and notch_d deep every period
 * metres, centred on the edge; they go to the left of a -> b, which is
 * inside a counter-clockwise outline. */
static void poly_edge(poly_t *p, double ax, double ay, double bx, double by, bool notched,
                      double period, double notch_w, double notch_d)
{
    poly_add(p, ax, ay);
    if (!notched) {
        return;
    }
    const double len = hypot(bx - ax, by - ay);
    const double ux = (bx - ax) / len;
    const double uy = (by - ay) / len;
    const double nx = -uy * notch_d;
    const double ny = ux * notch_d;
    if (len < period) {
        return;
    }
    const unsigned count = (unsigned)floor((len - period) / period) + 1u;
    const double first = 0.5 * (len - (double)(count - 1u) * period - notch_w);
    for (unsigned j = 0u; j < count; j++) {
        const double s0 = first + (double)j * period;
        const double s1 = s0 + notch_w;
        poly_add(p, ax + ux * s0, ay + uy * s0);
        poly_add(p, ax + ux * s0 + nx, ay + uy * s0 + ny);
        poly_add(p, ax + ux * s1 + nx, ay + uy * s1 + ny);
        poly_add(p, ax + ux * s1, ay + uy * s1);
    }
}

/* Rectangle [x0, x1] x [y0, y1]; the edges named in notched (EDGE_*) get
 * recesses. */
static void add_building(wmap_t *map, double x0, double y0, double x1, double y1,
                         unsigned notched, double period, double notch_w, double notch_d)
{
    static poly_t p;
    p.n = 0u;
    poly_edge(&p, x0, y0, x1, y0, (notched & EDGE_S) != 0u, period, notch_w, notch_d);
    poly_edge(&p, x1, y0, x1, y1, (notched & EDGE_E) != 0u, period, notch_w, notch_d);
    poly_edge(&p, x1, y1, x0, y1, (notched & EDGE_N) != 0u, period, notch_w, notch_d);
    poly_edge(&p, x0, y1, x0, y0, (notched & EDGE_W) != 0u, period, notch_w, notch_d);
    wmap_add_polyline(map, p.xy, p.n, 1);
}

/* A square post of side size centred on (x, y). */
static void add_post(wmap_t *map, double x, double y, double size)
{
    wmap_add_rect(map, x - 0.5 * size, y - 0.5 * size, x + 0.5 * size, y + 0.5 * size);
}

/* ------------------------------------------------------------------ */
/* The campus map. */

#define TREE_R 0.35
#define POST_SIZE 0.25

#define PLAZA_X 100.0
#define PLAZA_Y 105.0
#define FOUNTAIN_R 3.0

static void build_campus_inside(wmap_t *m)
{
    /* North side of the corridor: one long flat facade at y = 7.75. */
    add_building(m, 30.0, 7.75, 170.0, 24.0, EDGE_N, 10.0, 3.0, 1.0);
    /* Lecture hall, rotunda, two small buildings. */
    add_building(m, 35.0, 32.0, 80.0, 56.0, EDGE_N | EDGE_W | EDGE_E, 6.0, 2.0, 0.8);
    wmap_add_circle(m, 95.0, 43.0, 7.0);
    add_building(m, 12.0, 30.0, 26.0, 46.0, 0u, 1.0, 0.0, 0.0);
    add_building(m, 176.0, 28.0, 190.0, 46.0, EDGE_W, 5.0, 1.5, 0.6);
    /* Parking lot: two rows of cars parked nose in, 2.7 m apart. */
    static const char rows[2][18] = {"11011101110110111", "10111011011101101"};
    for (size_t r = 0u; r < 2u; r++) {
        for (size_t j = 0u; j < 17u; j++) {
            if (rows[r][j] == '1') {
                wmap_add_box(m, 118.0 + 2.7 * (double)j, (r == 0u) ? 37.0 : 49.0, 0.5 * WORLD_PI,
                             WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
            }
        }
    }
    /* Trees and lamp posts along the inside of the top road. */
    for (unsigned j = 0u; j <= 14u; j++) {
        wmap_add_circle(m, 30.0 + 10.0 * (double)j, 60.5, TREE_R);
    }
    for (unsigned j = 0u; j <= 6u; j++) {
        add_post(m, 35.0 + 20.0 * (double)j, 61.8, POST_SIZE);
    }
    wmap_add_circle(m, 12.0, 52.0, TREE_R);
    /* Bollards along the inside of the left road. */
    for (unsigned j = 0u; j <= 10u; j++) {
        wmap_add_circle(m, 8.5, 21.0 + 3.0 * (double)j, 0.1);
    }
    wmap_add_circle(m, 186.0, 55.0, TREE_R);
}

static void build_campus_outside(wmap_t *m)
{
    /* South side of the corridor: flat facade at y = -4. */
    add_building(m, 30.0, -24.0, 170.0, -4.0, EDGE_S, 12.0, 4.0, 1.5);
    /* South-west and south-east blocks, and trees along the road. */
    add_building(m, -30.0, -40.0, 22.0, -12.0, EDGE_N, 7.0, 2.5, 1.0);
    add_building(m, 178.0, -40.0, 230.0, -12.0, EDGE_N, 7.0, 2.5, 1.0);
    for (unsigned j = 0u; j <= 6u; j++) {
        wmap_add_circle(m, -20.0 + 8.0 * (double)j, -6.5, TREE_R);
        wmap_add_circle(m, 172.0 + 8.0 * (double)j, -6.5, TREE_R);
    }
    /* West: a long building, a wall to the south block, parked cars. */
    add_building(m, -45.0, 5.0, -12.0, 65.0, EDGE_E, 8.0, 3.0, 1.2);
    wmap_add_segment(m, -12.0, 5.0, -12.0, -12.0);
    static const double parked_y[] = {21.0, 27.5, 34.0, 47.0};
    for (size_t j = 0u; j < sizeof parked_y / sizeof parked_y[0]; j++) {
        wmap_add_box(m, -5.5, parked_y[j], 0.5 * WORLD_PI, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
    }
    /* East: a building with a recessed facade, a row of trees. */
    add_building(m, 210.0, 0.0, 240.0, 40.0, EDGE_W, 6.0, 2.0, 1.0);
    for (unsigned j = 0u; j <= 5u; j++) {
        wmap_add_circle(m, 205.5, 10.0 + 9.0 * (double)j, TREE_R);
    }
    /* North-east: a zig-zag fence, 3 m panels. */
    double fence[2u * 21u];
    for (unsigned j = 0u; j <= 20u; j++) {
        fence[2u * j] = 172.0 + 3.0 * (double)j;
        fence[2u * j + 1u] = 79.0 + (((j % 2u) != 0u) ? 0.3 : -0.3);
    }
    wmap_add_polyline(m, fence, 21u, 0);
    /* Trees along the outside of the top road, a bus shelter, and the
     * north-west block behind them. */
    for (unsigned j = 0u; j <= 13u; j++) {
        wmap_add_circle(m, 20.0 + 12.0 * (double)j, 76.0, TREE_R);
    }
    wmap_add_rect(m, 28.0, 77.5, 34.0, 78.7);
    add_building(m, -40.0, 84.0, 20.0, 120.0, EDGE_S | EDGE_E, 7.0, 2.5, 1.2);
}

static void build_plaza(wmap_t *m)
{
    /* The round fountain, four benches around it, a ring of trees and a
     * ring of lamp posts. */
    wmap_add_circle(m, PLAZA_X, PLAZA_Y, FOUNTAIN_R);
    for (unsigned j = 0u; j < 4u; j++) {
        const double a = world_rad(45.0 + 90.0 * (double)j);
        wmap_add_box(m, PLAZA_X + 7.0 * cos(a), PLAZA_Y + 7.0 * sin(a), a + 0.5 * WORLD_PI, 2.0,
                     0.6);
    }
    for (unsigned j = 0u; j < 12u; j++) {
        const double a = world_rad(15.0 + 30.0 * (double)j);
        wmap_add_circle(m, PLAZA_X + 19.0 * cos(a), PLAZA_Y + 19.0 * sin(a), 0.3);
    }
    for (unsigned j = 0u; j < 8u; j++) {
        const double a = world_rad(45.0 * (double)j);
        add_post(m, PLAZA_X + 16.5 * cos(a), PLAZA_Y + 16.5 * sin(a), POST_SIZE);
    }
    /* Library to the north, a block to the west, an L-shaped block east. */
    add_building(m, 60.0, 130.0, 140.0, 150.0, EDGE_S, 8.0, 3.0, 1.5);
    add_building(m, 42.0, 84.0, 66.0, 122.0, EDGE_E, 6.0, 2.0, 1.0);
    static const double ell[] = {134.0, 82.0,  168.0, 82.0,  168.0, 126.0,
                                 152.0, 126.0, 152.0, 98.0,  134.0, 98.0};
    wmap_add_polyline(m, ell, 6u, 1);
}

static void build_campus(wmap_t *m)
{
    build_campus_inside(m);
    build_campus_outside(m);
    build_plaza(m);
}

/* ------------------------------------------------------------------ */
/* The ring road: lane centre of the counter-clockwise direction. */

#define LOOP_W 200.0
#define LOOP_H 70.0
#define LOOP_R 17.0
#define LANE_OFFSET 3.5 /* oncoming lane, to the left */

static void loop_path(wpath_t *path)
{
    const double arc = 0.5 * WORLD_PI * LOOP_R;
    const wpiece_t pieces[8] = {
        {LOOP_W - 2.0 * LOOP_R, 0.0}, {arc, 1.0 / LOOP_R}, {LOOP_H - 2.0 * LOOP_R, 0.0},
        {arc, 1.0 / LOOP_R},          {LOOP_W - 2.0 * LOOP_R, 0.0}, {arc, 1.0 / LOOP_R},
        {LOOP_H - 2.0 * LOOP_R, 0.0}, {arc, 1.0 / LOOP_R},
    };
    const wpose_t start = {LOOP_R, 0.0, 0.0};
    wpath_init(path, start, pieces, 8u, true);
}

/* Arc length of the campus start: (45, 70) on the top edge, heading west. */
static double campus_start(const wpath_t *loop)
{
    return loop->offsets[4] + (LOOP_W - LOOP_R - 45.0);
}

/* Campus speed profile: from rest to 7 m/s, 6 m/s through the first
 * corner, 9 m/s on the left edge, 6 m/s through the second corner, then
 * 10 m/s into the corridor. */
static const wknot_t campus_knots[] = {
    {0.0, 0.0},  {4.0, 7.0},  {5.5, 6.0},  {10.0, 6.0}, {12.0, 9.0},
    {13.0, 9.0}, {14.5, 6.0}, {19.0, 6.0}, {21.0, 10.0},
};
#define CAMPUS_KNOTS (sizeof campus_knots / sizeof campus_knots[0])

static double campus_s(const wpath_t *loop, double t)
{
    return campus_start(loop) + wprofile_distance(campus_knots, CAMPUS_KNOTS, t);
}

/* At rest before t = 0 (a beam of scan 0 with --timing lms is measured
 * then): the profile's distance is 0 there. */
static wpose_t campus_pose(unsigned k, double period, double dt)
{
    wpath_t loop;
    loop_path(&loop);
    return wpath_pose(&loop, campus_s(&loop, scene_time(k, period, dt)), 0.0);
}

/* ------------------------------------------------------------------ */
/* busy: the campus drive with traffic. */

typedef struct {
    double ahead; /* m, arc length ahead of the ego's start at t = 0 */
    double speed; /* m/s */
} oncoming_t;

static const oncoming_t oncoming[] = {
    {60.0, 8.0}, {110.0, 9.0}, {150.0, 7.5}, {200.0, 9.0}, {250.0, 8.5}, {300.0, 8.0},
};
#define ONCOMING_COUNT (sizeof oncoming / sizeof oncoming[0])

static void set_mover(wmover_t *m, wpose_t p)
{
    m->x = p.x;
    m->y = p.y;
    m->heading = p.theta;
    m->length = WORLD_CAR_LENGTH;
    m->width = WORLD_CAR_WIDTH;
}

static size_t busy_movers(double t, wmover_t *out)
{
    wpath_t loop;
    loop_path(&loop);
    size_t n = 0u;
    /* The car ahead, in the ego's lane, 12-20 m ahead (period 12 s). */
    const double gap = 16.0 + 4.0 * sin(2.0 * WORLD_PI * t / 12.0);
    set_mover(&out[n++], wpath_pose(&loop, campus_s(&loop, t) + gap, 0.0));
    /* Oncoming traffic in the other lane. */
    const double s0 = campus_start(&loop);
    for (size_t i = 0u; i < ONCOMING_COUNT && n < WORLD_MAX_MOVERS; i++) {
        wpose_t p = wpath_pose(&loop, s0 + oncoming[i].ahead - oncoming[i].speed * t, LANE_OFFSET);
        p.theta = world_wrap(p.theta + WORLD_PI);
        set_mover(&out[n++], p);
    }
    return n;
}

/* ------------------------------------------------------------------ */
/* fast: the ring road at 2-3 m per scan. */

#define FAST_STEP 2.5        /* m per scan on average */
#define FAST_SWING 0.5       /* +- m per scan */
#define FAST_PERIOD_SCANS 37.0

/* Defined per scan: between scans, u = k + dt / period is a continuous
 * scan index (u = k exactly at dt = 0). */
static wpose_t fast_pose(unsigned k, double period, double dt)
{
    wpath_t loop;
    loop_path(&loop);
    const double u = (double)k + dt / period;
    /* s(k + 1) - s(k) = STEP + SWING cos(2 pi (k + 1/2) / P) exactly. */
    const double amp = 0.5 * FAST_SWING / sin(WORLD_PI / FAST_PERIOD_SCANS);
    const double s = FAST_STEP * u + amp * sin(2.0 * WORLD_PI * u / FAST_PERIOD_SCANS);
    return wpath_pose(&loop, campus_start(&loop) + s, 0.0);
}

/* ------------------------------------------------------------------ */
/* circle: 27 m diameter around the plaza's fountain at 3 m/s. */

#define CIRCLE_R 13.5
#define CIRCLE_SPEED 3.0

static wpose_t circle_pose(unsigned k, double period, double dt)
{
    /* Arc length v k period + v dt, in this order: at dt = 0 the bytes of
     * the original per-scan form. */
    const double arc = CIRCLE_SPEED * (double)k * period + CIRCLE_SPEED * dt;
    const double phi = -0.5 * WORLD_PI + arc / CIRCLE_R;
    wpose_t p;
    p.x = PLAZA_X + CIRCLE_R * cos(phi);
    p.y = PLAZA_Y + CIRCLE_R * sin(phi);
    p.theta = world_wrap(phi + 0.5 * WORLD_PI);
    return p;
}

/* ------------------------------------------------------------------ */
/* table2: one pair in the plaza. */

/* Scans 0 and 1 are the paper's poses exactly; in between and around them
 * (--timing lms) the scanner moves at the constant twist that takes scan 0
 * to scan 1 in one period: the pose at scan index u is first (+) exp(u xi),
 * xi = log(rel) (SE(2) exponential: a circular arc, or a line for no turn). */
static wpose_t table2_pose(unsigned k, double period, double dt)
{
    const wpose_t first = {108.0, 96.0, world_rad(100.0)};
    const wpose_t rel = {WORLD_TABLE2_DX, WORLD_TABLE2_DY, world_rad(WORLD_TABLE2_DEG)};
    if (dt == 0.0 && k == 0u) {
        return first;
    }
    if (dt == 0.0) {
        return world_compose(first, rel);
    }
    const double u = (double)k + dt / period;
    /* log: rel = (V(w) v, w) with V(w) = [[sin w, cos w - 1], [1 - cos w, sin w]] / w. */
    const double w = rel.theta;
    const double a = sin(w) / w;
    const double b = (1.0 - cos(w)) / w;
    const double det = a * a + b * b;
    const double vx = (a * rel.x + b * rel.y) / det;
    const double vy = (-b * rel.x + a * rel.y) / det;
    const double uw = u * w;
    const double ua = sin(uw) / w;
    const double ub = (1.0 - cos(uw)) / w;
    const wpose_t step = {ua * vx - ub * vy, ub * vx + ua * vy, uw};
    return world_compose(first, step);
}

/* ------------------------------------------------------------------ */
/* corridor: two parallel walls, 7.5 m apart, 3 km long. */

#define CORRIDOR_LEFT 4.5
#define CORRIDOR_RIGHT (-3.0)
#define CORRIDOR_BACK (-60.0)
#define CORRIDOR_END 3000.0

static void build_corridor(wmap_t *m)
{
    wmap_add_segment(m, CORRIDOR_BACK, CORRIDOR_RIGHT, CORRIDOR_END, CORRIDOR_RIGHT);
    wmap_add_segment(m, CORRIDOR_BACK, CORRIDOR_LEFT, CORRIDOR_END, CORRIDOR_LEFT);
    wmap_add_segment(m, CORRIDOR_BACK, CORRIDOR_RIGHT, CORRIDOR_BACK, CORRIDOR_LEFT);
    wmap_add_segment(m, CORRIDOR_END, CORRIDOR_RIGHT, CORRIDOR_END, CORRIDOR_LEFT);
}

/* Speed 8 +- 2 m/s (period 10 s): s(t) = 8 t + (10 / pi)(1 - cos(2 pi t / 10)). */
static wpose_t corridor_pose(unsigned k, double period, double dt)
{
    const double t = scene_time(k, period, dt);
    wpose_t p;
    p.x = 8.0 * t + (10.0 / WORLD_PI) * (1.0 - cos(2.0 * WORLD_PI * t / 10.0));
    p.y = 0.0;
    p.theta = 0.0;
    return p;
}

/* ------------------------------------------------------------------ */
/* Irregular placement without rand(): splitmix64 steps from a fixed
 * state per map, so every map is the same on every run and platform. */

typedef struct {
    uint64_t state;
} pick_t;

/* Uniform in [0, 1), 53 bits. */
static double pick_unit(pick_t *p)
{
    p->state += 0x9E3779B97F4A7C15u;
    uint64_t z = p->state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* Uniform in [lo, hi). */
static double pick_range(pick_t *p, double lo, double hi)
{
    return lo + (hi - lo) * pick_unit(p);
}

/* ------------------------------------------------------------------ */
/* plaza: a round plaza 36 m across, driven around on a near-concentric
 * circle. Centre (0, 0). */

#define PLAZA_RING_R 18.0
#define PLAZA_RING_SIDES 180u
#define PLAZA_ISLAND_R 4.0
#define PLAZA_DRIVE_X 0.5 /* centre of the drive, off the plaza's by 0.58 m */
#define PLAZA_DRIVE_Y 0.3
#define PLAZA_DRIVE_R 11.0
#define PLAZA_SPEED 3.5  /* m/s, +- PLAZA_SWING over PLAZA_SWING_S */
#define PLAZA_SWING 0.5
#define PLAZA_SWING_S 8.0

/* A regular polygon of sides sides, its corners on a circle of radius r
 * about (cx, cy), the first at angle first (rad). */
static void add_ring(wmap_t *m, double cx, double cy, double r, unsigned sides, double first)
{
    static poly_t p;
    p.n = 0u;
    for (unsigned j = 0u; j < sides; j++) {
        const double a = first + 2.0 * WORLD_PI * (double)j / (double)sides;
        poly_add(&p, cx + r * cos(a), cy + r * sin(a));
    }
    wmap_add_polyline(m, p.xy, p.n, 1);
}

static void build_plaza_ring(wmap_t *m)
{
    add_ring(m, 0.0, 0.0, PLAZA_RING_R, PLAZA_RING_SIDES, 0.0);
    wmap_add_circle(m, 0.0, 0.0, PLAZA_ISLAND_R);
    /* Kiosks: polar position (m, deg), size (m), heading (deg). Inside the
     * drive at 6.5-7.5 m, outside it at 15-15.5 m. */
    static const double kiosks[][5] = {
        {15.2, 22.0, 2.2, 1.5, 112.0}, {7.0, 108.0, 1.4, 1.4, 30.0},
        {15.0, 197.0, 2.0, 1.6, 10.0}, {15.4, 296.0, 1.8, 1.2, 26.0},
        {6.8, 252.0, 1.6, 1.0, 75.0},
    };
    for (size_t j = 0u; j < sizeof kiosks / sizeof kiosks[0]; j++) {
        const double *k = kiosks[j];
        const double a = world_rad(k[1]);
        wmap_add_box(m, k[0] * cos(a), k[0] * sin(a), world_rad(k[4]), k[2], k[3]);
    }
    /* Posts (radius 0.15 m): polar (m, deg). */
    static const double posts[][2] = {
        {8.5, 41.0},  {13.6, 77.0},  {16.4, 133.0}, {8.2, 168.0},
        {13.8, 236.0}, {16.6, 331.0}, {13.7, 352.0},
    };
    for (size_t j = 0u; j < sizeof posts / sizeof posts[0]; j++) {
        const double a = world_rad(posts[j][1]);
        wmap_add_circle(m, posts[j][0] * cos(a), posts[j][0] * sin(a), 0.15);
    }
}

/* Counter-clockwise from the south point of the drive, heading east;
 * speed 3.5 + 0.5 sin(2 pi t / 8) m/s. */
static wpose_t plaza_pose(unsigned k, double period, double dt)
{
    const double t = scene_time(k, period, dt);
    const double w = 2.0 * WORLD_PI / PLAZA_SWING_S;
    const double arc = PLAZA_SPEED * t + (PLAZA_SWING / w) * (1.0 - cos(w * t));
    const double phi = -0.5 * WORLD_PI + arc / PLAZA_DRIVE_R;
    wpose_t p;
    p.x = PLAZA_DRIVE_X + PLAZA_DRIVE_R * cos(phi);
    p.y = PLAZA_DRIVE_Y + PLAZA_DRIVE_R * sin(phi);
    p.theta = world_wrap(phi + 0.5 * WORLD_PI);
    return p;
}

/* ------------------------------------------------------------------ */
/* ring: a bare 72-sided ring, radius 9 m, the scanner turning at its
 * centre. */

#define RING_R 9.0
#define RING_SIDES 72u
#define RING_RATE_DEG 18.75 /* deg/s: 0.5 deg per scan at 37.5 Hz */

static void build_bare_ring(wmap_t *m)
{
    add_ring(m, 0.0, 0.0, RING_R, RING_SIDES, 0.0);
}

static wpose_t ring_pose(unsigned k, double period, double dt)
{
    wpose_t p;
    p.x = 0.0;
    p.y = 0.0;
    p.theta = world_wrap(world_rad(RING_RATE_DEG) * scene_time(k, period, dt));
    return p;
}

/* ------------------------------------------------------------------ */
/* sparse: a featureless corridor 7 m wide with a 0.3 m post every 25-40 m. */

#define SPARSE_HALF 3.5
#define SPARSE_BACK (-50.0)
#define SPARSE_END 900.0
#define SPARSE_POST 0.3
#define SPARSE_SPEED 6.5 /* m/s, +- SPARSE_SWING over SPARSE_SWING_S */
#define SPARSE_SWING 1.5
#define SPARSE_SWING_S 9.0

static void build_sparse(wmap_t *m)
{
    wmap_add_segment(m, SPARSE_BACK, -SPARSE_HALF, SPARSE_END, -SPARSE_HALF);
    wmap_add_segment(m, SPARSE_BACK, SPARSE_HALF, SPARSE_END, SPARSE_HALF);
    wmap_add_segment(m, SPARSE_BACK, -SPARSE_HALF, SPARSE_BACK, SPARSE_HALF);
    wmap_add_segment(m, SPARSE_END, -SPARSE_HALF, SPARSE_END, SPARSE_HALF);
    /* Posts from x = 14 on, 25-40 m apart, on either side; two in five
     * stand in the wall line (half of them out of the wall), the others
     * 0.4-1.0 m clear of it. */
    pick_t pick = {0x5A55E5u};
    double x = 14.0;
    while (x < SPARSE_END - 10.0) {
        const double side = (pick_unit(&pick) < 0.5) ? 1.0 : -1.0;
        const double in_line = pick_unit(&pick);
        const double gap = pick_range(&pick, 0.4, 1.0);
        const double y = (in_line < 0.4) ? SPARSE_HALF : SPARSE_HALF - 0.5 * SPARSE_POST - gap;
        add_post(m, x, side * y, SPARSE_POST);
        x += pick_range(&pick, 25.0, 40.0);
    }
}

/* y = 0, heading east, speed 6.5 + 1.5 sin(2 pi t / 9) m/s. */
static wpose_t sparse_pose(unsigned k, double period, double dt)
{
    const double t = scene_time(k, period, dt);
    const double w = 2.0 * WORLD_PI / SPARSE_SWING_S;
    wpose_t p;
    p.x = SPARSE_SPEED * t + (SPARSE_SWING / w) * (1.0 - cos(w * t));
    p.y = 0.0;
    p.theta = 0.0;
    return p;
}

/* ------------------------------------------------------------------ */
/* highway: 10-30 m/s on a road with curves of up to 0.5 rad/s, lined with
 * buildings, posts, parked cars and walls. */

#define HIGHWAY_FROM (-80.0) /* m of road mapped before the start */
#define HIGHWAY_TO 820.0     /* m of road mapped (the path goes straight on) */

static void highway_path(wpath_t *path)
{
    const double quarter = 0.5 * WORLD_PI;
    const wpiece_t pieces[9] = {
        {100.0, 0.0},                          /* 30 m/s */
        {60.0 * quarter, 1.0 / 60.0},          /* left, 30 m/s: 0.5 rad/s */
        {97.75, 0.0},                          /* braking to 10 m/s */
        {20.0 * quarter, -1.0 / 20.0},         /* right, 10 m/s: 0.5 rad/s */
        {36.6, 0.0},                           /* accelerating */
        {150.0 * world_rad(40.0), 1.0 / 150.0}, /* left, 23-30 m/s */
        {15.3, 0.0},
        {90.0 * world_rad(45.0), -1.0 / 90.0}, /* right, 30 m/s: 0.33 rad/s */
        {300.0, 0.0},
    };
    const wpose_t start = {0.0, 0.0, 0.0};
    wpath_init(path, start, pieces, 9u, false);
}

/* 30 m/s, braking to 10 m/s for the tight right turn, back to 30 m/s,
 * then 30 m/s on (half-cosine ramps). */
static const wknot_t highway_knots[] = {
    {0.0, 30.0}, {7.0, 30.0}, {11.0, 10.0}, {14.5, 10.0}, {18.5, 30.0},
};
#define HIGHWAY_KNOTS (sizeof highway_knots / sizeof highway_knots[0])

static wpose_t highway_pose(unsigned k, double period, double dt)
{
    wpath_t path;
    highway_path(&path);
    const double s = wprofile_distance(highway_knots, HIGHWAY_KNOTS, scene_time(k, period, dt));
    return wpath_pose(&path, s, 0.0);
}

/* The mapped road sampled every 0.5 m, for the clearance of what stands
 * beside it. */
#define HIGHWAY_STEP 0.5
#define HIGHWAY_SAMPLES 1801u /* (HIGHWAY_TO - HIGHWAY_FROM) / step + 1 */

typedef struct {
    wpath_t path;
    double xy[2u * HIGHWAY_SAMPLES];
} road_t;

/* A box at arc length s of the road, lateral metres to its left (< 0:
 * right), turned by turn (rad) from the road's heading; kept only when it
 * stays clear metres away from the whole mapped road. */
static void highway_box(wmap_t *m, const road_t *road, double s, double lateral, double turn,
                        double length, double width, double clear)
{
    const wpose_t at = wpath_pose(&road->path, s, lateral);
    const double reach = 0.5 * hypot(length, width);
    wmap_t box;
    wmap_init(&box);
    wmap_add_box(&box, at.x, at.y, at.theta + turn, length, width);
    bool ok = true;
    for (size_t i = 0u; i < HIGHWAY_SAMPLES && ok; i++) {
        const double x = road->xy[2u * i];
        const double y = road->xy[2u * i + 1u];
        if (hypot(x - at.x, y - at.y) - reach < clear) {
            ok = wmap_clearance(&box, x, y) >= clear;
        }
    }
    wmap_free(&box);
    if (ok) {
        wmap_add_box(m, at.x, at.y, at.theta + turn, length, width);
    }
}

static void build_highway(wmap_t *m)
{
    static road_t road;
    highway_path(&road.path);
    for (size_t i = 0u; i < HIGHWAY_SAMPLES; i++) {
        const wpose_t p = wpath_pose(&road.path, HIGHWAY_FROM + HIGHWAY_STEP * (double)i, 0.0);
        road.xy[2u * i] = p.x;
        road.xy[2u * i + 1u] = p.y;
    }
    /* One pick per statement: the order of the picks is the order of the
     * statements (C leaves the order of arguments unspecified). */
    pick_t pick = {0x4167u};
    for (int side = -1; side <= 1; side += 2) {
        const double dir = (double)side;
        /* Front row: facades 9-14 m from the lane centre, 10-30 m long,
         * 3-12 m gaps; one in four turned 10-25 deg. */
        double s = HIGHWAY_FROM;
        while (s < HIGHWAY_TO) {
            const double len = pick_range(&pick, 10.0, 30.0);
            const double depth = pick_range(&pick, 8.0, 14.0);
            const double setback = pick_range(&pick, 9.0, 14.0);
            const bool turned = pick_unit(&pick) < 0.25;
            const double turn = turned ? dir * world_rad(pick_range(&pick, 10.0, 25.0)) : 0.0;
            highway_box(m, &road, s + 0.5 * len, dir * (setback + 0.5 * depth), turn, len, depth,
                        6.0);
            s += len + pick_range(&pick, 3.0, 12.0);
        }
        /* Back row: 26-36 m out, 15-40 m long, 12 m deep. */
        s = HIGHWAY_FROM;
        while (s < HIGHWAY_TO) {
            const double len = pick_range(&pick, 15.0, 40.0);
            const double setback = pick_range(&pick, 26.0, 36.0);
            highway_box(m, &road, s + 0.5 * len, dir * (setback + 6.0), 0.0, len, 12.0, 8.0);
            s += len + pick_range(&pick, 5.0, 20.0);
        }
        /* Walls at 20-60 deg to the road, 17-22 m out, 6-14 m long. */
        s = HIGHWAY_FROM + pick_range(&pick, 0.0, 40.0);
        while (s < HIGHWAY_TO) {
            const double angle = world_rad(pick_range(&pick, 20.0, 60.0));
            const double turn = (pick_unit(&pick) < 0.5) ? angle : -angle;
            const double out = pick_range(&pick, 17.0, 22.0);
            const double len = pick_range(&pick, 6.0, 14.0);
            highway_box(m, &road, s, dir * out, turn, len, 0.3, 6.0);
            s += pick_range(&pick, 45.0, 80.0);
        }
        /* Posts 5-6.5 m out, every 15-35 m (0.3 m square). */
        s = HIGHWAY_FROM + pick_range(&pick, 0.0, 15.0);
        while (s < HIGHWAY_TO) {
            const double out = pick_range(&pick, 5.0, 6.5);
            highway_box(m, &road, s, dir * out, 0.0, 0.3, 0.3, 3.5);
            s += pick_range(&pick, 15.0, 35.0);
        }
        /* Parked cars, 6 m out, in groups of 1-4 every 50-110 m. */
        s = HIGHWAY_FROM + pick_range(&pick, 10.0, 50.0);
        while (s < HIGHWAY_TO) {
            const unsigned cars = 1u + (unsigned)(4.0 * pick_unit(&pick));
            for (unsigned j = 0u; j < cars; j++) {
                highway_box(m, &road, s + 6.5 * (double)j, dir * 6.0, 0.0, WORLD_CAR_LENGTH,
                            WORLD_CAR_WIDTH, 4.0);
            }
            s += pick_range(&pick, 50.0, 110.0);
        }
    }
}

/* ------------------------------------------------------------------ */
/* Busy streets (issue 17): traffic, platoon, overtake, crossing,
 * pedestrians and stopgo. Straight roads along +x (the crossing adds one
 * along y); the ego's lane centre is y = 0 and lanes are 3.5 m wide
 * (LANE_OFFSET). Every mover is a closed-form function of time, and the
 * movers that share a lane share the period of their speed swings, so
 * their gaps stay bounded at any time (docs/synthetic-worlds.md gives
 * the ranges). */

/* Distance driven from t = 0 at the speed mean + amp sin(2 pi t / period_s
 * + phase), m. */
static double swing_distance(double mean, double amp, double period_s, double phase, double t)
{
    const double w = 2.0 * WORLD_PI / period_s;
    return mean * t + (amp / w) * (cos(phase) - cos(w * t + phase));
}

/* A mover of the given size at (x, y, heading). */
static void put_mover(wmover_t *m, double x, double y, double heading, double length,
                      double width)
{
    m->x = x;
    m->y = y;
    m->heading = heading;
    m->length = length;
    m->width = width;
}

/* A straight street along x: per side (0 right, y < 0; 1 left, y > 0)
 * the facade line, the line of kerb posts and trees and the centre line
 * of parked cars (0: none). */
typedef struct {
    double from, to; /* x mapped, m */
    double facade[2];
    double posts[2];
    double parked[2];
    uint64_t seed; /* splitmix64 state of the map's draws */
} street_t;

/* A row of buildings from `from` to `to` along x (along_y false) or along
 * y (a cross street), whose facades stand 0-1.5 m behind the line
 * (y or x) = facade, away from the road (dir -1: the road is on the
 * higher side of them, +1: the lower); 8-24 m long, 12 m deep, 3-10 m
 * gaps, half of them with recesses. */
static void building_row(wmap_t *m, pick_t *pick, double from, double to, double facade,
                         double dir, bool along_y)
{
    double at = from;
    while (at < to) {
        const double len = pick_range(pick, 8.0, 24.0);
        const double back = pick_range(pick, 0.0, 1.5);
        const bool notched = pick_unit(pick) < 0.5;
        const double near = facade + dir * back;
        const double far = near + dir * 12.0;
        const double lo = fmin(near, far);
        const double hi = fmax(near, far);
        unsigned edge = 0u;
        if (notched) {
            edge = along_y ? ((dir < 0.0) ? (unsigned)EDGE_E : (unsigned)EDGE_W)
                           : ((dir < 0.0) ? (unsigned)EDGE_N : (unsigned)EDGE_S);
        }
        if (along_y) {
            add_building(m, lo, at, hi, at + len, edge, 5.0, 1.5, 0.6);
        } else {
            add_building(m, at, lo, at + len, hi, edge, 5.0, 1.5, 0.6);
        }
        at += len + pick_range(pick, 3.0, 10.0);
    }
}

/* Posts and trees along y = at from x0 to x1, every 8-20 m. */
static void kerb_row(wmap_t *m, pick_t *pick, double x0, double x1, double at)
{
    double x = x0 + pick_range(pick, 0.0, 8.0);
    while (x < x1) {
        if (pick_unit(pick) < 0.5) {
            add_post(m, x, at, POST_SIZE);
        } else {
            wmap_add_circle(m, x, at, TREE_R);
        }
        x += pick_range(pick, 8.0, 20.0);
    }
}

/* Parked cars along y = at, in groups of 1-3 every 15-50 m. */
static void parked_row(wmap_t *m, pick_t *pick, double x0, double x1, double at)
{
    double x = x0 + pick_range(pick, 0.0, 30.0);
    while (x < x1) {
        const unsigned cars = 1u + (unsigned)(3.0 * pick_unit(pick));
        for (unsigned j = 0u; j < cars; j++) {
            wmap_add_box(m, x + 6.0 * (double)j, at, 0.0, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
        }
        x += 6.0 * (double)cars + pick_range(pick, 15.0, 50.0);
    }
}

static void build_street(wmap_t *m, const street_t *st)
{
    pick_t pick = {st->seed};
    for (size_t side = 0u; side < 2u; side++) {
        const double dir = (side == 0u) ? -1.0 : 1.0;
        building_row(m, &pick, st->from, st->to, st->facade[side], dir, false);
        if (st->posts[side] != 0.0) {
            kerb_row(m, &pick, st->from, st->to, st->posts[side]);
        }
        if (st->parked[side] != 0.0) {
            parked_row(m, &pick, st->from, st->to, st->parked[side]);
        }
    }
}

/* ---- traffic: a two-way street, seven cars ahead in our lane and seven
 * oncoming. Every speed swings with period TRAFFIC_SWING_S about
 * 7.5 m/s: the ego's by 4.5 m/s (3-12 m/s), the others' by 2.5-3.5 m/s
 * (4-11 m/s). */

#define TRAFFIC_SWING_S 16.0
#define TRAFFIC_MEAN 7.5
#define TRAFFIC_WEAVE 0.3   /* m, the ego's sway in its lane */
#define TRAFFIC_WEAVE_M 60.0 /* m of road per sway */

static void build_traffic(wmap_t *m)
{
    /* Parked cars 3.4 m right of our lane and left of the oncoming one. */
    const street_t st = {-60.0, 300.0, {-9.0, 12.5}, {-5.0, 8.5}, {-3.4, LANE_OFFSET + 3.4},
                         0x7AFF1Cu};
    build_street(m, &st);
}

/* The ego's distance along the road; it sways 0.3 m in its lane. */
static wpose_t traffic_pose(unsigned k, double period, double dt)
{
    const double t = scene_time(k, period, dt);
    const double x = swing_distance(TRAFFIC_MEAN, 4.5, TRAFFIC_SWING_S, 0.0, t);
    const double wave = 2.0 * WORLD_PI / TRAFFIC_WEAVE_M;
    wpose_t p;
    p.x = x;
    p.y = TRAFFIC_WEAVE * sin(wave * x);
    p.theta = atan(TRAFFIC_WEAVE * wave * cos(wave * x));
    return p;
}

typedef struct {
    double x0;    /* m, position at t = 0 (ahead) or meeting offset (oncoming) */
    double amp;   /* m/s, speed swing */
    double phase; /* rad */
} swinger_t;

/* Ahead: the nearest 8.9-27 m ahead of the scanner, 8.5 m or more
 * between centres (checked by world_check scenarios). */
static const swinger_t traffic_ahead[] = {
    {24.0, 3.5, 0.9},   {36.0, 3.0, 0.3},   {51.0, 3.5, -0.5}, {73.0, 2.5, 0.8},
    {86.0, 3.0, -0.2},  {100.0, 3.5, 0.5},  {122.0, 3.0, -0.8},
};
/* Oncoming: at x0 at t = 0, one meets the scanner every 3 s or so. */
static const swinger_t traffic_oncoming[] = {
    {35.0, 3.0, 0.4},   {80.0, 3.5, 2.0},  {125.0, 2.5, -1.0}, {170.0, 3.0, 1.2},
    {215.0, 3.5, -0.3}, {260.0, 3.0, 2.6}, {305.0, 2.5, 0.8},
};
#define TRAFFIC_AHEAD (sizeof traffic_ahead / sizeof traffic_ahead[0])
#define TRAFFIC_ONCOMING (sizeof traffic_oncoming / sizeof traffic_oncoming[0])
_Static_assert(TRAFFIC_AHEAD + TRAFFIC_ONCOMING <= WORLD_MAX_MOVERS, "traffic: too many movers");

static size_t traffic_movers(double t, wmover_t *out)
{
    size_t n = 0u;
    for (size_t i = 0u; i < TRAFFIC_AHEAD; i++) {
        const swinger_t *c = &traffic_ahead[i];
        const double x = c->x0 + swing_distance(TRAFFIC_MEAN, c->amp, TRAFFIC_SWING_S, c->phase, t);
        put_mover(&out[n++], x, 0.0, 0.0, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
    }
    for (size_t i = 0u; i < TRAFFIC_ONCOMING; i++) {
        const swinger_t *c = &traffic_oncoming[i];
        const double x = c->x0 - swing_distance(TRAFFIC_MEAN, c->amp, TRAFFIC_SWING_S, c->phase, t);
        put_mover(&out[n++], x, LANE_OFFSET, WORLD_PI, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
    }
    return n;
}

/* ---- platoon: three lanes our way (y = -3.5, 0, 3.5), two trucks in
 * each, the first with its rear face 7-11 m ahead of the scanner; each
 * gap to the ego swings by at most 1.2 m over 17-23 s, so every truck is
 * within 0.45 m/s of the ego's 7-11 m/s. */

#define PLATOON_SPEED 9.0
#define PLATOON_SWING 2.0
#define PLATOON_SWING_S 14.0

static void build_platoon(wmap_t *m)
{
    const street_t st = {-60.0, 320.0, {-11.5, 11.5}, {-8.6, 8.6}, {-7.0, 7.0}, 0x9147u};
    build_street(m, &st);
}

static double platoon_x(double t)
{
    return swing_distance(PLATOON_SPEED, PLATOON_SWING, PLATOON_SWING_S, 0.0, t);
}

static wpose_t platoon_pose(unsigned k, double period, double dt)
{
    wpose_t p;
    p.x = platoon_x(scene_time(k, period, dt));
    p.y = 0.0;
    p.theta = 0.0;
    return p;
}

typedef struct {
    double lane;     /* y, m */
    double gap;      /* m, mean distance of the centre ahead of the scanner */
    double amp;      /* m, swing of that distance */
    double period_s; /* s */
    double phase;    /* rad */
} follower_t;

static const follower_t platoon_trucks[] = {
    {0.0, 14.0, 1.0, 20.0, 0.0},
    {-LANE_OFFSET, 15.5, 1.2, 17.0, 1.3},
    {LANE_OFFSET, 16.0, 1.1, 23.0, -2.0},
    {0.0, 29.0, 0.8, 19.0, 2.2},
    {-LANE_OFFSET, 31.0, 1.0, 21.0, -0.7},
    {LANE_OFFSET, 31.5, 0.9, 18.0, 0.9},
};
#define PLATOON_TRUCKS (sizeof platoon_trucks / sizeof platoon_trucks[0])
_Static_assert(PLATOON_TRUCKS <= WORLD_MAX_MOVERS, "platoon: too many movers");

static size_t platoon_movers(double t, wmover_t *out)
{
    const double ego = platoon_x(t);
    for (size_t i = 0u; i < PLATOON_TRUCKS; i++) {
        const follower_t *f = &platoon_trucks[i];
        const double gap = f->gap + f->amp * sin(2.0 * WORLD_PI * t / f->period_s + f->phase);
        put_mover(&out[i], ego + gap, f->lane, 0.0, WORLD_TRUCK_LENGTH, WORLD_TRUCK_WIDTH);
    }
    return PLATOON_TRUCKS;
}

/* ---- overtake: two lanes our way; a truck comes from behind in the
 * left lane at 17 m/s, is alongside the scanner (8-10 m/s) at t = 6 s,
 * slows to 12 m/s and changes into our lane from t = 9 to 12 s, 15 m
 * ahead. */

#define OVERTAKE_MEET_S 6.0
#define OVERTAKE_CHANGE_S 9.0 /* start of the lane change */
#define OVERTAKE_CHANGE_LEN_S 3.0

static const wknot_t overtake_knots[] = {{0.0, 20.0}, {6.5, 20.0}, {9.5, 12.0}};
#define OVERTAKE_KNOTS (sizeof overtake_knots / sizeof overtake_knots[0])

static void build_overtake(wmap_t *m)
{
    const street_t st = {-60.0, 250.0, {-9.0, 10.0}, {-5.0, 7.0}, {-3.4, 0.0}, 0x0E57u};
    build_street(m, &st);
}

static double overtake_ego_x(double t)
{
    return swing_distance(9.0, 1.0, 12.0, 0.0, t);
}

static wpose_t overtake_pose(unsigned k, double period, double dt)
{
    wpose_t p;
    p.x = overtake_ego_x(scene_time(k, period, dt));
    p.y = 0.0;
    p.theta = 0.0;
    return p;
}

static size_t overtake_movers(double t, wmover_t *out)
{
    /* Alongside (same x) at OVERTAKE_MEET_S. */
    const double start = overtake_ego_x(OVERTAKE_MEET_S) -
                         wprofile_distance(overtake_knots, OVERTAKE_KNOTS, OVERTAKE_MEET_S);
    const double x = start + wprofile_distance(overtake_knots, OVERTAKE_KNOTS, t);
    const double v = wprofile_speed(overtake_knots, OVERTAKE_KNOTS, t);
    /* Lane change: the lateral offset falls along a half cosine; the
     * truck heads along its velocity. */
    double y = LANE_OFFSET;
    double vy = 0.0;
    const double u = (t - OVERTAKE_CHANGE_S) / OVERTAKE_CHANGE_LEN_S;
    if (u >= 1.0) {
        y = 0.0;
    } else if (u > 0.0) {
        y = 0.5 * LANE_OFFSET * (1.0 + cos(WORLD_PI * u));
        vy = -0.5 * LANE_OFFSET * WORLD_PI / OVERTAKE_CHANGE_LEN_S * sin(WORLD_PI * u);
    }
    put_mover(&out[0], x, y, atan2(vy, v), WORLD_TRUCK_LENGTH, WORLD_TRUCK_WIDTH);
    return 1u;
}

/* ---- crossing: our street along x meets a cross street along y at
 * x = CROSS_X. The ego slows from 8 to 1.5 m/s before it (t 4-8 s),
 * creeps, then crosses at 8 m/s (t 13-14 s) while four cars each way
 * have passed in front at 9 (northbound) and 10 m/s (southbound). */

#define CROSS_X 70.0
#define CROSS_NORTH 9.0  /* m/s, lane x = CROSS_X + 1.75 */
#define CROSS_SOUTH 10.0 /* m/s, lane x = CROSS_X - 1.75 */

static const wknot_t crossing_knots[] = {
    {0.0, 8.0}, {4.0, 8.0}, {8.0, 1.5}, {10.0, 1.5}, {13.0, 8.0},
};
#define CROSSING_KNOTS (sizeof crossing_knots / sizeof crossing_knots[0])

static void build_crossing(wmap_t *m)
{
    pick_t pick = {0xC055u};
    const double gap = 8.5; /* facades from the cross street's centre line */
    /* Along our street: facades at y = -7 (south) and 11 (north). */
    building_row(m, &pick, -80.0, CROSS_X - gap - 12.0, -7.0, -1.0, false);
    building_row(m, &pick, CROSS_X + gap, 300.0, -7.0, -1.0, false);
    building_row(m, &pick, -80.0, CROSS_X - gap - 12.0, 11.0, 1.0, false);
    building_row(m, &pick, CROSS_X + gap, 300.0, 11.0, 1.0, false);
    /* Along the cross street, beyond our street's facades. */
    building_row(m, &pick, -200.0, -7.0 - 12.0, CROSS_X - gap, -1.0, true);
    building_row(m, &pick, -200.0, -7.0 - 12.0, CROSS_X + gap, 1.0, true);
    building_row(m, &pick, 11.0, 200.0, CROSS_X - gap, -1.0, true);
    building_row(m, &pick, 11.0, 200.0, CROSS_X + gap, 1.0, true);
    /* Posts and trees on the kerbs, traffic-light posts at the corners. */
    kerb_row(m, &pick, -80.0, CROSS_X - 7.0, -5.0);
    kerb_row(m, &pick, CROSS_X + 7.0, 300.0, -5.0);
    kerb_row(m, &pick, -80.0, CROSS_X - 7.0, 8.5);
    kerb_row(m, &pick, CROSS_X + 7.0, 300.0, 8.5);
    parked_row(m, &pick, -80.0, CROSS_X - 20.0, -3.4);
    add_post(m, CROSS_X - 5.0, -5.0, POST_SIZE);
    add_post(m, CROSS_X + 5.0, -5.0, POST_SIZE);
    add_post(m, CROSS_X - 5.0, 8.5, POST_SIZE);
    add_post(m, CROSS_X + 5.0, 8.5, POST_SIZE);
}

static wpose_t crossing_pose(unsigned k, double period, double dt)
{
    wpose_t p;
    p.x = wprofile_distance(crossing_knots, CROSSING_KNOTS, scene_time(k, period, dt));
    p.y = 0.0;
    p.theta = 0.0;
    return p;
}

/* When each cross car is on our lane's centre line (y = 0), s. */
static const double cross_north[] = {3.0, 5.8, 8.4, 11.2};
static const double cross_south[] = {4.4, 7.0, 9.8, 12.0};
#define CROSS_EACH (sizeof cross_north / sizeof cross_north[0])
_Static_assert(sizeof cross_south == sizeof cross_north, "crossing: as many each way");
_Static_assert(2u * CROSS_EACH <= WORLD_MAX_MOVERS, "crossing: too many movers");

static size_t crossing_movers(double t, wmover_t *out)
{
    size_t n = 0u;
    for (size_t i = 0u; i < CROSS_EACH; i++) {
        put_mover(&out[n++], CROSS_X + 0.5 * LANE_OFFSET, CROSS_NORTH * (t - cross_north[i]),
                  0.5 * WORLD_PI, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
    }
    for (size_t i = 0u; i < CROSS_EACH; i++) {
        put_mover(&out[n++], CROSS_X - 0.5 * LANE_OFFSET, -CROSS_SOUTH * (t - cross_south[i]),
                  -0.5 * WORLD_PI, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
    }
    return n;
}

/* ---- pedestrians: a one-way shopping street 13 m between facades,
 * driven at 1-3 m/s; alleys through both rows every 16-18 m; people
 * walking both ways on the pavements and across the street from alley
 * to alley. */

#define PED_FACADE 6.5  /* facades at y = +-6.5 */
#define PED_POSTS 3.2   /* posts and trees at y = +-3.2 */
#define PED_ALLEY_W 3.5 /* m */

static const double ped_alleys[] = {12.0, 30.0, 47.0, 63.0, 80.0, 97.0};
#define PED_ALLEYS (sizeof ped_alleys / sizeof ped_alleys[0])

static void build_pedestrians(wmap_t *m)
{
    /* Shops between the alleys (and before the first, after the last),
     * split into fronts of 5-9 m with recessed doors. */
    pick_t pick = {0x9ED5u};
    for (size_t side = 0u; side < 2u; side++) {
        const double dir = (side == 0u) ? -1.0 : 1.0;
        for (size_t a = 0u; a <= PED_ALLEYS; a++) {
            const double x0 = (a == 0u) ? -60.0 : ped_alleys[a - 1u] + 0.5 * PED_ALLEY_W;
            const double x1 = (a == PED_ALLEYS) ? 160.0 : ped_alleys[a] - 0.5 * PED_ALLEY_W;
            double x = x0;
            while (x < x1 - 1.0) {
                const double want = pick_range(&pick, 5.0, 9.0);
                const double len = (x1 - x < want + 3.0) ? x1 - x : want;
                const double near = dir * PED_FACADE;
                const double far = dir * (PED_FACADE + 10.0);
                const unsigned edge = (side == 0u) ? (unsigned)EDGE_N : (unsigned)EDGE_S;
                add_building(m, x, fmin(near, far), x + len, fmax(near, far), edge, len, 1.4,
                             0.5);
                x += len;
            }
        }
        /* Posts and trees every 5-9 m, none in front of an alley. */
        double x = -55.0;
        while (x < 155.0) {
            bool clear = true;
            for (size_t a = 0u; a < PED_ALLEYS; a++) {
                clear = clear && fabs(x - ped_alleys[a]) > 0.5 * PED_ALLEY_W + 0.5;
            }
            const bool tree = pick_unit(&pick) < 0.4;
            if (clear && tree) {
                wmap_add_circle(m, x, dir * PED_POSTS, TREE_R);
            } else if (clear) {
                add_post(m, x, dir * PED_POSTS, POST_SIZE);
            }
            x += pick_range(&pick, 5.0, 9.0);
        }
    }
}

#define PED_EGO_SPEED 2.0 /* m/s, +- 1 over 10 s */

static double pedestrians_ego_x(double t)
{
    return swing_distance(PED_EGO_SPEED, 1.0, 10.0, 0.0, t);
}

static wpose_t pedestrians_pose(unsigned k, double period, double dt)
{
    wpose_t p;
    p.x = pedestrians_ego_x(scene_time(k, period, dt));
    p.y = 0.0;
    p.theta = 0.0;
    return p;
}

typedef struct {
    double x0, y0;   /* m, at t = 0 */
    double heading;  /* rad */
    double speed;    /* m/s */
} walker_t;

/* On the pavements: one speed per line (y), so nobody walks into anyone
 * on the same line; eastbound at |y| = 4.1, westbound at |y| = 5.2. */
static const walker_t ped_walkers[] = {
    {-4.0, -4.1, 0.0, 1.2},       {14.0, -4.1, 0.0, 1.2},      {37.0, -4.1, 0.0, 1.2},
    {25.0, -5.2, WORLD_PI, 1.5},  {52.0, -5.2, WORLD_PI, 1.5}, {78.0, -5.2, WORLD_PI, 1.5},
    {2.0, 4.1, 0.0, 1.0},         {33.0, 4.1, 0.0, 1.0},       {26.0, 5.2, WORLD_PI, 1.8},
    {60.0, 5.2, WORLD_PI, 1.8},   {95.0, 5.2, WORLD_PI, 1.8},
};
#define PED_WALKERS (sizeof ped_walkers / sizeof ped_walkers[0])

/* Across: alley x, direction (+1 north), speed, and when the walker is on
 * y = 0 (the scanner is then 10-38 m short of the alley). The two on one
 * alley walk the same way at the same speed, so they never meet. */
static const double ped_crossers[][4] = {
    {12.0, 1.0, 1.4, 1.0},  {30.0, -1.0, 1.1, 5.0}, {47.0, 1.0, 1.6, 10.0},
    {47.0, 1.0, 1.6, 15.0}, {63.0, 1.0, 1.2, 17.5}, {80.0, -1.0, 1.7, 21.0},
};
#define PED_CROSSERS (sizeof ped_crossers / sizeof ped_crossers[0])
_Static_assert(PED_WALKERS + PED_CROSSERS <= WORLD_MAX_MOVERS, "pedestrians: too many movers");

static size_t pedestrians_movers(double t, wmover_t *out)
{
    size_t n = 0u;
    for (size_t i = 0u; i < PED_WALKERS; i++) {
        const walker_t *w = &ped_walkers[i];
        put_mover(&out[n++], w->x0 + w->speed * t * cos(w->heading), w->y0, w->heading,
                  WORLD_PED_SIZE, WORLD_PED_SIZE);
    }
    for (size_t i = 0u; i < PED_CROSSERS; i++) {
        const double *c = ped_crossers[i];
        put_mover(&out[n++], c[0], c[1] * c[2] * (t - c[3]), c[1] * 0.5 * WORLD_PI,
                  WORLD_PED_SIZE, WORLD_PED_SIZE);
    }
    return n;
}

/* ---- stopgo: a queue on a two-way street. Every car of the queue and
 * the ego drive the same stop-and-go profile, each car ahead of us
 * STOPGO_LEAD_S earlier than the one behind it, so the queue starts and
 * stops front first and its gaps never shrink below the 7 m at rest.
 * The ego stands still from 5 to 10 s and from 17.5 to 21 s. */

#define STOPGO_LEAD_S 1.0
#define STOPGO_QUEUE 5u
#define STOPGO_SPACING 7.0 /* m between centres at rest */

static const wknot_t stopgo_knots[] = {
    {0.0, 5.0},  {2.0, 5.0},  {5.0, 0.0},  {10.0, 0.0}, {13.0, 4.0},
    {15.0, 4.0}, {17.5, 0.0}, {21.0, 0.0}, {24.0, 5.0},
};
#define STOPGO_KNOTS (sizeof stopgo_knots / sizeof stopgo_knots[0])

/* Oncoming at 6-9 m/s. */
static const swinger_t stopgo_oncoming[] = {
    {40.0, 1.5, 0.3},  {75.0, 1.5, 2.1},   {110.0, 1.5, -0.9}, {145.0, 1.5, 1.4},
    {180.0, 1.5, -2.2}, {215.0, 1.5, 0.7}, {250.0, 1.5, 2.8},
};
#define STOPGO_ONCOMING (sizeof stopgo_oncoming / sizeof stopgo_oncoming[0])
_Static_assert(STOPGO_QUEUE + STOPGO_ONCOMING <= WORLD_MAX_MOVERS, "stopgo: too many movers");

static void build_stopgo(wmap_t *m)
{
    const street_t st = {-60.0, 160.0, {-9.0, 12.5}, {-5.0, 8.5}, {-3.4, LANE_OFFSET + 3.4},
                         0x5709u};
    build_street(m, &st);
}

/* Standing still, the profile's distance is the same double at every
 * time (wprofile_distance adds 0 over a zero-speed span), so the truth
 * pairs are exactly 0. */
static wpose_t stopgo_pose(unsigned k, double period, double dt)
{
    wpose_t p;
    p.x = wprofile_distance(stopgo_knots, STOPGO_KNOTS, scene_time(k, period, dt));
    p.y = 0.0;
    p.theta = 0.0;
    return p;
}

static size_t stopgo_movers(double t, wmover_t *out)
{
    size_t n = 0u;
    for (unsigned i = 0u; i < STOPGO_QUEUE; i++) {
        const double lead = STOPGO_LEAD_S * (double)(i + 1u);
        const double x = STOPGO_SPACING * (double)(i + 1u) +
                         wprofile_distance(stopgo_knots, STOPGO_KNOTS, t + lead);
        put_mover(&out[n++], x, 0.0, 0.0, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
    }
    for (size_t i = 0u; i < STOPGO_ONCOMING; i++) {
        const swinger_t *c = &stopgo_oncoming[i];
        const double x = c->x0 - swing_distance(TRAFFIC_MEAN, c->amp, TRAFFIC_SWING_S, c->phase, t);
        put_mover(&out[n++], x, LANE_OFFSET, WORLD_PI, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH);
    }
    return n;
}

/* ------------------------------------------------------------------ */

static const wscenario_t scenarios[] = {
    {"campus", "campus drive, 0-10 m/s, two corners, into the corridor (929 scans)", 929u, 0u,
     build_campus, campus_pose, NULL},
    {"circle", "27 m circle around the plaza fountain at 3 m/s (1200 scans)", 1200u, 0u,
     build_campus, circle_pose, NULL},
    {"corridor", "3 km corridor, 7.5 m wide, driven straight at 6-10 m/s (700 scans)", 700u,
     0u, build_corridor, corridor_pose, NULL},
    {"table2", "the paper's Table 2 pair: 25.07 deg, (-2.439, 3.568) m (2 scans)", 2u, 2u,
     build_campus, table2_pose, NULL},
    {"fast", "ring road at 2-3 m and up to ~10 deg per scan (200 scans)", 200u, 0u,
     build_campus, fast_pose, NULL},
    {"busy", "the campus drive with a car ahead and oncoming traffic (929 scans)", 929u, 0u,
     build_campus, campus_pose, busy_movers},
    {"plaza", "round plaza, 36 m across, driven round on an 11 m circle at 3-4 m/s (600 scans)",
     600u, 0u, build_plaza_ring, plaza_pose, NULL},
    {"ring", "bare 72-sided ring, 9 m radius, the scanner turning at its centre (200 scans)",
     200u, 0u, build_bare_ring, ring_pose, NULL},
    {"sparse", "featureless 7 m corridor, a post every 25-40 m, at 5-8 m/s (700 scans)", 700u,
     0u, build_sparse, sparse_pose, NULL},
    {"highway", "10-30 m/s, curves up to 0.5 rad/s, buildings, cars, posts (900 scans)", 900u,
     0u, build_highway, highway_pose, NULL},
    {"traffic", "two-way street, 7 cars ahead at 4-11 m/s, 7 oncoming; ego 3-12 m/s (900 scans)",
     900u, 0u, build_traffic, traffic_pose, traffic_movers},
    {"platoon", "3 lanes of trucks 7-11 m ahead within 0.5 m/s of our 7-11 m/s (900 scans)",
     900u, 0u, build_platoon, platoon_pose, platoon_movers},
    {"overtake", "a 12 m truck overtakes on the left at t = 6 s and cuts in (600 scans)", 600u,
     0u, build_overtake, overtake_pose, overtake_movers},
    {"crossing", "an intersection: slowing to 1.5 m/s while 8 cars cross ahead (750 scans)",
     750u, 0u, build_crossing, crossing_pose, crossing_movers},
    {"pedestrians", "shopping street at 1-3 m/s, 17 pedestrians walking and crossing (900 scans)",
     900u, 0u, build_pedestrians, pedestrians_pose, pedestrians_movers},
    {"stopgo", "stop-and-go queue: standing still 5-10 s and 17.5-21 s, traffic moving (900 scans)",
     900u, 0u, build_stopgo, stopgo_pose, stopgo_movers},
};

size_t wscenario_count(void)
{
    return sizeof scenarios / sizeof scenarios[0];
}

const wscenario_t *wscenario_at(size_t index)
{
    return (index < wscenario_count()) ? &scenarios[index] : NULL;
}

const wscenario_t *wscenario_find(const char *name)
{
    for (size_t i = 0u; i < wscenario_count(); i++) {
        if (strcmp(scenarios[i].name, name) == 0) {
            return &scenarios[i];
        }
    }
    return NULL;
}
