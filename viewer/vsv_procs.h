/* vsv_procs.h — the processes and System V IPC objects of a FreeVR run, as
 * the program sees them from outside FreeVR: whether a render process is
 * still alive, how it ended, this process's children, and the semaphore
 * sets and shared-memory segments FreeVR created (those that appeared
 * while vrConfigure and vrStart ran), so that a run FreeVR cannot end
 * itself (a render process died: vrExit would wait for it forever) still
 * ends clean. Linux: it reads /proc. */
#ifndef VSV_PROCS_H
#define VSV_PROCS_H

#include <stddef.h>
#include <sys/types.h>

/* 1 while pid runs; 0 when it is gone or a zombie (it ended). */
int vsv_proc_alive(pid_t pid);
/* How child pid ended, when it did: "killed by signal 9 (Killed)" or
 * "exited with status 3", into buf; 0, or -1 when it has not ended within
 * 2 s or is not a child (buf then empty). It is reaped. For a child
 * vsv_proc_alive says is gone: one on its way to a zombie is not waitable
 * at once. */
int vsv_proc_ended(pid_t pid, char *buf, size_t cap);
/* This process's children (up to cap pids into out); how many. */
int vsv_proc_children(pid_t *out, int cap);
/* Sends SIGTERM to each of the n pids, waits up to grace seconds for
 * them, then SIGKILLs those left and reaps them all. */
void vsv_proc_end(const pid_t *pids, int n, double grace);

/* The System V IPC ids (semaphore sets, shared-memory segments) of this
 * user at a moment. */
typedef struct vsv_ipc {
    int sem[256], nsem;
    int shm[256], nshm;
} vsv_ipc;
void vsv_ipc_list(vsv_ipc *out);
/* The ids in after that are not in before. */
void vsv_ipc_new(const vsv_ipc *before, const vsv_ipc *after, vsv_ipc *out);
/* Removes them (those still there); how many it removed. Async-signal-safe. */
int vsv_ipc_remove(const vsv_ipc *ids);

#endif
