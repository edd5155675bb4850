/* vsv_exr.c — frames to OpenEXR through its C API (openexr.h): RGBA as half
 * floats (premultiplied, as compositing tools expect) and Z as float, one
 * scanline part, ZIP compression, written to a listed temporary, synced and renamed (vsv_output.c). */
#include "vsv_render.h"

#include <errno.h>
#include <fcntl.h>
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* OpenEXR's complaints: its default handler prints them; here the errno of
 * a failed write (OpenEXR's text of it is "Error writing to stream") is
 * kept for the message, per thread as the library calls it */
static _Thread_local int exr_errno;

static void on_exr_error(exr_const_context_t ctx, exr_result_t code, const char *msg)
{
    (void)ctx, (void)msg;
    if (code == EXR_ERR_WRITE_IO && !exr_errno)
        exr_errno = errno;
}

int vsv_exr_write(const char *path, const float *rgba, const float *depth, int w, int h, char *err, size_t cap)
{
    char tmp[4200];
    const int fd = vsv_output_temp(path, NULL, tmp, sizeof tmp); /* listed; OpenEXR writes it by name */
    if (fd < 0) {
        snprintf(err, cap, "%s: cannot create: %s", path, strerror(errno));
        return -1;
    }
    close(fd);
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    exr_errno = 0;
    int part = 0;
    exr_result_t rc = exr_start_write(&ctx, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
    if (!rc)
        rc = exr_add_part(ctx, "vesuvius", EXR_STORAGE_SCANLINE, &part);
    if (!rc)
        rc = exr_initialize_required_attr_simple(ctx, part, w, h, EXR_COMPRESSION_ZIP);
    static const char *const names[5] = {"R", "G", "B", "A", "Z"};
    for (int c = 0; c < 5 && !rc; c++)
        rc = exr_add_channel(ctx, part, names[c], c < 4 ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                             c < 3 ? EXR_PERCEPTUALLY_LOGARITHMIC : EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (!rc)
        rc = exr_write_header(ctx);
    int32_t lines = 1;
    if (!rc)
        rc = exr_get_scanlines_per_chunk(ctx, part, &lines);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int have_enc = 0;
    for (int y = 0; !rc && y < h; y += lines) {
        exr_chunk_info_t ci;
        rc = exr_write_scanline_chunk_info(ctx, part, y, &ci);
        if (!rc)
            rc = have_enc ? exr_encoding_update(ctx, part, &ci, &enc) : exr_encoding_initialize(ctx, part, &ci, &enc);
        if (rc)
            break;
        for (int c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            const char *n = ch->channel_name;
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = 4;
            if (!strcmp(n, "Z")) {
                ch->user_pixel_stride = 4;
                ch->user_line_stride = 4 * w;
                ch->encode_from_ptr = (const uint8_t *)(depth + (size_t)ci.start_y * w);
            } else {
                const int k = !strcmp(n, "R") ? 0 : !strcmp(n, "G") ? 1 : !strcmp(n, "B") ? 2 : 3;
                ch->user_pixel_stride = 16;
                ch->user_line_stride = 16 * w;
                ch->encode_from_ptr = (const uint8_t *)(rgba + (size_t)ci.start_y * w * 4 + k);
            }
        }
        if (!have_enc)
            rc = exr_encoding_choose_default_routines(ctx, part, &enc);
        have_enc = 1;
        if (!rc)
            rc = exr_encoding_run(ctx, part, &enc);
    }
    if (have_enc)
        exr_encoding_destroy(ctx, &enc);
    exr_result_t fr = exr_finish(&ctx);
    if (!rc)
        rc = fr;
    if (rc == EXR_ERR_WRITE_IO && exr_errno) {
        snprintf(err, cap, "%s: cannot write: %s", path, strerror(exr_errno));
        vsv_output_discard(tmp);
        return -1;
    }
    if (rc) {
        snprintf(err, cap, "%s: EXR writing failed: %s", path, exr_get_default_error_message(rc));
        vsv_output_discard(tmp);
        return -1;
    }
    /* synced before the rename: a full disk is an error, not a short file */
    const int sfd = open(tmp, O_RDONLY | O_CLOEXEC);
    if (sfd < 0 || vsv_output_commit(sfd, tmp, path)) {
        snprintf(err, cap, "%s: cannot write: %s", path, strerror(errno));
        if (sfd < 0)
            vsv_output_discard(tmp);
        return -1;
    }
    return 0;
}
