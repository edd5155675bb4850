/* freevr_process.c — the FreeVR stand-in's life cycle: vrConfigure reads the
 * configuration, sets SIGINT ignored and sets up the shared state, vrStart
 * forks one render process per visren process and one input process per
 * input process, and vrExit stops them, waits for each to say it is done
 * and removes the shared state. */
#include "freevr_standin.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static pid_t g_main, g_children[MAXPROC + 1];
static int g_nchildren;
int fvs_slot = -1;

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
    /* FreeVR ignores SIGINT (FREEVR.md, "Signals"): Ctrl-C does nothing
     * unless the application installs a handler after vrStart; set here,
     * so every process vrStart forks inherits it */
    struct sigaction ign;
    memset(&ign, 0, sizeof ign);
    ign.sa_handler = SIG_IGN;
    sigemptyset(&ign.sa_mask);
    sigaction(SIGINT, &ign, NULL);
    fvs_config_load(argc, argv);
    fvs_shmem_create(fvs_config_count('v'));
    fvs_base->start = fvs_now();
    fvs_sensors_init();
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
        /* No PR_SET_PDEATHSIG: with FreeVR the render and input processes
         * outlive a main process killed by SIGTERM or SIGHUP and go on
         * drawing (FREEVR.md, "Signals"); nothing sets the quit flag then,
         * so they run until someone kills them. */
        fvs_slot = g_nchildren;
        if (p->type == 'v')
            fvs_render_process(p);
        else
            fvs_input_process(p);
        _exit(0);
    }
    g_children[g_nchildren++] = pid;
}

void fvs_process_done(void)
{
    if (fvs_base && fvs_slot >= 0 && fvs_slot <= MAXPROC)
        fvs_base->done[fvs_slot] = 1;
}

void vrStart(void)
{
    const sys_def *sys = fvs_used_system();
    if (!fvs_base || !sys || fvs_base->started)
        return;
    fvs_base->started = 1;
    for (int k = 0; k < sys->nprocs && g_nchildren <= MAXPROC; k++) {
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
    /* FreeVR waits for every process to say it has finished: one that died
     * (killed, or crashed) never says so, and vrExit never returns
     * (FREEVR.md, "A render process that dies"). Its exit status is not
     * what is waited for, so reaping the dead one changes nothing. */
    for (int i = 0; i < g_nchildren; i++) {
        while (!fvs_base->done[i]) {
            waitpid(g_children[i], NULL, WNOHANG);
            nanosleep(&(struct timespec){0, 10000000}, NULL);
        }
        while (waitpid(g_children[i], NULL, 0) == -1 && errno == EINTR)
            ;
    }
    g_nchildren = 0;
    fvs_shmem_destroy();
}

double vrCurrentSimTime(void) { return fvs_base ? fvs_now() - fvs_base->start : 0; }
