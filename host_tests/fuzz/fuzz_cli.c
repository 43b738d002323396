/* fuzz_cli.c - libFuzzer target over the command-line option parsers of
 * lmsego (firmware/host/cli_options.h: replay, import-carmen, run,
 * record, sim, play) and the value parsers they share (cli.h).
 *
 * Input: byte 0 picks the parser (b % 7: replay, import-carmen, run,
 * record, sim, play, or the shared value parsers); the rest is split at
 * NUL bytes into up to 24 arguments (argv[0] is the command's name). The
 * seeds are command lines of the CLI tests (firmware/host/tests/).
 *
 * Checks (abort on violation):
 *  - a parser returns CLI_PARSED, CLI_PARSED_HELP or CLI_EXIT_USAGE, or
 *    CLI_EXIT_RUNTIME only when --help / -h was given (stdout failed);
 *  - it is a pure function of argv: a second call on a fresh struct gives
 *    the same return and the same struct, and argv is left unchanged;
 *  - every string it keeps points to one of the arguments;
 *  - CLI_PARSED means the command can run on it: replay has a FILE, a
 *    step 1..100000, an offset <= 100000, a period 0 or 1 ms .. 10 s, a line
 *    rate and measuring mode it knows, not both --times; import-carmen
 *    has LOG and -o, a stride 1..100000, an offset below it and a
 *    no-return > 0; run and record a --port (record -o too) and a session
 *    configuration lms_session_check_config accepts; play exactly one of
 *    --pty and --port and a FILE;
 *  - the value parsers: cli_parse_whole accepts only digits and a value
 *    within [min, max], cli_parse_meas_mode only 00..06 and 0F,
 *    cli_parse_double only finite numbers, cli_parse_mount only |X|, |Y|
 *    <= 100 m;
 *  - no crash, no undefined behaviour (ASan, UBSan).
 * The parsers print help and usage errors: run it with -close_fd_mask=3.
 */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "cli_options.h"
#include "fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_ARGS 24
#define MAX_TEXT 4096u

typedef struct {
    int argc;
    char *argv[MAX_ARGS + 1];
    char name[16];
    char text[MAX_TEXT + 1u];
    size_t len;
} args_t;

static const cli_command_t commands[6] = {
    {"replay", "", "", NULL},  {"import-carmen", "", "", NULL}, {"run", "", "", NULL},
    {"record", "", "", NULL},  {"sim", "", "", NULL},           {"play", "", "", NULL},
};

static void split(args_t *a, const char *name, const uint8_t *bytes, size_t n)
{
    if (n > MAX_TEXT) {
        n = MAX_TEXT;
    }
    memcpy(a->text, bytes, n);
    a->text[n] = '\0';
    a->len = n + 1u;
    a->argc = 0;
    (void)snprintf(a->name, sizeof a->name, "%s", name);
    a->argv[a->argc++] = a->name;
    size_t at = 0u;
    while (at < n && a->argc < MAX_ARGS) {
        a->argv[a->argc++] = &a->text[at];
        at += strlen(&a->text[at]) + 1u;
    }
    a->argv[a->argc] = NULL;
}

/* p is NULL or one of the arguments. */
static bool in_argv(const args_t *a, const char *p)
{
    if (p == NULL) {
        return true;
    }
    for (int i = 1; i < a->argc; i++) {
        if (p == a->argv[i]) {
            return true;
        }
    }
    return false;
}

static bool has_help(const args_t *a)
{
    for (int i = 1; i < a->argc; i++) {
        if (cli_is_help(a->argv[i])) {
            return true;
        }
    }
    return false;
}

static void check_rc(const args_t *a, int rc)
{
    FUZZ_CHECK(rc == CLI_PARSED || rc == CLI_PARSED_HELP || rc == CLI_EXIT_USAGE ||
               (rc == CLI_EXIT_RUNTIME && has_help(a)));
    FUZZ_CHECK(rc != CLI_PARSED_HELP || has_help(a));
}

static bool known_mode(uint8_t mode)
{
    return mode <= 0x06u || mode == 0x0Fu;
}

static void fuzz_replay(const cli_command_t *self, args_t *a)
{
    static replay_options_t o;
    static replay_options_t again;
    memset(&o, 0, sizeof o);
    memset(&again, 0, sizeof again);
    replay_options_defaults(&o);
    replay_options_defaults(&again);
    const int rc = replay_parse_options(self, a->argc, a->argv, &o);
    check_rc(a, rc);
    FUZZ_CHECK(replay_parse_options(self, a->argc, a->argv, &again) == rc);
    FUZZ_CHECK(memcmp(&o, &again, sizeof o) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): both zeroed first, padding equal
    FUZZ_CHECK(in_argv(a, o.path) && in_argv(a, o.pairs_path) && in_argv(a, o.prior_path) &&
               in_argv(a, o.tum_path) && in_argv(a, o.frames_path));
    if (rc != CLI_PARSED) {
        return;
    }
    FUZZ_CHECK(o.path != NULL);
    FUZZ_CHECK(o.scan_step >= 1u && o.scan_step <= 100000u && o.scan_offset <= 100000u);
    /* 0: each scan's own period (ego_loop.h), else --period's. */
    FUZZ_CHECK(o.config.period_us == 0u ||
               (o.config.period_us >= 1000u && o.config.period_us <= 10000000u));
    FUZZ_CHECK((unsigned)o.baud < LMS_BAUD_COUNT);
    FUZZ_CHECK(known_mode(o.config.lms.meas_mode));
    FUZZ_CHECK(!(o.times_index && o.times_arrival));
    FUZZ_CHECK(o.config.ego.work_per_s == 0u || o.config.ego.work_per_s >= 100000u);
}

static void fuzz_import(const cli_command_t *self, args_t *a)
{
    import_options_t o;
    import_options_t again;
    memset(&o, 0, sizeof o);
    memset(&again, 0, sizeof again);
    import_options_defaults(&o);
    import_options_defaults(&again);
    const int rc = import_carmen_parse_options(self, a->argc, a->argv, &o);
    check_rc(a, rc);
    FUZZ_CHECK(import_carmen_parse_options(self, a->argc, a->argv, &again) == rc);
    FUZZ_CHECK(memcmp(&o, &again, sizeof o) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): both zeroed first, padding equal
    FUZZ_CHECK(in_argv(a, o.log_path) && in_argv(a, o.out_path) && in_argv(a, o.odom_path));
    if (rc != CLI_PARSED) {
        return;
    }
    FUZZ_CHECK(o.log_path != NULL && o.out_path != NULL);
    FUZZ_CHECK(o.stride >= 1u && o.stride <= 100000u && o.offset < o.stride);
    FUZZ_CHECK(o.no_return == 0.0 || o.no_return > 0.0);
}

static void fuzz_live(const cli_command_t *self, args_t *a, bool record)
{
    static live_options_t o;
    static live_options_t again;
    live_options_defaults(&o);
    live_options_defaults(&again);
    const int rc = live_parse_options(self, a->argc, a->argv, record, &o);
    check_rc(a, rc);
    FUZZ_CHECK(live_parse_options(self, a->argc, a->argv, record, &again) == rc);
    FUZZ_CHECK(memcmp(&o, &again, sizeof o) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): both zeroed first, padding equal
    FUZZ_CHECK(in_argv(a, o.port) && in_argv(a, o.out_path));
    if (rc != CLI_PARSED) {
        return;
    }
    FUZZ_CHECK(o.port != NULL && (!record || o.out_path != NULL));
    FUZZ_CHECK(lms_session_check_config(&o.session) == LMS_OK);
    FUZZ_CHECK(o.session.meas_mode == LMS_SESSION_KEEP || known_mode(o.session.meas_mode));
}

static void fuzz_sim(const cli_command_t *self, args_t *a, bool play)
{
    static sim_options_t o;
    static sim_options_t again;
    sim_options_defaults(&o);
    sim_options_defaults(&again);
    const int rc = sim_parse_options(self, a->argc, a->argv, play, &o);
    check_rc(a, rc);
    FUZZ_CHECK(sim_parse_options(self, a->argc, a->argv, play, &again) == rc);
    FUZZ_CHECK(memcmp(&o, &again, sizeof o) == 0); // NOLINT(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): both zeroed first, padding equal
    FUZZ_CHECK(in_argv(a, o.source) && in_argv(a, o.link) && in_argv(a, o.port));
    if (rc != CLI_PARSED) {
        return;
    }
    FUZZ_CHECK(!play || (o.source != NULL && o.pty != (o.port != NULL)));
    FUZZ_CHECK(o.sim.address <= 0x7Fu);
}

static bool all_digits(const char *t)
{
    if (t[0] == '\0') {
        return false;
    }
    for (; *t != '\0'; t++) {
        if (*t < '0' || *t > '9') {
            return false;
        }
    }
    return true;
}

/* The shared value parsers on each argument. */
static void fuzz_values(const args_t *a)
{
    for (int i = 1; i < a->argc; i++) {
        const char *t = a->argv[i];
        unsigned long v = 0u;
        const unsigned long lo = (unsigned long)(strlen(t) % 7u);
        const unsigned long hi = lo + 100000u;
        if (cli_parse_whole(t, lo, hi, &v) == 0) {
            FUZZ_CHECK(all_digits(t) && v >= lo && v <= hi);
        }
        uint8_t mode = 0xEEu;
        if (cli_parse_meas_mode(t, &mode) == 0) {
            FUZZ_CHECK(known_mode(mode));
        }
        double d = 0.0;
        if (cli_parse_double(t, &d) == 0) {
            FUZZ_CHECK(isfinite(d));
        }
        ego_lms_params_t lms;
        ego_lms_defaults(&lms);
        if (cli_parse_mount(t, &lms) == 0) {
            FUZZ_CHECK(lms.mount_x >= -100 * 65536 && lms.mount_x <= 100 * 65536);
            FUZZ_CHECK(lms.mount_y >= -100 * 65536 && lms.mount_y <= 100 * 65536);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static args_t a;
    static char copy[MAX_TEXT + 1u];
    if (size < 1u) {
        return 0;
    }
    const unsigned pick = data[0] % 7u;
    split(&a, (pick < 6u) ? commands[pick].name : "values", data + 1, size - 1u);
    memcpy(copy, a.text, a.len);
    switch (pick) {
    case 0u:
        fuzz_replay(&commands[0], &a);
        break;
    case 1u:
        fuzz_import(&commands[1], &a);
        break;
    case 2u:
    case 3u:
        fuzz_live(&commands[pick], &a, pick == 3u);
        break;
    case 4u:
    case 5u:
        fuzz_sim(&commands[pick], &a, pick == 5u);
        break;
    default:
        fuzz_values(&a);
        break;
    }
    FUZZ_CHECK(memcmp(copy, a.text, a.len) == 0); /* argv untouched */
    return 0;
}
