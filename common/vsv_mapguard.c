/* vsv_mapguard.c — a mapped file that shrinks while it is read (another
 * program truncates or rewrites it in place) makes every access past its new
 * end raise SIGBUS, which kills the process. Every mapping of an input is
 * registered here (the .vsv reader's, a byte source's, the model readers'
 * through vsv_input_map); on SIGBUS inside one, the handler puts a page of
 * zeros over the faulting page and marks the mapping "cut", so the access
 * completes (reading zeros) and the reader then reports "truncated while
 * reading" (vsv_input_cut). Chosen over sigsetjmp around every read
 * (per-thread jump buffers across the pager's workers, and every mapped
 * access would need one) and over pread (the format is designed to be mapped:
 * O(1) open, zero-copy payloads). A SIGBUS outside every mapping goes to the
 * handler installed before, or kills as before. Each library that links this
 * file privately (ARCHITECTURE.md) has its own slots and handler; each
 * handler passes a fault outside its slots to the one installed before it. */
#include "vsv_common.h"

#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <unistd.h>

#define SLOTS 512

/* A slot is claimed with a compare-and-swap on `used`; lo (stored last)
 * publishes it to the handler, lo == 0 hides it. */
static struct {
    uintptr_t lo, hi;
    int cut, used;
} slot[SLOTS];

static struct sigaction previous;
static pthread_once_t once = PTHREAD_ONCE_INIT;
static long page;

static void on_sigbus(int sig, siginfo_t *si, void *ctx)
{
    const uintptr_t a = (uintptr_t)si->si_addr;
    int zeroed = 0, failed = 0;
    /* every slot that holds the address is marked (one range may be
     * registered twice: a byte source's base and its owner's) */
    for (int i = 0; i < SLOTS && !failed; i++) {
        const uintptr_t lo = __atomic_load_n(&slot[i].lo, __ATOMIC_ACQUIRE);
        if (lo && a >= lo && a < __atomic_load_n(&slot[i].hi, __ATOMIC_ACQUIRE)) {
            if (!zeroed) {
                /* the raw system call: async-signal-safe, and no
                 * sanitizer's wrapper in a signal handler */
                const uintptr_t p = a & ~(uintptr_t)(page - 1);
                failed = syscall(SYS_mmap, (void *)p, (size_t)page, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED,
                                 -1, 0L) == -1;
                zeroed = !failed;
            }
            if (zeroed)
                __atomic_store_n(&slot[i].cut, 1, __ATOMIC_RELEASE);
        }
    }
    if (zeroed)
        return;
    if (previous.sa_flags & SA_SIGINFO) {
        previous.sa_sigaction(sig, si, ctx);
        return;
    }
    if (previous.sa_handler != SIG_DFL && previous.sa_handler != SIG_IGN) {
        previous.sa_handler(sig);
        return;
    }
    /* as if never handled: the faulting access runs again and kills */
    signal(SIGBUS, SIG_DFL);
}

static void install(void)
{
    page = sysconf(_SC_PAGESIZE);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_sigaction = on_sigbus;
    sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGBUS, &sa, &previous);
}

int vsv_mapguard_add(const void *p, size_t n)
{
    pthread_once(&once, install);
    const uintptr_t lo = (uintptr_t)p;
    for (int i = 0; i < SLOTS; i++) {
        int free_slot = 0;
        if (__atomic_compare_exchange_n(&slot[i].used, &free_slot, 1, 0, __ATOMIC_ACQ_REL, __ATOMIC_RELAXED)) {
            __atomic_store_n(&slot[i].cut, 0, __ATOMIC_RELAXED);
            __atomic_store_n(&slot[i].hi, lo + n, __ATOMIC_RELAXED);
            __atomic_store_n(&slot[i].lo, lo, __ATOMIC_RELEASE);
            return i;
        }
    }
    return -1; /* unguarded: as before (a truncation kills) */
}

int vsv_mapguard_cut(int i) { return i >= 0 && __atomic_load_n(&slot[i].cut, __ATOMIC_ACQUIRE); }

void vsv_mapguard_remove(int i)
{
    if (i >= 0) {
        __atomic_store_n(&slot[i].lo, 0, __ATOMIC_RELEASE);
        __atomic_store_n(&slot[i].used, 0, __ATOMIC_RELEASE);
    }
}
