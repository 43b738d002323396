/* commands.h - the subcommands of lmsego; lmsego_main.c lists them in its
 * dispatch table. Each one follows cli_command_fn (see cli.h). */
#ifndef LMSEGO_COMMANDS_H
#define LMSEGO_COMMANDS_H

#include "cli.h"

/* lmsego stats FILE: one line of framer and decoder counters. */
int cmd_stats(const cli_command_t *self, int argc, char **argv);

/* lmsego scans [--mode HEX] FILE: one line per decoded B0 scan. */
int cmd_scans(const cli_command_t *self, int argc, char **argv);

/* lmsego replay [--period S] [--mount X,Y,DEG] [--mode HEX] FILE: the
 * firmware loop over a recording; ego-motion CSV on stdout. */
int cmd_replay(const cli_command_t *self, int argc, char **argv);

/* lmsego frames FILE: binary ego-motion frames (ego_frame.h) back to the
 * replay CSV; decoder counters on stderr (cmd_frames.c). */
int cmd_frames(const cli_command_t *self, int argc, char **argv);

/* lmsego import-carmen LOG -o STREAM [--odometry OUT] [--no-return M|none]. */
int cmd_import_carmen(const cli_command_t *self, int argc, char **argv);

/* lmsego run --port DEV ...: a live scanner, ego-motion CSV (cmd_run.c). */
int cmd_run(const cli_command_t *self, int argc, char **argv);

/* lmsego record --port DEV ... -o FILE: the raw stream with arrival times. */
int cmd_record(const cli_command_t *self, int argc, char **argv);

/* lmsego sim ...: a simulated LMS 2xx on a pseudo-terminal (cmd_sim.c). */
int cmd_sim(const cli_command_t *self, int argc, char **argv);

/* lmsego play FILE --pty | --port DEV: hardware-in-loop replay. */
int cmd_play(const cli_command_t *self, int argc, char **argv);

#endif /* LMSEGO_COMMANDS_H */
