/* fuzz_text.c — fuzz target for the project's small text languages: the
 * transfer-function text (SPEC.md §14, vsv_tf_parse, then prepared and
 * evaluated), the time grammar (vsv_timesel_parse, vsv_time_parse,
 * vsv_duration_parse) and the FreeVR configuration counter
 * (vsv_freevr_conf.h). The first byte chooses the parser, the rest is the
 * text. Built for libFuzzer by `make fuzz`; also runs as a regression test
 * over tests/corpus/text (fuzz_main.c). */
#include "vsv_format.h"
#include "vsv_freevr_conf.h"
#include "vsv_render.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/text", NULL, NULL, NULL};
const char fuzz_label[] = "text parsers (transfer functions, times, FreeVR configuration)";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1 || size > 65536)
        return 0;
    char *text = malloc(size);
    if (!text)
        return 0;
    memcpy(text, data + 1, size - 1);
    text[size - 1] = 0;
    char msg[512];
    switch (data[0] % 4) {
    case 0: {
        vsv_tf *tf = calloc(1, sizeof *tf);
        if (tf && vsv_tf_parse(tf, text, msg, sizeof msg) == 0 && vsv_tf_prepare(tf) == 0) {
            float rgba[4];
            for (int i = -2; i <= 12; i++)
                vsv_tf_eval(tf, (float)(tf->lo + (tf->hi - tf->lo) * i / 10.0), rgba);
            char buf[1024];
            vsv_tf_format(tf, buf, sizeof buf);
        }
        free(tf);
        break;
    }
    case 1: {
        static const int64_t times[5] = {946684800, 946688400, 946692000, 946695600, 946699200};
        vsv_timesel sel;
        (void)vsv_timesel_parse(text, times, 5, 0, &sel, msg, sizeof msg);
        (void)vsv_timesel_parse(text, times, 5, VSV_TIMESEL_ONE, &sel, msg, sizeof msg);
        (void)vsv_timesel_parse(text, NULL, 0, 0, &sel, msg, sizeof msg);
        break;
    }
    case 2: {
        int64_t t;
        (void)vsv_time_parse(text, &t);
        if (vsv_duration_parse(text, &t) == 0)
            vsv_duration_format(t, msg, sizeof msg);
        break;
    }
    default: {
        /* several texts, as FreeVR reads its files and variables */
        const char *texts[4] = {text, NULL, NULL, NULL};
        int n = 1;
        for (char *p = text; n < 4 && (p = strchr(p, '\f')); p++)
            texts[n++] = p + 1;
        vsv_freevr_layout l;
        vsv_freevr_layout_count(texts, n, &l);
        (void)vsv_freevr_arena_bytes(&l, 1u << 20);
    }
    }
    free(text);
    return 0;
}
