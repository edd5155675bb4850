/* fuzz_source.c — see fuzz_source.h. */
#include "fuzz_source.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[512];

static void cleanup(void)
{
    if (!dir[0])
        return;
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "fuzz: could not remove %s\n", dir);
}

/* where the scratch folder goes: $VSV_FUZZ_TMP, else /dev/shm (memory:
 * on a disk, ext4 wrote every input out when its file was truncated and
 * written again, which made the file-based targets 5 to 12 times slower,
 * tests/FUZZING.md), else $TMPDIR, else /tmp */
static const char *scratch_root(void)
{
    const char *t = getenv("VSV_FUZZ_TMP");
    if (t && *t)
        return t;
    if (access("/dev/shm", W_OK | X_OK) == 0)
        return "/dev/shm";
    t = getenv("TMPDIR");
    return t && *t ? t : "/tmp";
}

const char *fuzz_dir(void)
{
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "%s/vsv-fuzz.XXXXXX", scratch_root());
        if (!mkdtemp(dir)) {
            perror(dir);
            abort();
        }
        atexit(cleanup);
    }
    return dir;
}

const char *fuzz_put(const char *name, const void *data, size_t n)
{
    static char path[700];
    snprintf(path, sizeof path, "%s/%s", fuzz_dir(), name);
    /* a new file, not the old one truncated (see scratch_root) */
    (void)unlink(path);
    FILE *fp = fopen(path, "wb");
    if (!fp)
        return NULL;
    const int ok = fwrite(data, 1, n, fp) == n;
    return fclose(fp) == 0 && ok ? path : NULL;
}

int fuzz_source_read_all(const char *path, const vsv_source_opts *opts)
{
    vsv_source *s = NULL;
    int rc = vsv_source_open(path, opts, &s) ? -1 : 0;
    if (rc == 0) {
        const vsv_meta *g = vsv_source_grid(s);
        const size_t cells = (size_t)g->nx * g->ny * g->nz;
        char *sum = vsv_source_summary(s);
        free(sum);
        if (cells && cells <= ((size_t)1 << 20)) {
            float *buf = malloc(cells * sizeof *buf);
            for (int t = 0; buf && t < vsv_source_ntimes(s) && t < 8; t++) {
                (void)vsv_source_time(s, t);
                for (int f = 0; f < vsv_source_nfields(s); f++) {
                    if (vsv_source_read(s, f, t, buf))
                        rc++;
                }
                if (g->vert_kind == VSV_VERT_NATIVE)
                    (void)vsv_source_heights(s, t, buf);
            }
            free(buf);
        }
    }
    vsv_source_free(s);
    return rc;
}
