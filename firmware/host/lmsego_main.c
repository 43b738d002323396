/* lmsego_main.c - the lmsego command-line program (host-only): global
 * options, usage and dispatch to the subcommands.
 *
 * A subcommand is one row in `commands` below plus its cmd_*.c file;
 * nothing else needs to change to add one.
 *
 * `lmsego --version` prints "lmsego <version>" (lmsego_version.h,
 * generated from the CMake project's version).
 *
 * Exit status: 0 ok, 1 runtime error (unreadable input, an input without
 * a scan, write error), 2 usage error (no subcommand, unknown subcommand
 * or option, a value out of its range).
 */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "lmsego_version.h"

static const cli_command_t commands[] = {
    {"stats", "FILE", "count telegrams, scans and framing errors of a recorded stream", cmd_stats},
    {"scans", "[--mode HEX] FILE", "print every decoded B0 scan, one line per scan", cmd_scans},
    {"replay",
     "[--period S] [--mount X,Y,DEG] [--mode HEX] [--budget none|default|U] [--icp] [--hist KIND] [--prior FILE] "
     "[--pairs OUT] [--tum OUT] [--frames OUT] [--scan-step K] [--scan-offset O] "
     "[--times arrival|index] [--baud B] [--sweep lms|instant] [--objects OUT] FILE",
     "run the firmware loop: ego-motion CSV, one line per scan", cmd_replay},
    {"frames", "FILE", "decode a captured stream of binary ego-motion frames to the replay CSV",
     cmd_frames},
    {"import-carmen", "LOG -o STREAM [--odometry OUT] [--no-return M|none] [--stride K] [--offset O]",
     "convert a CARMEN laser log (plain or .gz) into an LMS 2xx telegram stream",
     cmd_import_carmen},
    {"run",
     "--port DEV [--baud B] [--variant DEG,RES] [--units cm|mm] [--mode HEX] [--partial] "
     "[--address A] [--power-wait S] [--mount X,Y,DEG] [--scans N] [--record FILE]",
     "bring a live scanner up and print its ego-motion CSV, one line per scan", cmd_run},
    {"record",
     "--port DEV [--baud B] [--variant DEG,RES] [--units cm|mm] [--mode HEX] [--partial] "
     "[--address A] [--power-wait S] -o FILE [--scans N]",
     "bring a live scanner up and record its stream with arrival times", cmd_record},
    {"sim",
     "[--baud B] [--source STREAM] [--faults SPEC] [--rate X] [--link PATH] [--address A] "
     "[--units cm|mm] [--power-delay MS] [--scans N]",
     "a simulated LMS 2xx on a pseudo-terminal (its path is the first output line)", cmd_sim},
    {"play", "FILE (--pty [--link PATH] | --port DEV) [--rate X] [--loop]",
     "hardware-in-loop replay: act as the scanner and play a recording with its timing",
     cmd_play},
};

#define COMMAND_COUNT (sizeof commands / sizeof commands[0])

static void print_usage(void)
{
    (void)puts("usage: lmsego <command> [options] [FILE]\n"
               "       lmsego --help | --version | <command> --help\n"
               "\n"
               "Turns the telegram stream of a SICK LMS 2xx into ego-motion: from a\n"
               "recording (the raw bytes the scanner sent, or an `lmsego record` file;\n"
               "FILE '-' reads standard input) or from a live scanner on a serial port.\n"
               "\n"
               "commands:");
    for (size_t i = 0u; i < COMMAND_COUNT; i++) {
        (void)printf("  %s %s\n      %s\n", commands[i].name, commands[i].synopsis,
                     commands[i].summary);
    }
    (void)puts("\n"
               "options:\n"
               "  -h, --help               show this help and exit\n"
               "      --version            print the version and exit\n"
               "\n"
               "exit status: 0 ok, 1 runtime error (e.g. an unreadable file, or one without a\n"
               "scan), 2 usage error; `lmsego <command> --help` says each command's own");
}

static const cli_command_t *find_command(const char *name)
{
    for (size_t i = 0u; i < COMMAND_COUNT; i++) {
        if (strcmp(commands[i].name, name) == 0) {
            return &commands[i];
        }
    }
    return NULL;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        return cli_usage_error(NULL, "missing command", NULL, NULL);
    }
    const char *first = argv[1];
    if (cli_is_help(first)) {
        print_usage();
        return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
    }
    if (strcmp(first, "--version") == 0) {
        (void)puts("lmsego " LMSEGO_VERSION);
        return cli_finish_stdout() ? CLI_EXIT_OK : CLI_EXIT_RUNTIME;
    }
    if (first[0] == '-') {
        return cli_usage_error(NULL, "unknown option", first, NULL);
    }
    const cli_command_t *cmd = find_command(first);
    if (cmd == NULL) {
        return cli_usage_error(NULL, "unknown command", first, NULL);
    }
    return cmd->run(cmd, argc - 1, argv + 1);
}
