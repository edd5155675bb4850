/* test_bytesrc.c — the reader's byte-source interface (vsv_file_open_source):
 * a source whose bytes are poisoned (0xA5) until the reader asks for them
 * proves that the reader asks for every byte it reads (else a checksum
 * fails or a decode differs); opening asks for the header, metadata, table
 * of contents and end marker only; the hint stays inside the species'
 * payloads; a failing source's message and code reach the caller; a
 * checksum that fails on a source's bytes is fetched again once. */
#include "vsv_format.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <stdlib.h>
#include <string.h>

static synth SY = {40, 30, 12, 14, 4, 9};

typedef struct poisoned {
    vsv_byte_source pub;
    const unsigned char *real;
    unsigned char *bytes;
    size_t size;
    unsigned char *asked; /* per byte: made resident */
    uint64_t asked_bytes, calls, refetches, ahead_max;
    int fail_after; /* > 0: the need after this many fails */
    int damage;     /* the next `damage` needs deliver a flipped byte each */
    int closed;
} poisoned;

static int p_need(vsv_byte_source *s, uint64_t off, uint64_t n, uint64_t ahead, char *msg, size_t cap)
{
    poisoned *p = (poisoned *)s;
    p->calls++;
    if (p->fail_after && (int)p->calls > p->fail_after) {
        snprintf(msg, cap, "test://x: connection dropped (bytes %llu-%llu)", (unsigned long long)off,
                 (unsigned long long)(off + n - 1));
        return VSV_EIO;
    }
    if (off > p->size || n > p->size - off) {
        snprintf(msg, cap, "test://x: past the end");
        return VSV_ETRUNC;
    }
    if (ahead > p->ahead_max)
        p->ahead_max = ahead;
    for (uint64_t i = off; i < off + n; i++)
        if (!p->asked[i]) {
            p->asked[i] = 1;
            p->asked_bytes++;
            p->bytes[i] = p->real[i];
        }
    if (p->damage > 0 && n > 0) {
        p->damage--;
        p->bytes[off + n / 2] ^= 0xFF; /* a damaged cache */
    }
    return 0;
}

static int p_refetch(vsv_byte_source *s, uint64_t off, uint64_t n, char *msg, size_t cap)
{
    (void)msg, (void)cap;
    poisoned *p = (poisoned *)s;
    p->refetches++;
    memcpy(p->bytes + off, p->real + off, (size_t)n);
    return 0;
}

static void p_close(vsv_byte_source *s) { ((poisoned *)s)->closed = 1; }

static void p_init(poisoned *p, const unsigned char *real, size_t size)
{
    memset(p, 0, sizeof *p);
    p->real = real;
    p->size = size;
    p->bytes = malloc(size);
    p->asked = calloc(size, 1);
    memset(p->bytes, 0xA5, size);
    p->pub.base = p->bytes;
    p->pub.size = size;
    p->pub.need = p_need;
    p->pub.refetch = p_refetch;
    p->pub.close = p_close;
}

static void p_free(poisoned *p)
{
    free(p->bytes);
    free(p->asked);
}

int main(void)
{
    const char *path = vsv_test_tmp("bytesrc.vsv");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 8;
    o.keyframe = 5;
    char err[512] = "";
    if (!CHECK(synth_write(&SY, path, &o, err, sizeof err) == 0, "write a 14-step, 3-species series", "%s", err))
        return vsv_test_done();
    size_t size;
    unsigned char *real = vsv_test_slurp(path, &size);
    vsv_file *ref = NULL;
    CHECK(real && vsv_file_open_mem(real, size, "ref", &ref) == 0, "the reference opens from memory", "");
    vsv_file_info info;
    vsv_file_info_get(ref, &info);

    /* open: the header, metadata, table of contents and end marker only */
    poisoned p;
    p_init(&p, real, size);
    vsv_file *f = NULL;
    int rc = vsv_file_open_source(&p.pub, "test://x", &f);
    const uint64_t toc = (uint64_t)info.nsteps * 24 + 32;
    CHECK(rc == 0, "a poisoned source opens", "%s", vsv_file_error(f));
    CHECK(p.calls == 3 && p.asked_bytes <= 128 + 65536 + toc,
          "opening asks 3 times, for the header, metadata, table of contents", "%llu calls, %llu bytes of %zu",
          (unsigned long long)p.calls, (unsigned long long)p.asked_bytes, size);
    CHECK(p.asked_bytes < size / 2, "and not for the chunks", "%llu of %zu bytes", (unsigned long long)p.asked_bytes,
          size);
    p.ahead_max = 0;

    /* every volume decodes as from memory: nothing read without asking */
    const size_t n = (size_t)SY.nx * SY.ny * SY.nz;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    vsv_decoder *da = NULL, *db = NULL;
    vsv_decoder_create(f, &da);
    vsv_decoder_create(ref, &db);
    int same = 1;
    for (int t = 0; t < info.nsteps && !rc; t++)
        for (int s = 0; s < info.nspecies && !rc; s++) {
            rc = vsv_decoder_volume(da, t, s, a);
            same = same && !rc && !vsv_decoder_volume(db, t, s, b) && !memcmp(a, b, n * sizeof *a);
        }
    CHECK(rc == 0 && same, "every volume through the source equals the memory reader's", "rc %d: %s", rc,
          vsv_decoder_error(da));
    CHECK(p.asked_bytes < size, "and the bytes asked for are fewer than the file's (no padding read)", "%llu of %zu",
          (unsigned long long)p.asked_bytes, size);
    CHECK(p.ahead_max > 0 && p.ahead_max < size / (size_t)info.nsteps * 2, "the hint reaches ahead within one chunk",
          "largest hint %llu", (unsigned long long)p.ahead_max);
    rc = vsv_file_check(f, NULL, NULL);
    CHECK(rc == 0 && p.asked_bytes == size, "vsv_file_check asks for every byte and passes", "%s (%llu of %zu)",
          vsv_file_error(f), (unsigned long long)p.asked_bytes, size);
    vsv_decoder_free(da);
    vsv_file_free(f);
    CHECK(p.closed, "vsv_file_free closes the source", "");
    p_free(&p);

    /* a source that fails: its message and code */
    p_init(&p, real, size);
    p.fail_after = 3;
    rc = vsv_file_open_source(&p.pub, "test://x", &f);
    vsv_decoder_create(f, &da);
    const int drc = vsv_decoder_volume(da, 1, 0, a);
    CHECK(rc == 0 && drc == VSV_EIO && strstr(vsv_decoder_error(da), "test://x: connection dropped (bytes "),
          "a failing need: the source's code and message", "%d: %s", drc, vsv_decoder_error(da));
    vsv_decoder_free(da);
    vsv_file_free(f);
    p_free(&p);
    p_init(&p, real, size);
    p.fail_after = 1;
    rc = vsv_file_open_source(&p.pub, "test://x", &f);
    CHECK(rc == VSV_EIO && f && strstr(vsv_file_error(f), "test://x: connection dropped"), "failing at open: the same",
          "%d: %s", rc, f ? vsv_file_error(f) : "");
    vsv_file_free(f);
    p_free(&p);

    /* a damaged byte is fetched again, once, and then decodes right */
    p_init(&p, real, size);
    rc = vsv_file_open_source(&p.pub, "test://x", &f);
    p.damage = 2; /* the first chunk index, then the first payload */
    vsv_decoder_create(f, &da);
    same = 1;
    for (int t = 0; t < info.nsteps && !rc; t++)
        for (int s = 0; s < info.nspecies && !rc; s++) {
            rc = vsv_decoder_volume(da, t, s, a);
            same = same && !rc && !vsv_decoder_volume(db, t, s, b) && !memcmp(a, b, n * sizeof *a);
        }
    CHECK(rc == 0 && same && p.refetches == 2, "damaged bytes (an index, a payload) are fetched again and decode right",
          "rc %d, %llu refetches: %s", rc, (unsigned long long)p.refetches, vsv_decoder_error(da));
    vsv_decoder_free(da);
    vsv_file_free(f);
    p_free(&p);

    vsv_decoder_free(db);
    vsv_file_free(ref);
    free(a);
    free(b);
    free(real);
    return vsv_test_done();
}
