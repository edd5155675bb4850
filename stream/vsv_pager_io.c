/* vsv_pager_io.c — the pager and transfers (a .vsv on a web server): the
 * chunk indexes its lock's code reads, fetched with the lock dropped, and
 * what a failed transfer leaves, tried again a moment later. A transfer
 * that fails is not damage: nothing is marked damaged for it. */
#include "vsv_pager_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int vsv_pager_due(const vsv_pager *p) { return vsv_pager_now() >= p->retry_at; }

void vsv_pager_stalled(vsv_pager *p, const char *msg)
{
    snprintf(p->ioerr, sizeof p->ioerr, "%s", msg);
    p->retry_at = vsv_pager_now() + VSV_PAGER_RETRY;
    p->st.transfer_failures++;
}

int vsv_pager_chunk(vsv_pager *p, int t)
{
    signed char *c = &p->cst[t];
    if (*c == C_RESIDENT)
        return 0;
    if (vsv_file_chunk_resident(p->f, t)) { /* (or fetched by a job's decoder) */
        *c = C_RESIDENT;
        return 0;
    }
    if (*c < 0) { /* damaged: said once fetched, never fetched again */
        vsv_pager_set_err(p, "%s", p->cmsg[t] ? p->cmsg[t] : "step's chunk index damaged");
        return *c;
    }
    if (*c == C_STALLED && !vsv_pager_due(p)) {
        vsv_pager_set_err(p, "%s", p->ioerr);
        return VSV_EIO;
    }
    if (*c != C_LOADING) {
        *c = C_UNKNOWN;
        if (p->missing < 0) { /* a worker fetches it (one waiting may) */
            p->missing = t;
            p->kick++;
            pthread_cond_broadcast(&p->work);
        }
    }
    vsv_pager_set_err(p, "step %d: its chunk index is not fetched yet", t);
    return VSV_EAGAIN;
}

int vsv_pager_kind(vsv_pager *p, int t, int s, int b)
{
    const int rc = vsv_pager_chunk(p, t);
    if (rc)
        return rc;
    const int k = vsv_file_brick_kind(p->f, t, s, b);
    if (k < 0)
        vsv_pager_set_err(p, "%s", vsv_file_error(p->f));
    return k;
}

int vsv_pager_fetch_missing(vsv_pager *p)
{
    const int t = p->missing;
    if (t < 0)
        return 0;
    p->missing = -1;
    if (p->cst[t] != C_UNKNOWN)
        return 1; /* there, or being fetched, meanwhile */
    p->cst[t] = C_LOADING;
    char msg[512];
    pthread_mutex_unlock(&p->mu);
    const int rc = vsv_file_chunk_fetch(p->f, t, msg, sizeof msg);
    pthread_mutex_lock(&p->mu);
    if (!rc) {
        p->cst[t] = C_RESIDENT;
    } else if (vsv_pager_damage(rc)) {
        p->cst[t] = (signed char)rc;
        free(p->cmsg[t]); /* (a rare path, not a loop) */
        p->cmsg[t] = strdup(msg);
    } else {
        p->cst[t] = C_STALLED;
        vsv_pager_stalled(p, msg);
    }
    p->gen++; /* the window looked at again, with this step */
    pthread_cond_broadcast(&p->work);
    pthread_cond_broadcast(&p->ready);
    return 1;
}

void vsv_pager_wait_chunk(vsv_pager *p)
{
    if (!vsv_pager_fetch_missing(p))
        pthread_cond_wait(&p->ready, &p->mu);
}
