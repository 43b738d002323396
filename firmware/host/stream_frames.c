/* stream_frames.c - see stream_frames.h. */
#include "stream_frames.h"

#include <stdio.h>
#include <string.h>

#include "cli.h"

/* Events a framer may report without consuming input: at most one per
 * byte it holds, plus one. More than that in a row means a broken framer;
 * stop instead of spinning (the tool must terminate on any input). */
#define STREAM_FRAMES_MAX_IDLE_EVENTS (LMS_FRAMER_BUF_SIZE + 2u)

/* Where telegrams go, and the arrival time of the bytes being fed. */
typedef struct {
    stream_telegram_fn fn;
    void *ctx;
    uint64_t time_us;
} sink_t;

/* Passes a telegram event on; 0 = go on. */
static int report(lms_framer_t *framer, lms_framer_event_t event, const sink_t *sink)
{
    if (event != LMS_FRAMER_TELEGRAM) {
        return 0;
    }
    size_t len = 0u;
    const uint8_t *telegram = lms_framer_telegram(framer, &len);
    if (telegram == NULL || len == 0u) {
        return 0;
    }
    return sink->fn(sink->ctx, telegram, len, sink->time_us);
}

/* Feeds one chunk completely. */
static stream_frames_result_t feed_chunk(lms_framer_t *framer, const uint8_t *chunk, size_t len,
                                         const sink_t *sink)
{
    size_t offset = 0u;
    size_t idle_events = 0u;
    for (;;) {
        size_t consumed = 0u;
        const lms_framer_event_t event =
            lms_framer_feed(framer, chunk + offset, len - offset, &consumed);
        if (consumed > len - offset) {
            return STREAM_FRAMES_STUCK;
        }
        offset += consumed;
        if (event == LMS_FRAMER_NEED_MORE) {
            return (offset == len) ? STREAM_FRAMES_DONE : STREAM_FRAMES_STUCK;
        }
        idle_events = (consumed == 0u) ? idle_events + 1u : 0u;
        if (idle_events > STREAM_FRAMES_MAX_IDLE_EVENTS) {
            return STREAM_FRAMES_STUCK;
        }
        if (report(framer, event, sink) != 0) {
            return STREAM_FRAMES_STOPPED;
        }
    }
}

/* End of input: flush until the framer holds nothing. */
static stream_frames_result_t flush_all(lms_framer_t *framer, const sink_t *sink)
{
    for (size_t events = 0u; events <= STREAM_FRAMES_MAX_IDLE_EVENTS; events++) {
        const lms_framer_event_t event = lms_framer_flush(framer);
        if (event == LMS_FRAMER_NEED_MORE) {
            return STREAM_FRAMES_DONE;
        }
        if (report(framer, event, sink) != 0) {
            return STREAM_FRAMES_STOPPED;
        }
    }
    return STREAM_FRAMES_STUCK;
}

stream_frames_result_t stream_frames_run(stream_file_t *in, lms_framer_t *framer,
                                         stream_telegram_fn on_telegram, void *ctx)
{
    uint8_t chunk[STREAM_FILE_CHUNK];
    sink_t sink = {on_telegram, ctx, 0u};
    for (;;) {
        size_t got = 0u;
        const stream_read_t r = stream_file_read(in, chunk, sizeof chunk, &got);
        if (r == STREAM_READ_ERROR) {
            return STREAM_FRAMES_READ_ERROR;
        }
        if (r == STREAM_READ_END) {
            return flush_all(framer, &sink);
        }
        sink.time_us = in->is_recording ? in->time_us : 0u;
        const stream_frames_result_t fed = feed_chunk(framer, chunk, got, &sink);
        if (fed != STREAM_FRAMES_DONE) {
            return fed;
        }
    }
}

void stream_frames_read_error(const stream_file_t *in, const char *shown)
{
    /* A malformed recording says what and where, anything else errno. */
    char why[128];
    cli_file_error((in->bad != NULL) ? "bad recording " : "error reading ", shown,
                   stream_file_problem(in, why, sizeof why));
}

void stream_frames_no_scan(const char *cmd, const char *shown, const lms_framer_stats_t *st,
                           unsigned long refused)
{
    char context[64];
    char problem[160];
    (void)snprintf(context, sizeof context, "%s: no scan in ", cmd);
    if (st->telegrams == 0u) {
        (void)snprintf(problem, sizeof problem, "%lu bytes, no valid LMS telegram",
                       (unsigned long)st->bytes_in);
    } else if (refused == 0u) {
        (void)snprintf(problem, sizeof problem, "%lu bytes, %lu telegrams, none a scan (B0)",
                       (unsigned long)st->bytes_in, (unsigned long)st->telegrams);
    } else {
        (void)snprintf(problem, sizeof problem,
                       "%lu bytes, %lu telegrams, %lu scans (B0) that do not decode",
                       (unsigned long)st->bytes_in, (unsigned long)st->telegrams, refused);
    }
    cli_file_error(context, shown, problem);
}

int stream_frames_run_path(const char *path, lms_framer_t *framer, stream_telegram_fn on_telegram,
                           void *ctx)
{
    /* In messages, stdin is "<stdin>" rather than "-". */
    const char *shown = (strcmp(path, "-") == 0) ? "<stdin>" : path;
    stream_file_t in;
    const int open_error = stream_file_open(&in, path);
    if (open_error != 0) {
        cli_file_error("cannot open ", shown, strerror(open_error));
        return CLI_EXIT_RUNTIME;
    }
    lms_framer_init(framer, LMS_FROM_SCANNER);
    const stream_frames_result_t result = stream_frames_run(&in, framer, on_telegram, ctx);
    stream_file_close(&in);

    switch (result) {
    case STREAM_FRAMES_DONE:
        return CLI_EXIT_OK;
    case STREAM_FRAMES_READ_ERROR:
        stream_frames_read_error(&in, shown);
        return CLI_EXIT_RUNTIME;
    case STREAM_FRAMES_STUCK:
        cli_file_error("internal error while framing ", shown, "the framer made no progress");
        return CLI_EXIT_RUNTIME;
    case STREAM_FRAMES_STOPPED:
        break;
    }
    return CLI_EXIT_RUNTIME; /* the callback stopped the run and said why */
}
