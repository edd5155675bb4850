/* freevr_process.c — the FreeVR stand-in's life cycle: vrConfigure reads the
 * configuration and sets up the shared state, vrStart forks one render
 * process per visren process and one input process per input process, and
 * vrExit stops and waits for them all and removes the shared state. */
#include "freevr_standin.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static pid_t g_main, g_children[MAXPROC + 1];
static int g_nchildren;

double fvs_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

vrContextInfo *vrConfigure(int *argc, char **argv, char **appargs)
{
    (void)appargs;
    g_main = getpid();
    fvs_config_load(argc, argv);
    fvs_shmem_create(fvs_config_count('v'));
    fvs_base->start = fvs_now();
    fvs_base->head[0] = 0, fvs_base->head[1] = 5, fvs_base->head[2] = 0;
    fvs_base->wand[0] = 1, fvs_base->wand[1] = 4, fvs_base->wand[2] = -1;
    for (int i = 0; i < 16; i++)
        fvs_base->travel[i] = i % 5 == 0;
    return (vrContextInfo *)fvs_base;
}

static void start_child(const proc_def *p)
{
    fflush(NULL);
    const pid_t pid = fork();
    if (pid < 0) {
        perror("FreeVR: fork");
        return;
    }
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL); /* never outlive the application */
        if (getppid() != g_main)
            _exit(1);
        if (p->type == 'v')
            fvs_render_process(p);
        else
            fvs_input_process(p);
        _exit(0);
    }
    g_children[g_nchildren++] = pid;
}

void vrStart(void)
{
    const sys_def *sys = fvs_used_system();
    if (!fvs_base || !sys || fvs_base->started)
        return;
    fvs_base->started = 1;
    for (int k = 0; k < sys->nprocs; k++) {
        const proc_def *p = fvs_find_proc(sys->procs[k]);
        if (!p)
            fprintf(stderr, "FreeVR: system '%s': no process '%s'\n", sys->name, sys->procs[k]);
        else if (p->type == 'v' || p->type == 'i')
            start_child(p);
    }
}

void vrExit(void)
{
    if (!fvs_base || getpid() != g_main)
        return;
    fvs_base->quit = 1;
    for (int i = 0; i < g_nchildren; i++) /* FreeVR waits for every process */
        while (waitpid(g_children[i], NULL, 0) == -1 && errno == EINTR)
            ;
    g_nchildren = 0;
    fvs_shmem_destroy();
}

double vrCurrentSimTime(void) { return fvs_base ? fvs_now() - fvs_base->start : 0; }
