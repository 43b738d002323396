/* room_scene.h - the simulated world of lmsgen (host-only, doubles): a
 * closed rectangular room with pillars and boxes, and a scanner driving a
 * loop through it.
 *
 * World frame: metres, x to the right, y up, angles in radians counter-
 * clockwise from +x. The room is [0, ROOM_WIDTH_M] x [0, ROOM_DEPTH_M];
 * nothing of the furniture touches the scanner's path.
 */
#ifndef LMSGEN_ROOM_SCENE_H
#define LMSGEN_ROOM_SCENE_H

#define ROOM_WIDTH_M 12.0
#define ROOM_DEPTH_M 8.0

typedef struct {
    double x;       /* m */
    double y;       /* m */
    double heading; /* rad: the scanner's 90-degree beam points this way */
} room_pose_t;

/* Pose of the scanner at scan number k: an elliptic loop around the middle
 * of the room, counter-clockwise, one full turn every ROOM_SCANS_PER_LOOP
 * scans (about 4 cm per scan). */
#define ROOM_SCANS_PER_LOOP 400u
room_pose_t room_scanner_pose(unsigned k);

/* Distance in metres from (x, y) along the world angle to the first
 * surface. The room is closed, so every ray from inside hits something. */
double room_cast_ray(double x, double y, double angle);

#endif /* LMSGEN_ROOM_SCENE_H */
