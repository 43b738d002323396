/* world_map.h - 2-D maps of line segments and circles, and an exact ray
 * caster over them (host-only, doubles).
 *
 * A map is just a list of primitives: walls and building outlines are
 * segments (hit from either side), posts and trees are circles. Rays are
 * cast from a point along a unit direction; the answer is the distance to
 * the first surface, or INFINITY when the ray hits nothing.
 */
#ifndef LMSWORLD_MAP_H
#define LMSWORLD_MAP_H

#include <stddef.h>

typedef struct {
    double ax, ay, bx, by; /* end points, m */
} wseg_t;

typedef struct {
    double cx, cy, r; /* centre and radius, m */
} wcircle_t;

typedef struct {
    wseg_t *segs;
    size_t seg_count;
    size_t seg_cap;
    wcircle_t *circles;
    size_t circle_count;
    size_t circle_cap;
} wmap_t;

/* An empty map (no allocation yet). */
void wmap_init(wmap_t *map);

/* Frees the storage; the map is empty and can be used again. */
void wmap_free(wmap_t *map);

/* Empties the map and keeps its storage. */
void wmap_clear(wmap_t *map);

/* Adding primitives. Out of memory ends the program (host tool). */
void wmap_add_segment(wmap_t *map, double ax, double ay, double bx, double by);
void wmap_add_circle(wmap_t *map, double cx, double cy, double r);

/* n points xy[2i], xy[2i + 1]; closed adds the segment back to the first. */
void wmap_add_polyline(wmap_t *map, const double *xy, size_t n, int closed);

/* Axis-aligned rectangle [x0, x1] x [y0, y1]. */
void wmap_add_rect(wmap_t *map, double x0, double y0, double x1, double y1);

/* Rectangle centred on (cx, cy), its length along the heading (rad). */
void wmap_add_box(wmap_t *map, double cx, double cy, double heading, double length,
                  double width);

/* Distance from (x, y) along the unit direction (dx, dy) to the nearest
 * surface further than 1e-9 m, or INFINITY. */
double wmap_cast(const wmap_t *map, double x, double y, double dx, double dy);

/* Distance from (x, y) to the nearest surface (0 on a surface). */
double wmap_clearance(const wmap_t *map, double x, double y);

/* Appends to dst the primitives of src that a ray from (x, y) no longer
 * than radius could hit in the closed half-plane ahead of the unit
 * direction (fx, fy) (a little slack behind it); (fx, fy) = (0, 0) keeps
 * every direction. Casting a beam of that half-plane on dst gives the same
 * answer as on src up to radius. */
void wmap_select(const wmap_t *src, double x, double y, double fx, double fy, double radius,
                 wmap_t *dst);

#endif /* LMSWORLD_MAP_H */
