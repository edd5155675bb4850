/* vsv_procs.c — see vsv_procs.h. /proc/PID/stat for a process's state and
 * parent, /proc/sysvipc/{sem,shm} for the IPC objects and their owners. */
#include "vsv_procs.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ipc.h>
#include <sys/sem.h>
#include <sys/shm.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* The state letter and parent of pid from /proc/PID/stat; 0 or -1. */
static int stat_of(pid_t pid, char *state, pid_t *ppid)
{
    char path[64], buf[512];
    snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
    FILE *fp = fopen(path, "r");
    if (!fp)
        return -1;
    const size_t n = fread(buf, 1, sizeof buf - 1, fp);
    fclose(fp);
    buf[n] = 0;
    const char *p = strrchr(buf, ')'); /* the name may hold anything */
    int pp;
    char st;
    if (!p || sscanf(p + 1, " %c %d", &st, &pp) != 2)
        return -1;
    *state = st;
    *ppid = pp;
    return 0;
}

int vsv_proc_alive(pid_t pid)
{
    char st;
    pid_t pp;
    return pid > 0 && !stat_of(pid, &st, &pp) && st != 'Z' && st != 'X';
}

int vsv_proc_ended(pid_t pid, char *buf, size_t cap)
{
    int status;
    buf[0] = 0;
    /* a process seen dead may not be waitable yet (state X, on its way to a
     * zombie: a sanitized one takes a while): up to 2 s */
    pid_t got = 0;
    for (int i = 0; pid > 0 && i < 200 && (got = waitpid(pid, &status, WNOHANG)) == 0; i++)
        nanosleep(&(struct timespec){0, 10000000}, NULL);
    if (pid <= 0 || got != pid)
        return -1;
    if (WIFSIGNALED(status))
        snprintf(buf, cap, "killed by signal %d (%s)", WTERMSIG(status), strsignal(WTERMSIG(status)));
    else
        snprintf(buf, cap, "exited with status %d", WEXITSTATUS(status));
    return 0;
}

int vsv_proc_children(pid_t *out, int cap)
{
    DIR *d = opendir("/proc");
    if (!d)
        return 0;
    const pid_t me = getpid();
    int n = 0;
    for (struct dirent *e; (e = readdir(d)) && n < cap;) {
        char *end;
        const long pid = strtol(e->d_name, &end, 10);
        char st;
        pid_t pp;
        if (*end || pid <= 0 || stat_of((pid_t)pid, &st, &pp) || pp != me)
            continue;
        out[n++] = (pid_t)pid;
    }
    closedir(d);
    return n;
}

void vsv_proc_end(const pid_t *pids, int n, double grace)
{
    for (int i = 0; i < n; i++)
        kill(pids[i], SIGTERM);
    for (double waited = 0; waited < grace; waited += 0.02) {
        int left = 0;
        for (int i = 0; i < n; i++)
            left += vsv_proc_alive(pids[i]);
        if (!left)
            break;
        nanosleep(&(struct timespec){0, 20000000}, NULL);
    }
    for (int i = 0; i < n; i++) {
        if (vsv_proc_alive(pids[i]))
            kill(pids[i], SIGKILL);
        while (waitpid(pids[i], NULL, 0) == -1 && errno == EINTR)
            ;
    }
}

/* The ids of one /proc/sysvipc table owned (creator uid) by this user. */
static int ids_of(const char *table, int uid_col, int *ids, int cap)
{
    FILE *fp = fopen(table, "r");
    if (!fp)
        return 0;
    char line[1024];
    int n = 0;
    const uid_t me = geteuid();
    if (!fgets(line, sizeof line, fp)) { /* the header */
        fclose(fp);
        return 0;
    }
    while (n < cap && fgets(line, sizeof line, fp)) {
        long col[16];
        int k = 0;
        for (char *p = line, *end; k < 16; p = end, k++) {
            col[k] = strtol(p, &end, 10);
            if (end == p)
                break;
        }
        if (k > uid_col && col[uid_col] == (long)me)
            ids[n++] = (int)col[1];
    }
    fclose(fp);
    return n;
}

void vsv_ipc_list(vsv_ipc *out)
{
    /* sem: key semid perms nsems uid gid cuid ...; shm: key shmid perms
     * size cpid lpid nattch uid gid cuid ... (creator uid columns) */
    out->nsem = ids_of("/proc/sysvipc/sem", 6, out->sem, 256);
    out->nshm = ids_of("/proc/sysvipc/shm", 9, out->shm, 256);
}

static int has(const int *a, int n, int v)
{
    for (int i = 0; i < n; i++)
        if (a[i] == v)
            return 1;
    return 0;
}

void vsv_ipc_new(const vsv_ipc *before, const vsv_ipc *after, vsv_ipc *out)
{
    vsv_ipc o = {{0}, 0, {0}, 0};
    for (int i = 0; i < after->nsem; i++)
        if (!has(before->sem, before->nsem, after->sem[i]))
            o.sem[o.nsem++] = after->sem[i];
    for (int i = 0; i < after->nshm; i++)
        if (!has(before->shm, before->nshm, after->shm[i]))
            o.shm[o.nshm++] = after->shm[i];
    *out = o;
}

int vsv_ipc_remove(const vsv_ipc *ids)
{
    int n = 0;
    for (int i = 0; i < ids->nsem; i++)
        n += semctl(ids->sem[i], 0, IPC_RMID) == 0;
    for (int i = 0; i < ids->nshm; i++)
        n += shmctl(ids->shm[i], IPC_RMID, NULL) == 0;
    return n;
}
