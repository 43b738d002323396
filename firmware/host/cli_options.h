/* cli_options.h - the option parsers of the lmsego subcommands that take
 * more than a FILE (host-only), each apart from the command that runs on
 * its result, so that they can be tested and fuzzed alone
 * (host_tests/fuzz/fuzz_cli.c).
 *
 * Each parser reads argv[1..argc-1] (argv[0] is the command's name) into
 * the caller's struct, which the caller has set to the command's defaults
 * first, and returns CLI_PARSED, CLI_PARSED_HELP (--help was printed on
 * stdout: nothing else to do) or an exit code (a usage error was printed
 * on stderr: CLI_EXIT_USAGE; stdout failed while printing the help:
 * CLI_EXIT_RUNTIME). They open no file, start nothing and keep no state;
 * the strings in the struct point into argv.
 */
#ifndef LMSEGO_CLI_OPTIONS_H
#define LMSEGO_CLI_OPTIONS_H

#include <stdbool.h>

#include "cli.h"
#include "ego_loop.h"
#include "lms_session.h"
#include "lms_sim.h"

#define CLI_PARSED 0
#define CLI_PARSED_HELP (-1)

/* replay (cmd_replay.c). Defaults: config from ego_loop_defaults and
 * ego_budget_defaults, step 1, offset 0, baud 500000, the rest 0/NULL. */
typedef struct {
    const char *path;
    const char *pairs_path;
    const char *prior_path;
    const char *tum_path;
    const char *frames_path;
    const char *objects_path; /* --objects */
    unsigned long scan_step;
    unsigned long scan_offset;
    int times_index;   /* --times index */
    int times_arrival; /* --times arrival */
    lms_baud_t baud;
    ego_loop_config_t config;
} replay_options_t;

void replay_options_defaults(replay_options_t *o);
int replay_parse_options(const cli_command_t *self, int argc, char **argv, replay_options_t *o);

/* import-carmen (cmd_import_carmen.c). Defaults: no_return 0 (the log's
 * largest reading; INFINITY: none), stride 1, offset 0, paths NULL. */
typedef struct {
    const char *log_path;
    const char *out_path;
    const char *odom_path;
    double no_return;
    unsigned long stride;
    unsigned long offset; /* < stride */
} import_options_t;

void import_options_defaults(import_options_t *o);
int import_carmen_parse_options(const cli_command_t *self, int argc, char **argv,
                                import_options_t *o);

/* run and record (cmd_run.c). Defaults: session and loop from
 * ego_live_defaults, the rest 0/NULL. */
typedef struct {
    const char *port;
    const char *out_path;  /* record */
    unsigned long scans;   /* 0: until a signal */
    bool run_records;      /* run --record */
    lms_session_config_t session;
    ego_loop_config_t loop;
} live_options_t;

void live_options_defaults(live_options_t *o);
int live_parse_options(const cli_command_t *self, int argc, char **argv, bool record,
                       live_options_t *o);

/* sim and play (cmd_sim.c). Defaults: sim from lms_sim_defaults, the
 * rest 0/NULL. */
typedef struct {
    const char *source;   /* sim --source / play FILE */
    const char *link;
    const char *port;
    bool pty;
    bool loop;
    unsigned long scans;  /* sim: stop after N (0: never) */
    lms_sim_config_t sim;
} sim_options_t;

void sim_options_defaults(sim_options_t *o);
int sim_parse_options(const cli_command_t *self, int argc, char **argv, bool play,
                      sim_options_t *o);

#endif /* LMSEGO_CLI_OPTIONS_H */
