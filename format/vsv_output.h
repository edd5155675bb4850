/* vsv_output.h — outputs written all or nothing. Part of the public
 * interface of vsv_format.h, which includes it at its end. */
#ifndef VSV_OUTPUT_H
#define VSV_OUTPUT_H

#include "vsv_format.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* Every file the libraries and tools write goes to a temporary beside its
 * destination (same directory: the rename is atomic), is synced, and is
 * renamed only when complete; a sequence renames its files only when all
 * are written. Each temporary is listed in one process-wide registry that
 * vsv_output_cleanup empties, so a program's signal handler leaves nothing
 * behind (vsv_output.c). */

/* The mode of a new file: 0666 less the process umask (read once, never by
 * changing it). */
unsigned vsv_output_mode(void);
/* Creates and lists a temporary for path ("path.tmp.PID.N" + suffix, which
 * may be NULL; exclusively, with vsv_output_mode()); its name into tmp
 * (caller buffer of cap bytes). The descriptor (close-on-exec), or -1 with
 * errno. */
int vsv_output_temp(const char *path, const char *suffix, char *tmp, size_t cap);
/* fsync and close fd: 0, or -1 with errno (a full disk or a failed write
 * shows here at the latest). */
int vsv_output_seal(int fd);
/* Renames tmp to path, syncs the directory and unlists tmp: 0, or -1 with
 * errno (tmp then stays listed and in place). */
int vsv_output_publish(const char *tmp, const char *path);
/* seal (when fd >= 0) and publish; on failure removes tmp: 0 or -1 with
 * errno. */
int vsv_output_commit(int fd, const char *tmp, const char *path);
/* Removes tmp and unlists it. */
void vsv_output_discard(const char *tmp);
/* Unlists tmp (when something else renamed or removed it). */
void vsv_output_forget(const char *tmp);
/* Lists tmp, a temporary another process made (the ranks of an MPI job
 * share the one rank 0 makes), so vsv_output_cleanup removes it here too;
 * vsv_output_forget unlists it. A name of 1024 bytes or more is not listed. */
void vsv_output_claim(const char *tmp);
/* Removes every listed temporary: async-signal-safe, for a program's
 * SIGINT/SIGTERM/SIGHUP handler (vsv_cli.c installs one). */
void vsv_output_cleanup(void);

VSV_API_END

#ifdef __cplusplus
}
#endif
#endif
