/* world_scenario.h - the scenarios of lmsworld: a static map, the
 * scanner's trajectory and, for some, moving vehicles (host-only).
 * docs/synthetic-worlds.md describes every map and trajectory.
 */
#ifndef LMSWORLD_SCENARIO_H
#define LMSWORLD_SCENARIO_H

#include <stddef.h>

#include "world_geom.h"
#include "world_map.h"

/* A moving object (vehicle or pedestrian) at one instant: a rectangle. */
typedef struct {
    double x, y;    /* centre, m */
    double heading; /* rad, direction of its length (and of its motion) */
    double length;  /* m */
    double width;   /* m */
} wmover_t;

/* Most movers a scenario has at once (the busy-street scenarios have up
 * to 18); callers keep arrays of this size. */
#define WORLD_MAX_MOVERS 32u

/* Vehicle size used for parked and moving cars. */
#define WORLD_CAR_LENGTH 4.5
#define WORLD_CAR_WIDTH 1.8

/* Trucks of the busy-street scenarios, and pedestrians (a square). */
#define WORLD_TRUCK_LENGTH 12.0
#define WORLD_TRUCK_WIDTH 2.5
#define WORLD_PED_SIZE 0.5

typedef struct {
    const char *name;
    const char *summary;      /* one line for --help */
    unsigned default_scans;
    unsigned required_scans;  /* 0 = any number; else exactly this many */
    void (*build_map)(wmap_t *map);
    /* Scanner pose at time k * period + dt (s): dt seconds after scan k of
     * a stream whose scan period is period (dt may be negative; --timing
     * lms asks for every beam's own time). Every scenario is a smooth
     * function of time. The time comes as a scan and an offset so that at
     * dt = 0 a scenario defined per scan (fast) sees k exactly and one
     * defined per second the same k * period as before. */
    wpose_t (*pose)(unsigned k, double period, double dt);
    /* Moving objects at time t (s), at most WORLD_MAX_MOVERS; NULL: none.
     * Every call returns the same movers in the same order, so a mover's
     * index is its id (lmsworld --objects), and each is a smooth function
     * of time. */
    size_t (*movers)(double t, wmover_t *out);
} wscenario_t;

/* The scenario called name, or NULL. */
const wscenario_t *wscenario_find(const char *name);

/* All scenarios, in a fixed order. */
size_t wscenario_count(void);
const wscenario_t *wscenario_at(size_t index);

/* Table 2 of the paper: the pose of scan 1 in the frame of scan 0. */
#define WORLD_TABLE2_DX (-2.439)
#define WORLD_TABLE2_DY 3.568
#define WORLD_TABLE2_DEG 25.07

#endif /* LMSWORLD_SCENARIO_H */
