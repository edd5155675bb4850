/* fuzz_player.c — fuzz target for the action language of vsv-play and its
 * --script files (viewer/vsv_player.h): a script, one action per line with
 * the optional leading SECONDS of a --script line, run against a player on
 * the golden file (clock and state only, as FreeVR's input process runs
 * it: no pager, no renderer), advancing the clock between actions. Built
 * for libFuzzer by `make fuzz`; also runs as a regression test over
 * tests/corpus/player (fuzz_main.c). */
#include "vsv_player.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/player", NULL, NULL, NULL};
const char fuzz_label[] = "player action language";

/* the golden file: $VSV_FUZZ_VSV, else tests/golden/small.vsv (run from the top) */
static const char *golden(void)
{
    const char *g = getenv("VSV_FUZZ_VSV");
    return g && *g ? g : "tests/golden/small.vsv";
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 16384)
        return 0;
    vsv_player_opts o;
    vsv_player_opts_init(&o);
    o.path = golden();
    o.clock_only = 1;
    vsv_player *p = NULL;
    char err[512];
    if (vsv_player_open(&o, &p, err, sizeof err)) {
        fprintf(stderr, "fuzz_player: %s\n", err);
        abort(); /* the harness itself is broken */
    }
    char line[1200];
    size_t at = 0;
    while (at < size && !vsv_player_quit(p)) {
        size_t n = 0;
        while (at < size && data[at] != '\n' && n < sizeof line - 1)
            line[n++] = (char)data[at++];
        while (at < size && data[at] != '\n')
            at++;
        at++;
        line[n] = 0;
        /* a --script line: SECONDS ACTION; else the action itself */
        char *end;
        double when = strtod(line, &end);
        const char *action = end != line && (*end == ' ' || *end == '\t') ? end + 1 : line;
        (void)vsv_player_do(p, action, err, sizeof err);
        vsv_player_tick(p, when > 0 && when < 1e6 ? when : 0.25);
        (void)vsv_player_take_screenshot(p);
        vsv_player_state st;
        vsv_player_state_get(p, &st);
        char status[2048];
        vsv_player_status(p, status, sizeof status);
    }
    vsv_player_free(p);
    return 0;
}
