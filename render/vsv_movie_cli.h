/* vsv_movie_cli.h — vsv-render's movies: frames piped to ffmpeg (program
 * code, never in a library: it exits on errors through vsv_cli_die). */
#ifndef VSV_MOVIE_CLI_H
#define VSV_MOVIE_CLI_H

#include <stdio.h>
#include <sys/types.h>

/* A movie: frames piped to ffmpeg, written under a temporary name renamed
 * into place when ffmpeg succeeds. */
typedef struct vsv_movie {
    pid_t pid;
    FILE *pipe;
    char tmp[4200];
    const char *out;
} vsv_movie;

/* Starts ffmpeg writing out (its muxer from the extension: .mp4, .m4v,
 * .mov, .mkv, .avi, .flv, .ts; H.264) from w x h frames at fps. */
void vsv_movie_open(vsv_movie *mv, const char *out, int w, int h, int fps);
/* Pipes one RGB frame. */
void vsv_movie_frame(vsv_movie *mv, const unsigned char *rgb, int w, int h);
/* Waits for ffmpeg; the movie stays a listed temporary until every output
 * of the run is complete (the caller then publishes it). */
void vsv_movie_close(vsv_movie *mv);

#endif
