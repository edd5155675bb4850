/* vsv_movie_cli.c — see vsv_movie_cli.h. */
#include "vsv_movie_cli.h"

#include "vsv_cli.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

static int have_program(const char *name)
{
    const char *path = getenv("PATH");
    if (!path)
        return 0;
    char *copy = strdup(path), *save = NULL;
    if (!copy)
        return 0;
    int found = 0;
    for (char *dir = strtok_r(copy, ":", &save); dir && !found; dir = strtok_r(NULL, ":", &save)) {
        char full[4200];
        snprintf(full, sizeof full, "%s/%s", *dir ? dir : ".", name);
        found = access(full, X_OK) == 0;
    }
    free(copy);
    return found;
}

/* ffmpeg's muxer for the movie's extension (H.264 in each), or NULL. */
static const char *movie_muxer(const char *out)
{
    static const char *const map[][2] = {{".mp4", "mp4"}, {".m4v", "mp4"}, {".mov", "mov"},  {".mkv", "matroska"},
                                         {".avi", "avi"}, {".flv", "flv"}, {".ts", "mpegts"}};
    const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (!dot || (slash && dot < slash))
        return NULL;
    for (size_t i = 0; i < sizeof map / sizeof *map; i++)
        if (!strcasecmp(dot, map[i][0]))
            return map[i][1];
    return NULL;
}

void vsv_movie_open(vsv_movie *mv, const char *out, int w, int h, int fps)
{
    if (!have_program("ffmpeg"))
        vsv_cli_die(1, "--movie needs ffmpeg, which is not installed (apt-get install ffmpeg)");
    const char *muxer = movie_muxer(out);
    if (!muxer)
        vsv_cli_usage_error("--movie %s: name a .mp4, .m4v, .mov, .mkv, .avi, .flv or .ts file", out);
    /* listed (vsv_output.c): removed on an error exit or a signal. ffmpeg
     * writes it as its descriptor 3 (/proc/self/fd/3), never by name: were
     * the tool killed before ffmpeg opened its output, a name would be
     * created again after the tool removed it (the SIGTERM sweep left
     * 'OUT.tmp.PID.0.mp4' so) */
    const int tfd = vsv_output_temp(out, strrchr(out, '.'), mv->tmp, sizeof mv->tmp);
    if (tfd < 0)
        vsv_cli_die(1, "%s: cannot create: %s", out, strerror(errno));
    mv->out = out;
    int fd[2];
    if (pipe2(fd, O_CLOEXEC))
        vsv_cli_die(1, "cannot start ffmpeg: %s", strerror(errno));
    char size[64], rate[32];
    snprintf(size, sizeof size, "%dx%d", w, h);
    snprintf(rate, sizeof rate, "%d", fps);
    /* -xerror: a failed write of the output (a full disk) is exit 1, not 0 */
    /* clang-format off */ /* (a table, laid out by hand) */
    char *const args[] = {"ffmpeg", "-hide_banner", "-loglevel", "error", "-xerror", "-nostdin", "-y", "-f", "rawvideo",
                          "-pix_fmt", "rgb24", "-s", size, "-r", rate, "-i", "pipe:0", "-an", "-vf",
                          "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "18",
                          "-f", (char *)muxer, "file:/proc/self/fd/3", NULL};
    /* clang-format on */
    /* posix_spawnp: nothing of ours runs between fork and exec (the
     * renderer's threads may exist; a forked copy must not touch a lock) */
    posix_spawn_file_actions_t fa;
    posix_spawnattr_t at;
    sigset_t dfl;
    sigemptyset(&dfl);
    sigaddset(&dfl, SIGPIPE); /* ignored here (below), not in ffmpeg */
    int rc = posix_spawn_file_actions_init(&fa);
    if (!rc && (rc = posix_spawnattr_init(&at)))
        posix_spawn_file_actions_destroy(&fa);
    if (rc)
        vsv_cli_die(1, "cannot start ffmpeg: %s", strerror(rc));
    rc = posix_spawn_file_actions_adddup2(&fa, fd[0], 0);
    if (!rc)
        rc = posix_spawn_file_actions_adddup2(&fa, tfd, 3);
    if (!rc)
        rc = posix_spawnattr_setsigdefault(&at, &dfl);
    if (!rc)
        rc = posix_spawnattr_setflags(&at, POSIX_SPAWN_SETSIGDEF);
    if (!rc)
        rc = posix_spawnp(&mv->pid, "ffmpeg", &fa, &at, args, environ);
    posix_spawnattr_destroy(&at);
    posix_spawn_file_actions_destroy(&fa);
    close(fd[0]);
    close(tfd);
    if (rc)
        vsv_cli_die(1, "cannot start ffmpeg: %s", strerror(rc));
    if (!(mv->pipe = fdopen(fd[1], "wb")))
        vsv_cli_die(1, "cannot start ffmpeg: %s", strerror(errno));
}

void vsv_movie_frame(vsv_movie *mv, const unsigned char *rgb, int w, int h)
{
    if (fwrite(rgb, 3, (size_t)w * h, mv->pipe) != (size_t)w * h)
        vsv_cli_die(1, "%s: ffmpeg stopped taking frames", mv->out);
}

void vsv_movie_close(vsv_movie *mv)
{
    int st = 0;
    const int wrote = fclose(mv->pipe) == 0;
    while (waitpid(mv->pid, &st, 0) < 0 && errno == EINTR) {
    }
    if (!wrote || !WIFEXITED(st) || WEXITSTATUS(st))
        vsv_cli_die(1, "%s: ffmpeg failed (exit %d)", mv->out, WIFEXITED(st) ? WEXITSTATUS(st) : -1);
    const int fd = open(mv->tmp, O_RDONLY | O_CLOEXEC);
    if (fd < 0 || vsv_output_seal(fd))
        vsv_cli_die(1, "%s: cannot write: %s", mv->out, strerror(errno));
}
