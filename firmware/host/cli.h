/* cli.h - shared pieces of the lmsego command-line program (host-only):
 * exit codes, the subcommand table entry, and one-line error messages.
 *
 * Every message goes to stderr as a single line starting "lmsego: ".
 * File names are printed with non-printable bytes replaced by '?', so a
 * hostile name cannot break the one-line rule.
 */
#ifndef LMSEGO_CLI_H
#define LMSEGO_CLI_H

#include <stdbool.h>
#include <stdint.h>

#include "ego.h"
#include "ego_lms.h"

/* Exit codes of lmsego and of every subcommand. */
#define CLI_EXIT_OK 0      /* success */
#define CLI_EXIT_RUNTIME 1 /* the input could not be read, output failed, ... */
#define CLI_EXIT_USAGE 2   /* bad command line */

struct cli_command;

/* A subcommand: argv[0] is its own name, argv[1..argc-1] its arguments.
 * Returns one of the CLI_EXIT_* codes. */
typedef int (*cli_command_fn)(const struct cli_command *self, int argc, char **argv);

typedef struct cli_command {
    const char *name;     /* word after "lmsego" */
    const char *synopsis; /* arguments, e.g. "[--mode HEX] FILE" */
    const char *summary;  /* one line for the help text */
    cli_command_fn run;
} cli_command_t;

/* "lmsego: <text>" on stderr. */
void cli_error(const char *text);

/* "lmsego: <context>'<file>': <problem>" on stderr, e.g.
 * cli_file_error("cannot open ", "scan.lms", "No such file or directory"). */
void cli_file_error(const char *context, const char *file, const char *problem);

/* Usage error on stderr, one line:
 *   "lmsego: <cmd>: <problem> '<arg>' (<detail>); try 'lmsego <cmd> --help'"
 * cmd, arg and detail may be NULL (then their parts are left out).
 * Returns CLI_EXIT_USAGE. */
int cli_usage_error(const cli_command_t *cmd, const char *problem, const char *arg,
                    const char *detail);

/* The help of one subcommand on stdout: "usage: lmsego <name> <synopsis>",
 * its summary, then help (may be NULL): what it reads, its options with
 * units and defaults, what it writes and its exit status. Each command
 * keeps its help text beside the code that parses its options. */
void cli_print_command_usage(const cli_command_t *cmd, const char *help);

/* The input of the commands that read a recorded stream, for their help. */
#define CLI_HELP_STREAM_INPUT                                                                    \
    "input:\n"                                                                                   \
    "  FILE          a recorded telegram stream: the raw bytes an LMS 2xx sent (scanner ->\n"    \
    "                host), or a recording of `lmsego record` (the same with arrival\n"          \
    "                times); '-' reads standard input\n"

/* The exit status of the commands that read one FILE, for their help. */
#define CLI_HELP_EXIT_STATUS                                                                     \
    "exit status: 0 ok; 1 the input cannot be read, holds no scan (no valid LMS\n"              \
    "  telegram at all: an empty file, noise, zeros), or output failed; 2 bad command line\n"

/* The output columns of replay / run on stdout, with units; the time
 * column as time_text says (what its zero is); latency: run's latency_ms
 * column too. The flag bits are those of estimator/ego.h. */
void cli_print_csv_columns(const char *time_text, bool latency);

/* True for "-h" and "--help". */
bool cli_is_help(const char *arg);

/* Flushes stdout; on a write error prints a message and returns false. */
bool cli_finish_stdout(void);

/* The --mode argument: one or two hex digits, optional 0x prefix, and only
 * the range modes 00..06 and 0F. Returns 0 on success. */
int cli_parse_meas_mode(const char *text, uint8_t *mode);

/* A whole number in [min, max], decimal digits only (strtoul alone would
 * take "-1", " 2" or "3x"). Returns 0 on success. */
int cli_parse_whole(const char *text, unsigned long min, unsigned long max, unsigned long *out);

/* A non-option argument: the command's one file (stdin is "-"). An option
 * it does not know, or a second file, is a usage error (its exit code is
 * returned); CLI_EXIT_OK when *path took arg. */
int cli_take_file(const cli_command_t *cmd, const char *arg, const char **path);

/* A finite double, the whole text. Returns 0 on success. */
int cli_parse_double(const char *text, double *out);

/* --mount "X,Y,THETA_DEG" (m, m, deg; |X|, |Y| <= 100) -> the mounting
 * pose of the scanner on the vehicle. Returns 0 on success. */
int cli_parse_mount(const char *text, ego_lms_params_t *lms);

#endif /* LMSEGO_CLI_H */
