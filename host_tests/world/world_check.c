/* world_check.c - checks of lmsworld's pieces and outputs (ctest label
 * "world"). Plain C, no Unity: every failed check prints one line to
 * stderr and the program exits 1.
 *
 *   world_check raycast              ray caster against closed-form ranges
 *   world_check paths                path pieces, loop closure, speed profiles
 *   world_check scenarios            clearance and motion limits of every
 *                                    scenario (prints a survey)
 *   world_check pairs TRUTH POSES N PERIOD SKIP
 *                                    truth file consistent with the TUM poses
 *   world_check table2 TRUTH         the pair equals the paper's Table 2
 *   world_check timing               --timing lms: beam times, and casts
 *                                    against closed forms under motion
 *   world_check decode SCANS SCENARIO RES UNIT MAX_RANGE SKIP [TIMING]
 *                                    `lmsego scans` output of a noise-free
 *                                    stream equals freshly cast ranges
 *                                    (TIMING lms: each value cast on the
 *                                    whole map at its own time)
 *   world_check objects OBJECTS SCENARIO RES MAX_RANGE SKIP TIMING [VEL_TOL]
 *                                    lmsworld --objects: poses against the
 *                                    scenario, stable ids, velocities
 *                                    against positions differenced over two
 *                                    scan periods (within VEL_TOL m/s, 0.02
 *                                    by default), returns recounted on the
 *                                    whole map
 *   world_check standstill TRUTH OBJECTS MIN_PAIRS
 *                                    at least MIN_PAIRS consecutive pairs of
 *                                    exactly zero motion while objects in
 *                                    view move, and some motion elsewhere
 */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lms_proto.h"
#include "world_geom.h"
#include "world_map.h"
#include "world_path.h"
#include "world_scan.h"
#include "world_scenario.h"

static unsigned failures;

static void fail(const char *what, double got, double want)
{
    if (failures < 20u) {
        (void)fprintf(stderr, "FAIL %s: got %.12g, want %.12g\n", what, got, want);
    }
    failures++;
}

/* got == want within tol; two infinities are equal. */
static void expect_near(const char *what, double got, double want, double tol)
{
    if (isinf(want) || isinf(got)) {
        if (!(isinf(want) && isinf(got))) {
            fail(what, got, want);
        }
        return;
    }
    if (!(fabs(got - want) <= tol)) {
        fail(what, got, want);
    }
}

static void expect_true(const char *what, bool ok)
{
    if (!ok) {
        fail(what, 0.0, 1.0);
    }
}

/* The SE(2) operations written out again from carmenlog.py, so that the
 * checks do not lean on world_geom.c: a (+) b and inverse(a) (+) b. */
static wpose_t ref_compose(wpose_t a, wpose_t b)
{
    const wpose_t out = {a.x + cos(a.theta) * b.x - sin(a.theta) * b.y,
                         a.y + sin(a.theta) * b.x + cos(a.theta) * b.y,
                         atan2(sin(a.theta + b.theta), cos(a.theta + b.theta))};
    return out;
}

static wpose_t ref_between(wpose_t a, wpose_t b)
{
    const double c = cos(a.theta);
    const double s = sin(a.theta);
    const double dx = b.x - a.x;
    const double dy = b.y - a.y;
    const wpose_t out = {c * dx + s * dy, -s * dx + c * dy,
                         atan2(sin(b.theta - a.theta), cos(b.theta - a.theta))};
    return out;
}

/* Difference of two angles, wrapped. */
static double angle_diff(double a, double b)
{
    return atan2(sin(a - b), cos(a - b));
}

/* ------------------------------------------------------------------ */
/* raycast */

#define RES_DEG 0.5
#define BEAMS 361u

/* Scanner-frame angle of beam i, radians. */
static double beam_phi(unsigned i)
{
    return ((double)i * RES_DEG - 90.0) * (WORLD_PI / 180.0);
}

static void cast_all(const wmap_t *map, wpose_t pose, double *ranges)
{
    wmap_t active;
    wmap_init(&active);
    world_scan_prepare(map, NULL, 0u, pose, 1e6, &active);
    world_scan_cast(&active, pose, BEAMS, RES_DEG, ranges);
    wmap_free(&active);
}

/* A straight wall 5 m ahead, perpendicular to the forward axis, 2 km
 * long: range d / cos(phi) while the hit stays on the wall. */
static void check_wall(void)
{
    const wpose_t pose = {3.2, -1.7, 0.6};
    const double d = 5.0;
    const double half = 1000.0;
    const wpose_t a_local = {d, -half, 0.0};
    const wpose_t b_local = {d, half, 0.0};
    const wpose_t a = ref_compose(pose, a_local);
    const wpose_t b = ref_compose(pose, b_local);
    wmap_t map;
    wmap_init(&map);
    wmap_add_segment(&map, a.x, a.y, b.x, b.y);
    double ranges[BEAMS];
    cast_all(&map, pose, ranges);
    unsigned hits = 0u;
    for (unsigned i = 0u; i < BEAMS; i++) {
        const double phi = beam_phi(i);
        double want = INFINITY;
        if (cos(phi) > 0.0 && d * fabs(tan(phi)) <= half) {
            want = d / cos(phi);
            hits++;
        }
        expect_near("wall range", ranges[i], want, 1e-9 * (1.0 + want));
    }
    expect_true("wall: 359 of 361 beams hit", hits == BEAMS - 2u);
    expect_near("wall: beam 180 (ahead)", ranges[180], d, 1e-12);
    expect_near("wall: beam 90 (45 deg right)", ranges[90], d * sqrt(2.0), 1e-12);
    wmap_free(&map);
}

/* Inside the square room [0, 10] x [0, 10]: per axis the wall ahead is at
 * (bound - p) / direction; the range is the nearer of the two. */
static void check_room(void)
{
    const double size = 10.0;
    const wpose_t pose = {3.0, 4.0, 0.3};
    wmap_t map;
    wmap_init(&map);
    wmap_add_rect(&map, 0.0, 0.0, size, size);
    double ranges[BEAMS];
    cast_all(&map, pose, ranges);
    for (unsigned i = 0u; i < BEAMS; i++) {
        const double angle = pose.theta + beam_phi(i);
        const double dx = cos(angle);
        const double dy = sin(angle);
        const double tx = (dx > 0.0) ? (size - pose.x) / dx : -pose.x / dx;
        const double ty = (dy > 0.0) ? (size - pose.y) / dy : -pose.y / dy;
        const double want = fmin(tx, ty);
        expect_near("room range", ranges[i], want, 1e-9);
    }
    /* The scanner's right (beam 0) and left (beam 360) in world terms. */
    const wpose_t right = ref_compose(pose, (wpose_t){0.0, -1.0, 0.0});
    expect_true("room: beam 0 points to the scanner's right",
                fabs(hypot(right.x - pose.x, right.y - pose.y) - 1.0) < 1e-12 &&
                    ranges[0] > 0.0);
    wmap_free(&map);

    /* Corner check in scanner terms: heading 0 at (3, 4): beam 180 ahead
     * hits x = 10 at 7 m, beam 0 (right, -y) hits y = 0 at 4 m, beam 360
     * (left) hits y = 10 at 6 m. */
    const wpose_t axis = {3.0, 4.0, 0.0};
    wmap_init(&map);
    wmap_add_rect(&map, 0.0, 0.0, size, size);
    cast_all(&map, axis, ranges);
    expect_near("room: ahead", ranges[180], 7.0, 1e-12);
    expect_near("room: right", ranges[0], 4.0, 1e-12);
    expect_near("room: left", ranges[360], 6.0, 1e-12);
    expect_near("room: 45 deg left", ranges[270], 6.0 * sqrt(2.0), 1e-12);
    wmap_free(&map);
}

/* A post of radius r at distance D straight ahead: the beam at phi meets
 * it where |D sin phi| <= r, at D cos phi - sqrt(r^2 - D^2 sin^2 phi). */
static void check_post(double dist, double r, unsigned want_hits)
{
    const wpose_t pose = {-4.0, 2.5, -2.0};
    const wpose_t c = ref_compose(pose, (wpose_t){dist, 0.0, 0.0});
    wmap_t map;
    wmap_init(&map);
    wmap_add_circle(&map, c.x, c.y, r);
    double ranges[BEAMS];
    cast_all(&map, pose, ranges);
    unsigned hits = 0u;
    for (unsigned i = 0u; i < BEAMS; i++) {
        const double phi = beam_phi(i);
        const double off = dist * sin(phi);
        double want = INFINITY;
        if (fabs(off) <= r && cos(phi) > 0.0) {
            want = dist * cos(phi) - sqrt(r * r - off * off);
            hits++;
        }
        expect_near("post range", ranges[i], want, 1e-9);
    }
    expect_near("post: beams that hit", (double)hits, (double)want_hits, 0.0);
    expect_near("post: ahead", ranges[180], dist - r, 1e-12);
    wmap_free(&map);
}

/* Inside a round wall of radius R, off its centre by e to the scanner's
 * left: the beam at phi leaves at t = -b + sqrt(b^2 - q), b = (p - c).d,
 * q = |p - c|^2 - R^2; every beam hits. */
static void check_inside_circle(void)
{
    const wpose_t pose = {10.0, 20.0, 2.5};
    const double big_r = 30.0;
    const double e = 12.0;
    const wpose_t c = ref_compose(pose, (wpose_t){0.0, e, 0.0});
    wmap_t map;
    wmap_init(&map);
    wmap_add_circle(&map, c.x, c.y, big_r);
    double ranges[BEAMS];
    cast_all(&map, pose, ranges);
    for (unsigned i = 0u; i < BEAMS; i++) {
        /* Scanner frame: centre at (0, e), direction (cos phi, sin phi). */
        const double phi = beam_phi(i);
        const double b = -e * sin(phi);
        const double q = e * e - big_r * big_r;
        expect_near("round wall range", ranges[i], -b + sqrt(b * b - q), 1e-9);
    }
    expect_near("round wall: right (away from the centre)", ranges[0], big_r - e, 1e-12);
    expect_near("round wall: left (past the centre)", ranges[360], big_r + e, 1e-12);
    wmap_free(&map);
}

/* A moving car 10 m ahead, same heading: its rear face is 7.75 m ahead
 * and 1.8 m wide. */
static void check_mover(void)
{
    const wpose_t pose = {50.0, -20.0, 1.0};
    const wpose_t at = ref_compose(pose, (wpose_t){10.0, 0.0, 0.0});
    const wmover_t car = {at.x, at.y, at.theta, WORLD_CAR_LENGTH, WORLD_CAR_WIDTH};
    wmap_t empty;
    wmap_t active;
    wmap_init(&empty);
    wmap_init(&active);
    world_scan_prepare(&empty, &car, 1u, pose, 50.0, &active);
    double ranges[BEAMS];
    world_scan_cast(&active, pose, BEAMS, RES_DEG, ranges);
    const double rear = 10.0 - 0.5 * WORLD_CAR_LENGTH;
    for (unsigned i = 0u; i < BEAMS; i++) {
        const double phi = beam_phi(i);
        const double want = (cos(phi) > 0.0 && rear * fabs(tan(phi)) <= 0.5 * WORLD_CAR_WIDTH)
                                ? rear / cos(phi)
                                : INFINITY;
        expect_near("car rear range", ranges[i], want, 1e-9);
    }
    /* Out of range: not even added. */
    world_scan_prepare(&empty, &car, 1u, pose, 5.0, &active);
    expect_true("car beyond the culling radius is dropped", active.seg_count == 0u);
    wmap_free(&empty);
    wmap_free(&active);
}

/* Culling must not change any range up to the maximum: campus map, many
 * poses, culled against the whole map. */
static void check_culling(void)
{
    const wscenario_t *campus = wscenario_find("campus");
    wmap_t map;
    wmap_t active;
    wmap_init(&map);
    wmap_init(&active);
    campus->build_map(&map);
    const double max_range = 50.0;
    for (unsigned k = 0u; k < 929u; k += 37u) {
        const wpose_t pose = campus->pose(k, 2.0 / 75.0, 0.0);
        world_scan_prepare(&map, NULL, 0u, pose, max_range, &active);
        expect_true("culling keeps fewer primitives",
                    active.seg_count <= map.seg_count && active.circle_count <= map.circle_count);
        double culled[BEAMS];
        world_scan_cast(&active, pose, BEAMS, RES_DEG, culled);
        for (unsigned i = 0u; i < BEAMS; i++) {
            const double angle = pose.theta + beam_phi(i);
            const double full = wmap_cast(&map, pose.x, pose.y, cos(angle), sin(angle));
            if (full <= max_range) {
                expect_near("culled range", culled[i], full, 0.0);
            } else {
                expect_true("culled: nothing new within range", !(culled[i] <= max_range));
            }
        }
    }
    wmap_free(&map);
    wmap_free(&active);
}

static void check_words(void)
{
    expect_near("cm 12.3449 m", world_range_word(12.3449, 0.0, LMS_UNIT_CM, 50.0), 1234.0, 0.0);
    expect_near("cm 12.3451 m", world_range_word(12.3451, 0.0, LMS_UNIT_CM, 50.0), 1235.0, 0.0);
    expect_near("cm noise", world_range_word(12.0, 0.026, LMS_UNIT_CM, 50.0), 1203.0, 0.0);
    expect_near("cm at max", world_range_word(50.0, 0.0, LMS_UNIT_CM, 50.0), 5000.0, 0.0);
    expect_near("cm beyond max", world_range_word(50.001, 0.0, LMS_UNIT_CM, 50.0),
                (double)WORLD_WORD_BEYOND_CM, 0.0);
    expect_near("cm no hit", world_range_word(INFINITY, 0.0, LMS_UNIT_CM, 50.0),
                (double)WORLD_WORD_BEYOND_CM, 0.0);
    expect_near("cm largest", world_range_word(81.82, 0.3, LMS_UNIT_CM, 81.82),
                (double)WORLD_WORD_MAX_CM, 0.0);
    expect_near("cm smallest", world_range_word(0.001, -0.5, LMS_UNIT_CM, 50.0), 1.0, 0.0);
    expect_near("mm 7.2345 m", world_range_word(7.2345, 0.0, LMS_UNIT_MM, 50.0), 7235.0, 0.0);
    expect_near("mm 49.9999 m", world_range_word(49.9999, 0.0, LMS_UNIT_MM, 50.0), 50000.0,
                0.0);
    expect_near("mm no hit", world_range_word(INFINITY, 0.0, LMS_UNIT_MM, 50.0),
                (double)WORLD_WORD_NONE_MM, 0.0);
    expect_near("mm beyond max", world_range_word(60.0, 0.0, LMS_UNIT_MM, 50.0),
                (double)WORLD_WORD_NONE_MM, 0.0);
    expect_near("mm largest", world_range_word(65.535, 0.01, LMS_UNIT_MM, 65.535),
                (double)WORLD_WORD_MAX_MM, 0.0);
}

static int cmd_raycast(void)
{
    check_wall();
    check_room();
    check_post(7.0, 0.5, 17u);   /* +-4.1 deg */
    check_post(42.0, 1.5, 9u);   /* +-2.05 deg */
    check_inside_circle();
    check_mover();
    check_culling();
    check_words();
    return 0;
}

/* ------------------------------------------------------------------ */
/* paths */

static int cmd_paths(void)
{
    /* A square loop of side 10 with quarter circles of radius 2. */
    const double arc = 0.5 * WORLD_PI * 2.0;
    const wpiece_t pieces[8] = {{6.0, 0.0}, {arc, 0.5}, {6.0, 0.0}, {arc, 0.5},
                                {6.0, 0.0}, {arc, 0.5}, {6.0, 0.0}, {arc, 0.5}};
    wpath_t path;
    wpath_init(&path, (wpose_t){2.0, 0.0, 0.0}, pieces, 8u, true);
    expect_near("loop length", path.total, 24.0 + 4.0 * arc, 1e-12);
    const wpose_t end = wpath_pose(&path, path.total - 1e-12, 0.0);
    expect_near("loop closes x", end.x, 2.0, 1e-9);
    expect_near("loop closes y", end.y, 0.0, 1e-9);
    expect_near("loop closes theta", world_wrap(end.theta), 0.0, 1e-9);
    const wpose_t corner = wpath_pose(&path, 6.0 + arc, 0.0);
    expect_near("after the first corner x", corner.x, 10.0, 1e-12);
    expect_near("after the first corner y", corner.y, 2.0, 1e-12);
    expect_near("after the first corner theta", corner.theta, 0.5 * WORLD_PI, 1e-12);
    const wpose_t mid = wpath_pose(&path, 6.0 + 0.5 * arc, 1.0);
    /* Half way round the corner centred on (8, 2), 1 m to the left. */
    expect_near("corner, lane offset x", mid.x, 8.0 + cos(-0.25 * WORLD_PI), 1e-12);
    expect_near("corner, lane offset y", mid.y, 2.0 + sin(-0.25 * WORLD_PI), 1e-12);
    const wpose_t wrapped = wpath_pose(&path, path.total + 3.0, 0.0);
    expect_near("loop wraps", wrapped.x, 5.0, 1e-9);

    /* Speed profile: the closed-form distance against Simpson's rule. */
    const wknot_t knots[] = {{0.0, 0.0}, {4.0, 7.0}, {5.5, 6.0}, {10.0, 10.0}};
    for (unsigned step = 0u; step <= 16u; step++) {
        const double t = 0.75 * (double)step;
        const unsigned n = 2000u;
        const double h = t / (double)n;
        double sum = wprofile_speed(knots, 4u, 0.0) + wprofile_speed(knots, 4u, t);
        for (unsigned i = 1u; i < n; i++) {
            sum += ((i % 2u) != 0u ? 4.0 : 2.0) * wprofile_speed(knots, 4u, (double)i * h);
        }
        expect_near("profile distance", wprofile_distance(knots, 4u, t), sum * h / 3.0, 1e-6);
    }
    expect_near("profile speed at a knot", wprofile_speed(knots, 4u, 5.5), 6.0, 1e-12);
    expect_near("profile speed after the last knot", wprofile_speed(knots, 4u, 50.0), 10.0,
                0.0);
    return 0;
}

/* ------------------------------------------------------------------ */
/* scenarios: the scanner never inside or next to anything, cars on the
 * road, motion per scan as documented. */

static double box_clearance(const wmover_t *m, double x, double y)
{
    wmap_t box;
    wmap_init(&box);
    wmap_add_box(&box, m->x, m->y, m->heading, m->length, m->width);
    const double d = wmap_clearance(&box, x, y);
    wmap_free(&box);
    return d;
}

static void survey(const wscenario_t *sc, double period)
{
    wmap_t map;
    wmap_init(&map);
    sc->build_map(&map);
    double min_clear = INFINITY;
    double min_car = INFINITY;
    double min_car_static = INFINITY;
    double length = 0.0;
    double step_min = INFINITY;
    double step_max = 0.0;
    double turn_max = 0.0;
    double turn_min = INFINITY;
    double seen_min = 1.0;     /* least fraction of beams hitting within 50 m */
    double fast_turn_max = 0.0; /* largest turn per scan at >= 10 m/s */
    wmap_t active;
    wmap_init(&active);
    wmover_t movers[WORLD_MAX_MOVERS];
    wpose_t last = sc->pose(0u, period, 0.0);
    for (unsigned k = 0u; k < sc->default_scans; k++) {
        const wpose_t p = sc->pose(k, period, 0.0);
        min_clear = fmin(min_clear, wmap_clearance(&map, p.x, p.y));
        if (sc->movers != NULL) {
            const size_t n = sc->movers((double)k * period, movers);
            for (size_t i = 0u; i < n; i++) {
                min_car = fmin(min_car, box_clearance(&movers[i], p.x, p.y));
                if (movers[i].length >= 3.0) { /* vehicles; pedestrians: survey_movers */
                    min_car_static = fmin(min_car_static, wmap_clearance(&map, movers[i].x,
                                                                         movers[i].y));
                }
            }
        }
        if (k > 0u) {
            const wpose_t rel = world_between(last, p);
            const double step = hypot(rel.x, rel.y);
            length += step;
            step_min = fmin(step_min, step);
            step_max = fmax(step_max, step);
            turn_max = fmax(turn_max, fabs(rel.theta) * 180.0 / WORLD_PI);
            turn_min = fmin(turn_min, fabs(rel.theta) * 180.0 / WORLD_PI);
            if (step >= 10.0 * period - 1e-9) {
                fast_turn_max = fmax(fast_turn_max, fabs(rel.theta));
            }
        }
        if (k % 8u == 0u) {
            /* 181 beams without movers: how much of the view is mapped. */
            double ranges[181];
            unsigned seen = 0u;
            world_scan_prepare(&map, NULL, 0u, p, 50.0, &active);
            world_scan_cast(&active, p, 181u, 1.0, ranges);
            for (unsigned i = 0u; i < 181u; i++) {
                seen += (ranges[i] <= 50.0) ? 1u : 0u;
            }
            seen_min = fmin(seen_min, (double)seen / 181.0);
        }
        last = p;
    }
    wmap_free(&active);
    (void)printf("%-9s %4u scans at %5.2f Hz: %7.1f m, step %.3f..%.3f m, turn <= %.2f deg, "
                 "clearance >= %.2f m, >= %.0f %% of beams hit",
                 sc->name, sc->default_scans, 1.0 / period, length, step_min, step_max, turn_max,
                 min_clear, 100.0 * seen_min);
    if (sc->movers != NULL) {
        (void)printf(", cars >= %.2f m from the scanner, car centres >= %.2f m from the map",
                     min_car, min_car_static);
    }
    (void)printf("\n");
    expect_true("scanner keeps 1.5 m from every surface", min_clear >= 1.5);
    if (sc->movers != NULL) {
        expect_true("cars keep 1 m from the scanner", min_car >= 1.0);
        expect_true("cars stay on the road", min_car_static >= 2.5);
    }
    if (strcmp(sc->name, "fast") == 0) {
        expect_true("fast: 2-3 m per scan (chords)", step_min >= 1.99 && step_max <= 3.0 + 1e-9);
        expect_true("fast: up to about 10 deg per scan", turn_max >= 8.0 && turn_max <= 10.5);
    }
    if (strcmp(sc->name, "campus") == 0 || strcmp(sc->name, "busy") == 0) {
        expect_true("campus: at most 10 m/s", step_max <= 10.0 * period + 1e-9);
    }
    if (strcmp(sc->name, "corridor") == 0 || strcmp(sc->name, "sparse") == 0) {
        expect_true("corridor: straight", turn_max == 0.0);
    }
    if (strcmp(sc->name, "sparse") == 0) {
        expect_true("sparse: 5-8 m/s", step_min >= 5.0 * period - 1e-9 &&
                                           step_max <= 8.0 * period + 1e-9);
    }
    if (strcmp(sc->name, "plaza") == 0) {
        expect_true("plaza: 3-4 m/s", step_min >= 3.0 * period * 0.999 &&
                                          step_max <= 4.0 * period + 1e-9);
    }
    if (strcmp(sc->name, "ring") == 0) {
        expect_true("ring: standing at the centre", length == 0.0 && min_clear >= 8.9);
        expect_near("ring: 18.75 deg/s (0.5 deg a scan at 37.5 Hz), min", turn_min,
                    18.75 * period, 1e-9);
        expect_near("ring: 18.75 deg/s, max", turn_max, 18.75 * period, 1e-9);
    }
    if (strcmp(sc->name, "highway") == 0) {
        /* Chords: a little under the speed on the curves. */
        expect_true("highway: 10-30 m/s", step_min >= 10.0 * period * 0.999 &&
                                              step_max <= 30.0 * period + 1e-9);
        expect_true("highway: at most 0.5 rad/s",
                    turn_max <= 0.5 * period * 180.0 / WORLD_PI + 1e-9);
        expect_true("highway: 0.5 rad/s reached at 10 m/s or more",
                    fast_turn_max >= 0.499 * period);
        expect_true("highway: structure in view (half the beams hit within 50 m)",
                    seen_min >= 0.5);
    }
    wmap_free(&map);
}

/* Do two movers' rectangles overlap? Separating axes: the two axes of
 * each rectangle. */
static bool boxes_overlap(const wmover_t *a, const wmover_t *b)
{
    const wmover_t *box[2] = {a, b};
    for (size_t axis = 0u; axis < 4u; axis++) {
        const wmover_t *own = box[axis / 2u];
        const double h = own->heading + (((axis % 2u) != 0u) ? 0.5 * WORLD_PI : 0.0);
        const double ux = cos(h);
        const double uy = sin(h);
        double span[2][2];
        for (size_t r = 0u; r < 2u; r++) {
            const wmover_t *m = box[r];
            const double c = m->x * ux + m->y * uy;
            const double reach = 0.5 * m->length * fabs(cos(m->heading - h)) +
                                 0.5 * m->width * fabs(sin(m->heading - h));
            span[r][0] = c - reach;
            span[r][1] = c + reach;
        }
        if (span[0][1] < span[1][0] || span[1][1] < span[0][0]) {
            return false;
        }
    }
    return true;
}

/* What the movers of the busy-street scenarios do. */
typedef struct {
    size_t movers;       /* per call, the same at every time */
    double car_v[2];     /* vehicles' speed range, m/s */
    double ped_v[2];     /* pedestrians' speed range, m/s */
    double ped_clear;    /* least distance of a pedestrian's centre to the map, m */
    double ego_rel_max;  /* largest |vehicle speed - ego speed|, m/s */
    double hidden_mean;  /* mean share of the 181 beams that hit a mover */
    double left_hidden_s; /* s with half the left beams or more on movers */
    double still_s;      /* longest standstill (identical poses), s */
    double still_move;   /* fastest mover during it, m/s */
    unsigned crossing_seen; /* samples with a mover crossing ahead in view */
    unsigned overlaps;   /* mover pairs that overlap */
} mover_stats_t;

#define SURVEY_EVERY 8u /* occlusion sampled every 8th scan */

static void survey_movers(const wscenario_t *sc, double period, mover_stats_t *st)
{
    wmap_t map;
    wmap_t active;
    wmap_t scratch;
    wmap_init(&map);
    wmap_init(&active);
    wmap_init(&scratch);
    sc->build_map(&map);
    memset(st, 0, sizeof *st);
    st->car_v[0] = st->ped_v[0] = st->ped_clear = INFINITY;
    wmover_t movers[WORLD_MAX_MOVERS];
    wmover_t last[WORLD_MAX_MOVERS];
    wpose_t last_pose = sc->pose(0u, period, 0.0);
    double hidden_sum = 0.0;
    unsigned samples = 0u;
    unsigned left_samples = 0u;
    double still = 0.0;
    for (unsigned k = 0u; k < sc->default_scans; k++) {
        const wpose_t p = sc->pose(k, period, 0.0);
        const size_t n = sc->movers((double)k * period, movers);
        if (k == 0u) {
            st->movers = n;
        }
        expect_true("the same number of movers at every time", n == st->movers);
        const bool standing = k > 0u && p.x == last_pose.x && p.y == last_pose.y &&
                              p.theta == last_pose.theta;
        still = standing ? still + period : 0.0;
        st->still_s = fmax(st->still_s, still);
        const double ego_v = hypot(p.x - last_pose.x, p.y - last_pose.y) / period;
        for (size_t i = 0u; i < n && k > 0u; i++) {
            const double v = hypot(movers[i].x - last[i].x, movers[i].y - last[i].y) / period;
            const bool car = movers[i].length >= 3.0;
            double *range = car ? st->car_v : st->ped_v;
            range[0] = fmin(range[0], v);
            range[1] = fmax(range[1], v);
            if (car) {
                st->ego_rel_max = fmax(st->ego_rel_max, fabs(v - ego_v));
            } else {
                st->ped_clear = fmin(st->ped_clear, wmap_clearance(&map, movers[i].x,
                                                                   movers[i].y));
            }
            if (standing) {
                st->still_move = fmax(st->still_move, v);
            }
            for (size_t j = i + 1u; j < n; j++) {
                st->overlaps += boxes_overlap(&movers[i], &movers[j]) ? 1u : 0u;
            }
        }
        if (k % SURVEY_EVERY == 0u) {
            /* 181 beams with and without the movers: a beam that comes out
             * shorter with them hit one. */
            double bare[181];
            double busy[181];
            world_scan_prepare(&map, NULL, 0u, p, 50.0, &active);
            world_scan_cast(&active, p, 181u, 1.0, bare);
            world_scan_prepare(&map, movers, n, p, 50.0, &active);
            world_scan_cast(&active, p, 181u, 1.0, busy);
            unsigned hidden = 0u;
            unsigned left = 0u;
            for (unsigned i = 0u; i < 181u; i++) {
                const bool on_mover = busy[i] <= 50.0 && !(busy[i] >= bare[i]);
                hidden += on_mover ? 1u : 0u;
                left += (on_mover && i > 90u) ? 1u : 0u;
            }
            hidden_sum += (double)hidden / 181.0;
            samples++;
            left_samples += (left >= 45u) ? 1u : 0u;
            /* A mover across our way, ahead and hit by 3 beams or more. */
            unsigned returns[WORLD_MAX_MOVERS];
            (void)world_scan_returns(sc, k, period, 181u, 1.0, false, busy, 50.0, &scratch,
                                     returns);
            for (size_t i = 0u; i < n; i++) {
                const wpose_t rel = ref_between(p, (wpose_t){movers[i].x, movers[i].y,
                                                             movers[i].heading});
                if (fabs(cos(rel.theta)) < 0.01 && rel.x > 0.0 && returns[i] >= 3u) {
                    st->crossing_seen++;
                    break;
                }
            }
        }
        for (size_t i = 0u; i < n; i++) {
            last[i] = movers[i];
        }
        last_pose = p;
    }
    st->hidden_mean = (samples > 0u) ? hidden_sum / (double)samples : 0.0;
    st->left_hidden_s = (double)left_samples * SURVEY_EVERY * period;
    wmap_free(&map);
    wmap_free(&active);
    wmap_free(&scratch);
}

/* The busy-street scenarios do what docs/synthetic-worlds.md says. */
static void check_streets(const wscenario_t *sc, double period)
{
    mover_stats_t st;
    survey_movers(sc, period, &st);
    (void)printf("%-11s movers %zu: vehicles %.2f..%.2f m/s (ego +- %.2f), pedestrians "
                 "%.2f..%.2f m/s >= %.2f m from the map, %.0f %% of beams on movers, left side "
                 "hidden %.2f s, still %.2f s (movers up to %.2f m/s), crossing seen %u\n",
                 sc->name, st.movers, st.car_v[0], st.car_v[1], st.ego_rel_max, st.ped_v[0],
                 st.ped_v[1], st.ped_clear, 100.0 * st.hidden_mean, st.left_hidden_s,
                 st.still_s, st.still_move, st.crossing_seen);
    char what[96];
    (void)snprintf(what, sizeof what, "%s: movers never overlap", sc->name);
    expect_true(what, st.overlaps == 0u);
    const double slack = 1e-6;
    if (strcmp(sc->name, "traffic") == 0) {
        expect_true("traffic: ten or more vehicles", st.movers >= 10u);
        expect_true("traffic: vehicles at 4-11 m/s",
                    st.car_v[0] >= 4.0 - slack && st.car_v[1] <= 11.0 + slack);
    }
    if (strcmp(sc->name, "platoon") == 0) {
        expect_true("platoon: within 0.5 m/s of the ego", st.ego_rel_max <= 0.5);
        expect_true("platoon: about a third of the beams on trucks",
                    st.hidden_mean >= 0.25 && st.hidden_mean <= 0.45);
    }
    if (strcmp(sc->name, "overtake") == 0) {
        expect_true("overtake: the left side half hidden for about a second",
                    st.left_hidden_s >= 0.6 && st.left_hidden_s <= 2.0);
    }
    if (strcmp(sc->name, "crossing") == 0) {
        expect_true("crossing: cars seen crossing ahead", st.crossing_seen >= 5u);
    }
    if (strcmp(sc->name, "pedestrians") == 0) {
        expect_true("pedestrians: 15 or more", st.movers >= 15u);
        expect_true("pedestrians: 1-1.8 m/s",
                    st.ped_v[0] >= 1.0 - slack && st.ped_v[1] <= 1.8 + slack);
        expect_true("pedestrians: never inside the map", st.ped_clear >= 0.4);
    }
    if (strcmp(sc->name, "stopgo") == 0) {
        expect_true("stopgo: standing still for several seconds", st.still_s >= 3.0);
        expect_true("stopgo: traffic moves meanwhile", st.still_move >= 3.0);
    }
}

static int cmd_scenarios(void)
{
    for (size_t i = 0u; i < wscenario_count(); i++) {
        survey(wscenario_at(i), 2.0 / 75.0);
        survey(wscenario_at(i), 1.0 / 75.0);
    }
    for (size_t i = 0u; i < wscenario_count(); i++) {
        const wscenario_t *sc = wscenario_at(i);
        if (sc->movers != NULL) {
            check_streets(sc, 2.0 / 75.0);
            check_streets(sc, 1.0 / 75.0);
        }
    }
    return 0;
}

/* ------------------------------------------------------------------ */
/* timing: --timing lms. Beam times written out again from the LMS 2xx's
 * mirror (75 Hz, one turn 13 333.3 us, one degree 37.037 us): a 181-value
 * scan is one sweep; a 361-value scan interlaces two turns, the even values
 * (0, 1, 2.. deg) from the first, the odd (0.5, 1.5.. deg) from the second. */

static double ref_beam_time(unsigned i, unsigned count)
{
    const double turn_us = 1e6 / 75.0;
    const double degree_us = turn_us / 360.0;
    if (count == 361u) {
        const unsigned pair = i / 2u; /* values 2j and 2j + 1 are j degrees in */
        return ((((i % 2u) != 0u) ? turn_us : 0.0) + (double)pair * degree_us) * 1e-6;
    }
    return (double)i * degree_us * 1e-6;
}

static double ref_mean_time(unsigned count)
{
    double sum = 0.0;
    for (unsigned i = 0u; i < count; i++) {
        sum += ref_beam_time(i, count);
    }
    return sum / (double)count;
}

/* The motions the timing checks cast: a file-level choice, since the
 * scenario callbacks take no context. */
static int motion;
enum { MOTION_STILL, MOTION_FORWARD, MOTION_TURN, MOTION_CAR };

#define TIMING_SPEED 25.0 /* m/s, forward */
#define TIMING_RATE 0.5   /* rad/s, turning */
#define TIMING_WALL 6.0   /* m ahead of the origin */
#define TIMING_CAR_SPEED 20.0

static wpose_t timing_pose(unsigned k, double period, double dt)
{
    const double t = (double)k * period + dt;
    wpose_t p = {0.0, 0.0, 0.0};
    if (motion == MOTION_STILL) {
        p.x = 95.0;
        p.y = 20.0;
        p.theta = 0.7;
    } else if (motion == MOTION_FORWARD) {
        p.x = TIMING_SPEED * t;
    } else if (motion == MOTION_TURN) {
        p.theta = TIMING_RATE * t;
    }
    return p;
}

/* MOTION_CAR: a car ahead of the still scanner, centre at 10 m + 20 m/s t. */
static size_t timing_movers(double t, wmover_t *out)
{
    if (motion != MOTION_CAR) {
        return 0u;
    }
    const wmover_t car = {10.0 + TIMING_CAR_SPEED * t, 0.0, 0.0, WORLD_CAR_LENGTH,
                          WORLD_CAR_WIDTH};
    out[0] = car;
    return 1u;
}

static void timing_wall_map(wmap_t *map)
{
    wmap_add_segment(map, TIMING_WALL, -1000.0, TIMING_WALL, 1000.0);
}

static void check_beam_times(void)
{
    char what[96];
    for (unsigned i = 0u; i < 181u; i++) {
        (void)snprintf(what, sizeof what, "181 values: value %u at %u x 37.037 us", i, i);
        expect_near(what, world_beam_time(i, 181u), ref_beam_time(i, 181u), 1e-15);
    }
    for (unsigned i = 0u; i < 361u; i++) {
        (void)snprintf(what, sizeof what, "361 values: value %u (interlaced)", i);
        expect_near(what, world_beam_time(i, 361u), ref_beam_time(i, 361u), 1e-15);
    }
    expect_near("181: value 180 at 6.667 ms", world_beam_time(180u, 181u), 1.0 / 150.0, 1e-15);
    expect_near("361: value 1 at 13.333 ms", world_beam_time(1u, 361u), 1.0 / 75.0, 1e-15);
    expect_near("361: value 2 at 37.037 us", world_beam_time(2u, 361u), 1.0 / 27000.0, 1e-15);
    expect_near("361: value 360 at 6.667 ms", world_beam_time(360u, 361u), 1.0 / 150.0, 1e-15);
    expect_near("361: value 359 at 13.333 ms + 179 x 37.037 us", world_beam_time(359u, 361u),
                1.0 / 75.0 + 179.0 / 27000.0, 1e-15);
    /* Means in closed form: 90 degrees into a sweep; for 361, 180 odd
     * values a turn later (180 / 75 s) and sum(i / 2) = 32 400 degrees:
     * (2.4 + 1.2) / 361 s. */
    expect_near("181: mean 3.333 ms", world_beam_mean_time(181u), 90.0 / 27000.0, 1e-15);
    expect_near("361: mean 9.972 ms", world_beam_mean_time(361u), 3.6 / 361.0, 1e-15);
    expect_near("361: mean (summed)", world_beam_mean_time(361u), ref_mean_time(361u), 1e-15);
    expect_true("passes", world_scan_passes(361u) == 2u && world_scan_passes(181u) == 1u);
}

/* One --timing lms scan of the motion in use; period 2/75 or 1/75. */
static void cast_timed(const wmap_t *map, unsigned k, unsigned count, double *ranges)
{
    const wscenario_t sc = {"timing", "", 10u, 0u, NULL, timing_pose, timing_movers};
    const double period = (count == 361u) ? 2.0 / 75.0 : 1.0 / 75.0;
    wmap_t active;
    wmap_t scratch;
    wmap_init(&active);
    wmap_init(&scratch);
    world_scan_cast_lms(&sc, map, k, period, count, 180.0 / (double)(count - 1u), 50.0,
                        &active, &scratch, ranges);
    wmap_free(&active);
    wmap_free(&scratch);
}

/* Every scenario is a function of time: continuous around each scan, and
 * dt = one period after scan k is scan k + 1. */
static void check_scenario_times(void)
{
    static const double periods[2] = {2.0 / 75.0, 1.0 / 75.0};
    static const unsigned scans[4] = {0u, 1u, 37u, 150u};
    char what[96];
    for (size_t i = 0u; i < wscenario_count(); i++) {
        const wscenario_t *sc = wscenario_at(i);
        for (size_t j = 0u; j < 2u * 4u; j++) {
            const double period = periods[j / 4u];
            const unsigned k = scans[j % 4u];
            if (sc->required_scans != 0u && k + 1u >= sc->required_scans) {
                continue;
            }
            const wpose_t at = sc->pose(k, period, 0.0);
            const wpose_t next = sc->pose(k + 1u, period, 0.0);
            const wpose_t later = sc->pose(k, period, period);
            const wpose_t before = sc->pose(k, period, -1e-6);
            const wpose_t after = sc->pose(k, period, 1e-6);
            (void)snprintf(what, sizeof what, "%s: scan %u + one period = scan %u", sc->name, k,
                           k + 1u);
            expect_near(what, hypot(later.x - next.x, later.y - next.y) +
                                  fabs(angle_diff(later.theta, next.theta)),
                        0.0, 1e-9);
            (void)snprintf(what, sizeof what, "%s: continuous at scan %u", sc->name, k);
            /* 1 us either side: at most 0.5 mm and 5e-5 rad (the keyframe
             * scenarios at 1/75 s are the fastest: table2 moves 4.3 m and
             * 25 deg a period, 0.33 mm and 3.3e-5 rad a microsecond). */
            expect_true(what, hypot(before.x - at.x, before.y - at.y) < 5e-4 &&
                                  hypot(after.x - at.x, after.y - at.y) < 5e-4 &&
                                  fabs(angle_diff(before.theta, at.theta)) < 5e-5 &&
                                  fabs(angle_diff(after.theta, at.theta)) < 5e-5);
        }
    }
}

static int cmd_timing(void)
{
    check_beam_times();
    check_scenario_times();
    static const unsigned counts[2] = {361u, 181u};
    for (size_t c = 0u; c < 2u; c++) {
        const unsigned count = counts[c];
        const double res = 180.0 / (double)(count - 1u);
        const double period = (count == 361u) ? 2.0 / 75.0 : 1.0 / 75.0;
        const double mean = ref_mean_time(count);
        const unsigned k = 7u;
        double lms[LMS_SCAN_MAX_VALUES];
        double instant[LMS_SCAN_MAX_VALUES];

        /* Standing still in the campus: lms timing changes nothing. */
        motion = MOTION_STILL;
        wmap_t campus;
        wmap_init(&campus);
        wscenario_find("campus")->build_map(&campus);
        cast_timed(&campus, k, count, lms);
        wmap_t active;
        wmap_init(&active);
        const wpose_t still = timing_pose(k, period, 0.0);
        world_scan_prepare(&campus, NULL, 0u, still, 50.0, &active);
        world_scan_cast(&active, still, count, res, instant);
        for (unsigned i = 0u; i < count; i++) {
            if (instant[i] <= 50.0 || lms[i] <= 50.0) {
                expect_near("standing still: lms = instant", lms[i], instant[i], 0.0);
            }
        }
        wmap_free(&active);
        wmap_free(&campus);

        /* Driving at 25 m/s at a wall 6 m ahead (perpendicular): value i
         * is cast from x = v t_i, range (D - v t_i) / cos(phi_i). */
        wmap_t wall;
        wmap_init(&wall);
        timing_wall_map(&wall);
        motion = MOTION_FORWARD;
        cast_timed(&wall, k, count, lms);
        unsigned differ = 0u;
        for (unsigned i = 0u; i < count; i++) {
            const double phi = world_rad((double)i * res - 90.0);
            const double t = (double)k * period + ref_beam_time(i, count) - mean;
            const double want = (cos(phi) > 1e-9) ? (TIMING_WALL - TIMING_SPEED * t) / cos(phi)
                                                  : INFINITY;
            const double at_scan = (cos(phi) > 1e-9)
                                       ? (TIMING_WALL - TIMING_SPEED * (double)k * period) /
                                             cos(phi)
                                       : INFINITY;
            if (want <= 50.0) {
                expect_near("forward at a wall: range at the value's own time", lms[i], want,
                            1e-9 * (1.0 + want));
                differ += (fabs(lms[i] - at_scan) > 0.01) ? 1u : 0u;
            }
        }
        expect_true("forward: most values differ from the scan instant by > 1 cm",
                    differ > count / 2u);

        /* Turning at 0.5 rad/s at the origin: value i points along
         * omega t_i + phi_i, range D / cos of that. */
        motion = MOTION_TURN;
        cast_timed(&wall, k, count, lms);
        for (unsigned i = 0u; i < count; i++) {
            const double t = (double)k * period + ref_beam_time(i, count) - mean;
            const double a = TIMING_RATE * t + world_rad((double)i * res - 90.0);
            const double want = (cos(a) > 1e-9) ? TIMING_WALL / cos(a) : INFINITY;
            if (want <= 50.0) {
                expect_near("turning at a wall: direction at the value's own time", lms[i], want,
                            1e-9 * (1.0 + want));
            }
        }
        wmap_free(&wall);

        /* A car driving away at 20 m/s from the still scanner at the
         * origin: its rear face at 10 + w t_i - 2.25 m. */
        motion = MOTION_CAR;
        wmap_t empty;
        wmap_init(&empty);
        cast_timed(&empty, k, count, lms);
        unsigned hits = 0u;
        for (unsigned i = 0u; i < count; i++) {
            const double phi = world_rad((double)i * res - 90.0);
            const double t = (double)k * period + ref_beam_time(i, count) - mean;
            const double rear = 10.0 + TIMING_CAR_SPEED * t - 0.5 * WORLD_CAR_LENGTH;
            const double want =
                (cos(phi) > 0.0 && rear * fabs(tan(phi)) <= 0.5 * WORLD_CAR_WIDTH)
                    ? rear / cos(phi)
                    : INFINITY;
            expect_near("car: its position at the value's own time", lms[i], want, 1e-9);
            hits += isinf(want) ? 0u : 1u;
        }
        expect_true("car: seen", hits > 5u);
        wmap_free(&empty);
    }
    return 0;
}

/* ------------------------------------------------------------------ */
/* Reading the outputs. */

/* Next non-comment line of fp into line; false at the end. */
static bool next_line(FILE *fp, char *line, size_t cap)
{
    while (fgets(line, (int)cap, fp) != NULL) {
        if (line[0] != '#' && line[0] != '\n') {
            return true;
        }
    }
    return false;
}

typedef struct {
    unsigned i, j;
    wpose_t rel;
} pair_t;

/* Exactly n numbers separated by blanks (strtod), nothing else. */
static bool parse_numbers(const char *line, double *out, size_t n)
{
    const char *cursor = line;
    for (size_t i = 0u; i < n; i++) {
        char *end = NULL;
        errno = 0;
        out[i] = strtod(cursor, &end);
        if (end == cursor || errno != 0 || !isfinite(out[i])) {
            return false;
        }
        cursor = end;
    }
    while (*cursor == ' ' || *cursor == '\t' || *cursor == '\r' || *cursor == '\n') {
        cursor++;
    }
    return *cursor == '\0';
}

/* A scan number written as a number. */
static bool as_index(double v, unsigned *out)
{
    if (!(v >= 0.0 && v <= 1e9 && floor(v) == v)) {
        return false;
    }
    *out = (unsigned)v;
    return true;
}

static FILE *open_or_die(const char *path)
{
    FILE *fp = fopen(path, "r");
    if (fp == NULL) {
        (void)fprintf(stderr, "world_check: cannot open '%s': %s\n", path, strerror(errno));
        exit(2);
    }
    return fp;
}

/* Reads up to cap truth lines; returns the count. */
static size_t read_pairs(const char *path, pair_t *out, size_t cap)
{
    FILE *fp = open_or_die(path);
    char line[512];
    size_t n = 0u;
    while (next_line(fp, line, sizeof line)) {
        pair_t p;
        double v[5];
        if (!parse_numbers(line, v, 5u) || !as_index(v[0], &p.i) || !as_index(v[1], &p.j)) {
            (void)fprintf(stderr, "FAIL bad truth line: %s", line);
            failures++;
            continue;
        }
        p.rel.x = v[2];
        p.rel.y = v[3];
        p.rel.theta = v[4];
        if (n < cap) {
            out[n] = p;
        }
        n++;
    }
    (void)fclose(fp);
    return n;
}

typedef struct {
    double t;
    wpose_t pose;
} stamped_t;

static size_t read_poses(const char *path, stamped_t *out, size_t cap)
{
    FILE *fp = open_or_die(path);
    char line[512];
    size_t n = 0u;
    while (next_line(fp, line, sizeof line)) {
        double v[8];
        if (!parse_numbers(line, v, 8u)) {
            (void)fprintf(stderr, "FAIL bad pose line: %s", line);
            failures++;
            continue;
        }
        /* time x y z qx qy qz qw */
        expect_near("pose z", v[3], 0.0, 0.0);
        expect_near("pose qx", v[4], 0.0, 0.0);
        expect_near("pose qy", v[5], 0.0, 0.0);
        expect_near("unit quaternion", v[6] * v[6] + v[7] * v[7], 1.0, 1e-8);
        if (n < cap) {
            out[n].t = v[0];
            out[n].pose.x = v[1];
            out[n].pose.y = v[2];
            out[n].pose.theta = 2.0 * atan2(v[6], v[7]);
        }
        n++;
    }
    (void)fclose(fp);
    return n;
}

static bool parse_count(const char *text, unsigned long *out)
{
    char *end = NULL;
    errno = 0;
    const unsigned long v = strtoul(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0') {
        return false;
    }
    *out = v;
    return true;
}

/* pairs TRUTH POSES N PERIOD SKIP */
static int cmd_pairs(const char *truth_path, const char *poses_path, const char *count_text,
                     const char *period_text, const char *skip_text)
{
    unsigned long count = 0u;
    unsigned long skip = 0u;
    char *end = NULL;
    const double period = strtod(period_text, &end);
    if (!parse_count(count_text, &count) || count < 2u || count > 100000u || *end != '\0' ||
        !parse_count(skip_text, &skip)) {
        (void)fputs("world_check pairs: bad N or PERIOD\n", stderr);
        return 2;
    }
    pair_t *pairs = calloc(count, sizeof *pairs);
    stamped_t *poses = calloc(count, sizeof *poses);
    if (pairs == NULL || poses == NULL) {
        free(pairs);
        free(poses);
        return 2;
    }
    const size_t npairs = read_pairs(truth_path, pairs, count);
    const size_t nposes = read_poses(poses_path, poses, count);
    expect_near("number of poses", (double)nposes, (double)count, 0.0);
    expect_near("number of pairs", (double)npairs, (double)(count - 1u), 0.0);
    if (npairs == count - 1u && nposes == count) {
        wpose_t chain = poses[0].pose;
        double drift = 0.0;
        for (size_t k = 0u; k < count; k++) {
            expect_near("time stamp", poses[k].t, (double)(skip + k) * period, 1e-9);
        }
        for (size_t k = 0u; k + 1u < count; k++) {
            const pair_t *p = &pairs[k];
            expect_true("pair indices i, i + 1", p->i == k && p->j == k + 1u);
            /* Local: P_i (+) rel = P_j, and rel = between(P_i, P_j). */
            const wpose_t a = poses[k].pose;
            const wpose_t b = poses[k + 1u].pose;
            const wpose_t composed = ref_compose(a, p->rel);
            expect_near("P_i (+) rel: x", composed.x, b.x, 1e-6);
            expect_near("P_i (+) rel: y", composed.y, b.y, 1e-6);
            expect_near("P_i (+) rel: theta", angle_diff(composed.theta, b.theta), 0.0, 1e-6);
            const wpose_t between = ref_between(a, b);
            expect_near("between(P_i, P_j): dx", between.x, p->rel.x, 1e-6);
            expect_near("between(P_i, P_j): dy", between.y, p->rel.y, 1e-6);
            expect_near("between(P_i, P_j): dtheta", angle_diff(between.theta, p->rel.theta),
                        0.0, 1e-6);
            expect_true("dtheta in (-pi, pi]", p->rel.theta > -WORLD_PI && p->rel.theta <= WORLD_PI);
            /* Global: the whole chain from P_0 stays on the poses. */
            chain = ref_compose(chain, p->rel);
            drift = fmax(drift, hypot(chain.x - b.x, chain.y - b.y));
            drift = fmax(drift, fabs(angle_diff(chain.theta, b.theta)));
        }
        expect_near("chained composition stays within 1e-4 of the poses", fmin(drift, 1.0),
                    fmin(drift, 1e-4), 0.0);
        (void)printf("pairs: %lu poses, largest drift of the chained truth %.3g\n", count, drift);
    }
    free(pairs);
    free(poses);
    return 0;
}

/* table2 TRUTH */
static int cmd_table2(const char *truth_path)
{
    pair_t pairs[4];
    const size_t n = read_pairs(truth_path, pairs, 4u);
    expect_near("table2: one pair", (double)n, 1.0, 0.0);
    if (n >= 1u) {
        expect_true("table2: pair 0 1", pairs[0].i == 0u && pairs[0].j == 1u);
        expect_near("table2: dx", pairs[0].rel.x, WORLD_TABLE2_DX, 1e-9);
        expect_near("table2: dy", pairs[0].rel.y, WORLD_TABLE2_DY, 1e-9);
        expect_near("table2: dtheta", pairs[0].rel.theta, world_rad(WORLD_TABLE2_DEG), 1e-9);
    }
    return 0;
}

/* decode SCANS SCENARIO RES UNIT MAX_RANGE SKIP: each scan line of
 * `lmsego scans` ("index unit_mm n v1 .. vn") against the ranges cast now. */
static int cmd_decode(const char *scans_path, const char *name, const char *res_text,
                      const char *unit_text, const char *max_text, const char *skip_text,
                      const char *timing_text)
{
    unsigned long skip = 0u;
    const bool lms_timing = strcmp(timing_text, "lms") == 0;
    if (!lms_timing && strcmp(timing_text, "instant") != 0) {
        (void)fputs("world_check decode: TIMING is instant or lms\n", stderr);
        return 2;
    }
    const wscenario_t *sc = wscenario_find(name);
    const double res = strtod(res_text, NULL);
    const bool mm = strcmp(unit_text, "mm") == 0;
    const double max_range = strtod(max_text, NULL);
    if (sc == NULL || (res != 1.0 && res != 0.5) || !(max_range > 0.0) ||
        !parse_count(skip_text, &skip)) {
        (void)fputs("world_check decode: bad arguments\n", stderr);
        return 2;
    }
    const unsigned count = (res == 1.0) ? 181u : 361u;
    const double period = (res == 1.0) ? 1.0 / 75.0 : 2.0 / 75.0;
    wmap_t map;
    wmap_t active;
    wmap_t cars;
    wmap_init(&map);
    wmap_init(&active);
    wmap_init(&cars);
    sc->build_map(&map);
    const double mean = ref_mean_time(count);
    FILE *fp = open_or_die(scans_path);
    static char line[8192];
    unsigned k = 0u;
    unsigned specials = 0u;
    wmover_t movers[WORLD_MAX_MOVERS];
    while (fgets(line, sizeof line, fp) != NULL) {
        const unsigned scene_k = (unsigned)skip + k;
        const double t = (double)scene_k * period;
        const wpose_t pose = sc->pose(scene_k, period, 0.0);
        const size_t nm = (sc->movers != NULL) ? sc->movers(t, movers) : 0u;
        world_scan_prepare(&map, movers, nm, pose, max_range, &active);
        double ranges[LMS_SCAN_MAX_VALUES];
        world_scan_cast(&active, pose, count, res, ranges);
        for (unsigned i = 0u; lms_timing && i < count; i++) {
            /* Each value from its own pose and cars, on the whole map. */
            const double dt = ref_beam_time(i, count) - mean;
            const wpose_t at = sc->pose(scene_k, period, dt);
            const size_t cn = (sc->movers != NULL) ? sc->movers(t + dt, movers) : 0u;
            wmap_clear(&cars);
            for (size_t j = 0u; j < cn; j++) {
                wmap_add_box(&cars, movers[j].x, movers[j].y, movers[j].heading,
                             movers[j].length, movers[j].width);
            }
            const double a = at.theta + world_rad((double)i * res - 90.0);
            ranges[i] = fmin(wmap_cast(&map, at.x, at.y, cos(a), sin(a)),
                             wmap_cast(&cars, at.x, at.y, cos(a), sin(a)));
        }

        char *cursor = line;
        const long index = strtol(cursor, &cursor, 10);
        const long unit_mm = strtol(cursor, &cursor, 10);
        const long n = strtol(cursor, &cursor, 10);
        expect_near("decoded scan index", (double)index, (double)k, 0.0);
        expect_near("decoded unit", (double)unit_mm, mm ? 1.0 : 10.0, 0.0);
        expect_near("decoded value count", (double)n, (double)count, 0.0);
        for (unsigned i = 0u; i < count && n == (long)count; i++) {
            const long got = strtol(cursor, &cursor, 10);
            double want;
            if (!(ranges[i] <= max_range)) {
                want = mm ? 0.0 : -7.0; /* 0F: value 0; 00: beyond max */
                specials++;
            } else {
                want = mm ? fmin(65535.0, fmax(1.0, round(ranges[i] * 1000.0)))
                          : 10.0 * fmin(8182.0, fmax(1.0, round(ranges[i] * 100.0)));
            }
            expect_near("decoded value", (double)got, want, 0.0);
        }
        k++;
    }
    (void)fclose(fp);
    (void)printf("decode: %u scans, %u beams without a surface within %g m\n", k, specials,
                 max_range);
    expect_true("decode: some scans", k > 0u);
    wmap_free(&map);
    wmap_free(&active);
    wmap_free(&cars);
    return 0;
}

/* ------------------------------------------------------------------ */
/* objects: the --objects file. */

typedef struct {
    unsigned scan, id;
    wpose_t rel;     /* centre and heading in the scanner frame */
    double vx, vy;   /* m/s over ground, scanner frame */
    double length, width;
    unsigned returns;
} object_line_t;

#define OBJECTS_MAX_LINES 200000u

/* Reads the objects file (its first line must be lmsworld's header);
 * returns the number of lines, *lines allocated. */
static size_t read_objects(const char *path, object_line_t **lines)
{
    FILE *fp = open_or_die(path);
    static char line[512];
    *lines = calloc(OBJECTS_MAX_LINES, sizeof **lines);
    if (*lines == NULL) {
        (void)fclose(fp);
        exit(2);
    }
    size_t n = 0u;
    bool first = true;
    while (fgets(line, sizeof line, fp) != NULL) {
        if (first) {
            expect_true("objects: the first line is lmsworld's header",
                        strncmp(line, "# lmsworld --scenario ", 22u) == 0);
            first = false;
        }
        if (line[0] == '#') {
            continue;
        }
        double v[10];
        object_line_t o;
        if (!parse_numbers(line, v, 10u) || !as_index(v[0], &o.scan) || !as_index(v[1], &o.id) ||
            !as_index(v[9], &o.returns) || n >= OBJECTS_MAX_LINES) {
            (void)fprintf(stderr, "FAIL bad objects line: %s", line);
            failures++;
            continue;
        }
        o.rel = (wpose_t){v[2], v[3], v[4]};
        o.vx = v[5];
        o.vy = v[6];
        o.length = v[7];
        o.width = v[8];
        (*lines)[n++] = o;
    }
    (void)fclose(fp);
    return n;
}

/* The beams of scan scene_k that hit each mover, counted here on the
 * whole (unculled) map, each value at its own time for TIMING lms. */
static void recount_returns(const wscenario_t *sc, const wmap_t *map, unsigned scene_k,
                            double period, unsigned count, double res, double max_range,
                            bool lms_timing, unsigned *returns)
{
    wmap_t box;
    wmap_init(&box);
    wmover_t movers[WORLD_MAX_MOVERS];
    const double mean = ref_mean_time(count);
    for (size_t j = 0u; j < WORLD_MAX_MOVERS; j++) {
        returns[j] = 0u;
    }
    for (unsigned i = 0u; i < count; i++) {
        const double dt = lms_timing ? ref_beam_time(i, count) - mean : 0.0;
        const wpose_t at = sc->pose(scene_k, period, dt);
        const size_t n = sc->movers((double)scene_k * period + dt, movers);
        const double a = at.theta + world_rad((double)i * res - 90.0);
        double nearest = wmap_cast(map, at.x, at.y, cos(a), sin(a));
        size_t hit = WORLD_MAX_MOVERS;
        for (size_t j = 0u; j < n; j++) {
            wmap_clear(&box);
            wmap_add_box(&box, movers[j].x, movers[j].y, movers[j].heading, movers[j].length,
                         movers[j].width);
            const double d = wmap_cast(&box, at.x, at.y, cos(a), sin(a));
            if (d < nearest) {
                nearest = d;
                hit = j;
            }
        }
        if (hit < WORLD_MAX_MOVERS && nearest <= max_range) {
            returns[hit]++;
        }
    }
    wmap_free(&box);
}

/* objects OBJECTS SCENARIO RES MAX_RANGE SKIP TIMING VEL_TOL */
static int cmd_objects(const char *path, const char *name, const char *res_text,
                       const char *max_text, const char *skip_text, const char *timing_text,
                       const char *tol_text)
{
    const double vel_tol = strtod(tol_text, NULL);
    unsigned long skip = 0u;
    const wscenario_t *sc = wscenario_find(name);
    const double res = strtod(res_text, NULL);
    const double max_range = strtod(max_text, NULL);
    const bool lms_timing = strcmp(timing_text, "lms") == 0;
    if (sc == NULL || sc->movers == NULL || (res != 1.0 && res != 0.5) || !(max_range > 0.0) ||
        !parse_count(skip_text, &skip) || (!lms_timing && strcmp(timing_text, "instant") != 0) ||
        !(vel_tol > 0.0)) {
        (void)fputs("world_check objects: bad arguments\n", stderr);
        return 2;
    }
    const unsigned count = (res == 1.0) ? 181u : 361u;
    const double period = (res == 1.0) ? 1.0 / 75.0 : 2.0 / 75.0;
    object_line_t *lines = NULL;
    const size_t n = read_objects(path, &lines);
    wmap_t map;
    wmap_init(&map);
    sc->build_map(&map);
    wmover_t movers[WORLD_MAX_MOVERS];
    const size_t per_scan = sc->movers(0.0, movers);
    const size_t scans = (per_scan > 0u) ? n / per_scan : 0u;
    expect_true("objects: whole scans of every mover", per_scan > 0u && n == scans * per_scan);
    expect_true("objects: two scans or more", scans >= 2u);
    unsigned seen = 0u;
    unsigned hidden = 0u;
    double worst_v = 0.0;
    for (size_t k = 0u; k < scans && failures == 0u; k++) {
        const unsigned scene_k = (unsigned)skip + (unsigned)k;
        const wpose_t pose = sc->pose(scene_k, period, 0.0);
        const size_t nm = sc->movers((double)scene_k * period, movers);
        unsigned returns[WORLD_MAX_MOVERS];
        recount_returns(sc, &map, scene_k, period, count, res, max_range, lms_timing, returns);
        for (size_t j = 0u; j < nm && j < per_scan; j++) {
            const object_line_t *o = &lines[k * per_scan + j];
            /* Stable ids: scan k holds ids 0..n-1 in order. */
            expect_true("objects: scan and id in order", o->scan == k && o->id == j);
            /* The pose, in the scanner frame at the scan's time. */
            const wpose_t want = ref_between(pose, (wpose_t){movers[j].x, movers[j].y,
                                                              movers[j].heading});
            expect_near("objects: cx", o->rel.x, want.x, 1e-5);
            expect_near("objects: cy", o->rel.y, want.y, 1e-5);
            expect_near("objects: heading", angle_diff(o->rel.theta, want.theta), 0.0, 1e-5);
            expect_near("objects: length", o->length, movers[j].length, 1e-3);
            expect_near("objects: width", o->width, movers[j].width, 1e-3);
            /* Returns: recounted; none from an object behind the scanner
             * or beyond the maximum range (0.5 m slack: with lms timing
             * the values are cast up to 10 ms from the scan's time). */
            expect_near("objects: returns recounted on the whole map", (double)o->returns,
                        (double)returns[j], 0.0);
            const double reach = 0.5 * hypot(o->length, o->width) + 0.5;
            const bool out_of_view =
                o->rel.x + reach < 0.0 || hypot(o->rel.x, o->rel.y) - reach > max_range;
            expect_true("objects: no returns out of view", !(out_of_view && o->returns > 0u));
            seen += (o->returns > 0u) ? 1u : 0u;
            hidden += (o->returns == 0u && !out_of_view) ? 1u : 0u;
            /* Velocity over ground against the world positions of the
             * scans either side, differenced, in this scan's frame. */
            if (k > 0u && k + 1u < scans) {
                const object_line_t *before = &lines[(k - 1u) * per_scan + j];
                const object_line_t *after = &lines[(k + 1u) * per_scan + j];
                const wpose_t p0 = ref_compose(sc->pose(scene_k - 1u, period, 0.0), before->rel);
                const wpose_t p1 = ref_compose(sc->pose(scene_k + 1u, period, 0.0), after->rel);
                const double wx = (p1.x - p0.x) / (2.0 * period);
                const double wy = (p1.y - p0.y) / (2.0 * period);
                const double c = cos(pose.theta);
                const double s = sin(pose.theta);
                const double err = hypot(c * wx + s * wy - o->vx, -s * wx + c * wy - o->vy);
                worst_v = fmax(worst_v, err);
                char what[128];
                (void)snprintf(what, sizeof what,
                               "objects: scan %zu id %zu velocity = differenced positions (m/s)",
                               k, j);
                expect_near(what, err, 0.0, vel_tol);
            }
        }
    }
    (void)printf("objects: %zu scans x %zu objects, %u seen, %u in view but hidden, velocity "
                 "within %.2g m/s of the differenced positions\n",
                 scans, per_scan, seen, hidden, worst_v);
    expect_true("objects: some seen", seen > 0u);
    free(lines);
    wmap_free(&map);
    return 0;
}

/* standstill TRUTH OBJECTS MIN_PAIRS */
static int cmd_standstill(const char *truth_path, const char *objects_path, const char *min_text)
{
    unsigned long min_pairs = 0u;
    if (!parse_count(min_text, &min_pairs)) {
        (void)fputs("world_check standstill: bad MIN_PAIRS\n", stderr);
        return 2;
    }
    static pair_t pairs[100000];
    const size_t n = read_pairs(truth_path, pairs, sizeof pairs / sizeof pairs[0]);
    object_line_t *lines = NULL;
    const size_t nobj = read_objects(objects_path, &lines);
    size_t run = 0u;
    size_t best = 0u;
    size_t moving = 0u;
    unsigned movers_seen = 0u; /* seen objects faster than 1 m/s while still */
    for (size_t k = 0u; k < n && k < sizeof pairs / sizeof pairs[0]; k++) {
        const wpose_t r = pairs[k].rel;
        const bool still = r.x == 0.0 && r.y == 0.0 && r.theta == 0.0;
        run = still ? run + 1u : 0u;
        best = (run > best) ? run : best;
        moving += still ? 0u : 1u;
        for (size_t i = 0u; still && i < nobj; i++) {
            const object_line_t *o = &lines[i];
            movers_seen += (o->scan == pairs[k].j && o->returns > 0u &&
                            hypot(o->vx, o->vy) > 1.0) ? 1u : 0u;
        }
    }
    (void)printf("standstill: %zu pairs of exactly zero motion in a row, %zu moving pairs, "
                 "%u sightings of moving objects meanwhile\n",
                 best, moving, movers_seen);
    expect_true("standstill: long enough", best >= min_pairs);
    expect_true("standstill: and motion before or after", moving > 0u);
    expect_true("standstill: moving objects seen meanwhile", movers_seen > 0u);
    free(lines);
    return 0;
}

static int usage(void)
{
    (void)fputs("usage: world_check raycast | paths | scenarios | timing |\n"
                "       pairs TRUTH POSES N PERIOD SKIP | table2 TRUTH |\n"
                "       decode SCANS SCENARIO RES UNIT MAX_RANGE SKIP [instant|lms] |\n"
                "       objects OBJECTS SCENARIO RES MAX_RANGE SKIP instant|lms [VEL_TOL] |\n"
                "       standstill TRUTH OBJECTS MIN_PAIRS\n",
                stderr);
    return 2;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        return usage();
    }
    const char *cmd = argv[1];
    int rc;
    if (strcmp(cmd, "raycast") == 0 && argc == 2) {
        rc = cmd_raycast();
    } else if (strcmp(cmd, "paths") == 0 && argc == 2) {
        rc = cmd_paths();
    } else if (strcmp(cmd, "scenarios") == 0 && argc == 2) {
        rc = cmd_scenarios();
    } else if (strcmp(cmd, "pairs") == 0 && argc == 7) {
        rc = cmd_pairs(argv[2], argv[3], argv[4], argv[5], argv[6]);
    } else if (strcmp(cmd, "table2") == 0 && argc == 3) {
        rc = cmd_table2(argv[2]);
    } else if (strcmp(cmd, "timing") == 0 && argc == 2) {
        rc = cmd_timing();
    } else if (strcmp(cmd, "decode") == 0 && (argc == 8 || argc == 9)) {
        rc = cmd_decode(argv[2], argv[3], argv[4], argv[5], argv[6], argv[7],
                        (argc == 9) ? argv[8] : "instant");
    } else if (strcmp(cmd, "objects") == 0 && (argc == 8 || argc == 9)) {
        rc = cmd_objects(argv[2], argv[3], argv[4], argv[5], argv[6], argv[7],
                         (argc == 9) ? argv[8] : "0.02");
    } else if (strcmp(cmd, "standstill") == 0 && argc == 5) {
        rc = cmd_standstill(argv[2], argv[3], argv[4]);
    } else {
        return usage();
    }
    if (rc != 0) {
        return rc;
    }
    if (failures > 0u) {
        (void)fprintf(stderr, "world_check %s: %u failed checks\n", cmd, failures);
        return 1;
    }
    (void)printf("world_check %s: ok\n", cmd);
    return 0;
}
