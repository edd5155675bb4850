/* freevr_shmem.c — the FreeVR stand-in's shared memory: one arena of exactly
 * the size the first vrShmemInit asked for, FreeVR's allocator over it, the
 * SysV semaphore set vrConfigure creates, and the locks made from it. */
#include "freevr_standin.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/sem.h>
#include <unistd.h>

#define NSEMS 250
#define BASE_STATE 445000ul

typedef struct {
    size_t used, cap;
} arena_head;

static size_t g_arena_size = 16ul << 20;
static int g_arena_asked;
static unsigned char *g_arena;
static int g_semid = -1;
base_state *fvs_base;
size_t fvs_per_window;

static void sem_add(int idx, int delta)
{
    struct sembuf op = {(unsigned short)idx, (short)delta, SEM_UNDO};
    while (semop(g_semid, &op, 1) == -1 && errno == EINTR)
        ;
}

/* FreeVR's allocator over the shared arena (semaphore 0 guards it). */
void *fvs_amalloc(size_t n)
{
    arena_head *h = (arena_head *)g_arena;
    sem_add(0, -1);
    const size_t off = (h->used + 15) & ~(size_t)15;
    if (off > h->cap || n > h->cap - off) {
        const size_t used = h->used;
        sem_add(0, 1);
        fprintf(stderr, "FreeVR: Not enough room to amalloc %zu bytes (arena of %zu bytes, %zu used)\n", n, h->cap,
                used);
        return NULL;
    }
    h->used = off + n;
    sem_add(0, 1);
    memset(g_arena + off, 0, n);
    return g_arena + off;
}

/* FreeVR's per-window state as measured: 525,000 bytes in all with one
 * window, 765,000 with four, 1,049,736 with eight (linear between, and
 * beyond eight at the last slope), less the base state. */
static size_t per_window_state(int windows)
{
    double total;
    if (windows <= 1)
        total = 525000;
    else if (windows <= 4)
        total = 525000 + (windows - 1) * 80000.0;
    else
        total = 765000 + (windows - 4) * 71184.0;
    return (size_t)((total - BASE_STATE) / (windows > 0 ? windows : 1));
}

long vrShmemInit(size_t bytes)
{
    if (!g_arena_asked && !g_arena) { /* only the first call counts */
        g_arena_asked = 1;
        g_arena_size = bytes;
    }
    return (long)g_arena_size;
}

void *vrShmemAlloc0(size_t bytes)
{
    if (!g_arena) {
        fprintf(stderr, "FreeVR: vrShmemAlloc0 before vrConfigure\n");
        return NULL;
    }
    return fvs_amalloc(bytes);
}

void fvs_shmem_create(int windows)
{
    /* the arena: exactly the size the first vrShmemInit asked for */
    g_arena = mmap(NULL, g_arena_size, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (g_arena == MAP_FAILED || g_arena_size < sizeof(arena_head)) {
        fprintf(stderr, "FreeVR: cannot map a shared arena of %zu bytes\n", g_arena_size);
        exit(1);
    }
    ((arena_head *)g_arena)->used = sizeof(arena_head);
    ((arena_head *)g_arena)->cap = g_arena_size;
    g_semid = semget(IPC_PRIVATE, NSEMS, IPC_CREAT | 0600);
    if (g_semid < 0) {
        perror("FreeVR: semget");
        exit(1);
    }
    for (int i = 0; i < NSEMS; i++)
        semctl(g_semid, i, SETVAL, 1);
    fprintf(stderr, "FreeVR stand-in: semaphore set %d (%d semaphores), arena %zu bytes, %d window%s\n", g_semid, NSEMS,
            g_arena_size, windows, windows == 1 ? "" : "s");
    fvs_base = fvs_amalloc(BASE_STATE);
    if (!fvs_base) {
        for (;;)
            pause();
    }
    fvs_base->nextlock = 1;
    fvs_per_window = per_window_state(windows);
}

void fvs_shmem_destroy(void)
{
    semctl(g_semid, 0, IPC_RMID);
    g_semid = -1;
    munmap(g_arena, g_arena_size);
    g_arena = NULL;
    fvs_base = NULL;
}

/* ----------------------------------------------------------------- locks */

vrLock vrNCLockCreate(void)
{
    if (!fvs_base)
        return NULL;
    sem_add(0, -1);
    const int idx = fvs_base->nextlock < NSEMS ? fvs_base->nextlock++ : NSEMS - 1;
    sem_add(0, 1);
    return (vrLock)(intptr_t)idx;
}
void vrLockWriteSet(vrLock l) { sem_add((int)(intptr_t)l, -1); }
void vrLockWriteRelease(vrLock l) { sem_add((int)(intptr_t)l, 1); }
void vrLockReadSet(vrLock l) { sem_add((int)(intptr_t)l, -1); }
void vrLockReadRelease(vrLock l) { sem_add((int)(intptr_t)l, 1); }
