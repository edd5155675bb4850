// vsv_vdb_helper.cc — the helper program vsv-vdb-reader's side of
// vsv_vdb_isolate.cc: it reads and writes .vdb files through vsv_vdb.cc's
// OpenVDB calls, within limits of time and memory, and leaves its results
// in the shared memory the caller passed as descriptor 3. This and
// vsv_vdb.cc are the only code that loads OpenVDB.
#include "vsv_vdb.h"
#include "vsv_vdb_internal.h"

#include <cerrno>
#include <cstdint>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

namespace
{

using namespace vsv_vdb_shm;
using shared_head = vsv_vdb_shm::head;

// Bounds the helper, since a damaged file can also send the library into
// reading gigabytes or looping: CPU and wall-clock time for `input` bytes (0:
// none; the reader times each file itself) and, outside AddressSanitizer
// builds (whose shadow memory is address space), memory of 1 GiB + `memory`
// more than it has; all far above what good files need.
void helper_limits(uint64_t input, uint64_t memory)
{
    struct rlimit rl;
    if (input) {
        /* SIGXCPU at the limit, which the caller reports as time; the
         * hard limit's SIGKILL (a crash to the caller) only if ignored */
        rl.rlim_cur = time_limit(input);
        rl.rlim_max = time_limit(input) + 5;
        setrlimit(RLIMIT_CPU, &rl);
        alarm(time_limit(input));
    }
#ifdef __SANITIZE_ADDRESS__
    (void)memory;
#else
    unsigned long long pages = 0;
    FILE *f = std::fopen("/proc/self/statm", "r");
    if (f) {
        if (std::fscanf(f, "%llu", &pages) != 1)
            pages = 0;
        std::fclose(f);
    }
    if (pages) {
        rl.rlim_cur = rl.rlim_max = pages * (uint64_t)sysconf(_SC_PAGESIZE) + ((uint64_t)1 << 30) + memory;
        setrlimit(RLIMIT_AS, &rl);
    }
#endif
}

// scan: the file count and their NUL-separated paths are in the memory;
// the result goes there too. Exit status 0 (the result's rc says how it went).
int helper_scan(void *m, size_t bytes, uint64_t memory)
{
    auto *h = static_cast<shared_head *>(m);
    const int n = h->nfiles;
    char *p = static_cast<char *>(m) + sizeof(shared_head);
    const char *blob = p + (size_t)MAXG * 128 + (size_t)(n > 0 ? n : 1) * sizeof(int64_t);
    const char *end = static_cast<const char *>(m) + bytes;
    if (n < 0 || blob > end)
        return 2;
    std::vector<const char *> paths((size_t)n);
    for (int i = 0; i < n; i++) {
        paths[(size_t)i] = blob;
        blob = static_cast<const char *>(std::memchr(blob, 0, (size_t)(end - blob)));
        if (!blob)
            return 2;
        blob++;
    }
    helper_limits(input_bytes(paths.data(), n), memory);
    vsv_vdb_info in;
    h->rc = vsv_vdb_scan_here(paths.data(), n, &in, h->err, sizeof h->err);
    if (h->rc)
        return 0;
    if (in.ngrids > MAXG) {
        std::snprintf(h->err, sizeof h->err, "%s: more than %d grids", paths[0], (int)MAXG);
        h->rc = -1;
        vsv_vdb_info_free(&in);
        return 0;
    }
    h->nx = in.nx, h->ny = in.ny, h->nz = in.nz, h->ngrids = in.ngrids;
    for (int a = 0; a < 3; a++)
        h->imin[a] = in.imin[a], h->origin[a] = in.origin[a], h->voxel[a] = in.voxel[a];
    std::memcpy(h->model, in.model, sizeof h->model);
    std::memcpy(h->projection, in.projection, sizeof h->projection);
    std::memcpy(p, in.names, (size_t)in.ngrids * 64);
    std::memcpy(p + (size_t)MAXG * 64, in.units, (size_t)in.ngrids * 64);
    std::memcpy(p + (size_t)MAXG * 128, in.times, (size_t)n * sizeof(int64_t));
    vsv_vdb_info_free(&in);
    return 0;
}

// read: waits for requests on stdin, answers each with a byte on stdout;
// exits when its caller closes the socket.
int helper_read(void *m, size_t bytes, uint64_t memory)
{
    helper_limits(0, memory);
    auto *h = static_cast<shared_head *>(m);
    for (;;) {
        char c;
        ssize_t n;
        while ((n = read(0, &c, 1)) < 0 && errno == EINTR) {
        }
        if (n != 1)
            return 0;
        auto *rq = reinterpret_cast<read_request *>(h + 1);
        const int count = rq->count;
        const size_t cells = (size_t)rq->nx * rq->ny * rq->nz;
        if (count < 1 || count > MAXG || read_head_bytes(count) > bytes ||
            cells > (bytes - read_head_bytes(count)) / sizeof(float) / (size_t)count)
            return 2;
        const read_layout l = read_parts(m, count);
        rq->path[sizeof rq->path - 1] = 0;
        vsv_vdb_info info;
        std::memset(&info, 0, sizeof info);
        info.nx = rq->nx, info.ny = rq->ny, info.nz = rq->nz;
        for (int a = 0; a < 3; a++)
            info.imin[a] = rq->imin[a];
        const char *const one[1] = {rq->path};
        alarm(time_limit(input_bytes(one, 1))); /* a damaged file must not hang */
        h->rc = vsv_vdb_read_here(rq->path, &info, l.names, count, l.data, l.st);
        alarm(0);
        while (write(1, &c, 1) < 0 && errno == EINTR) {
        }
    }
}

// Reads n bytes of the request from stdin: 0, or -1 (it ended early).
int read_all(void *p, size_t n)
{
    char *c = static_cast<char *>(p);
    while (n) {
        const ssize_t k = read(0, c, n);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return -1;
        c += k, n -= (size_t)k;
    }
    return 0;
}

// write: a write request on stdin (vsv_vdb_shm::write_request, its grid
// records, their values), the reply (write_reply) on stdout. Exit status
// 0 with a reply, 2 for a request that is not one.
int helper_write(uint64_t memory)
{
    helper_limits(0, memory);
    write_request rq;
    if (read_all(&rq, sizeof rq) || rq.ngrids < 1 || rq.ngrids > MAXG || rq.nx < 1 || rq.ny < 1 || rq.nz < 1)
        return 2;
    rq.path[sizeof rq.path - 1] = 0;
    const size_t cells = (size_t)rq.nx * rq.ny * rq.nz, n = (size_t)rq.ngrids;
    std::vector<write_grid> grids(n);
    if (read_all(grids.data(), n * sizeof(write_grid)))
        return 2;
    write_reply reply;
    std::memset(&reply, 0, sizeof reply);
    float *values = cells <= SIZE_MAX / sizeof(float) / n ? static_cast<float *>(std::malloc(n * cells * 4)) : nullptr;
    if (!values) {
        std::snprintf(reply.err, sizeof reply.err, "out of memory (%zu MB for the grids in the OpenVDB writer)",
                      (size_t)((double)n * cells * 4 / 1048576));
        reply.rc = -1;
    } else if (read_all(values, n * cells * sizeof(float))) {
        return 2;
    } else {
        alarm(time_limit((uint64_t)n * cells * sizeof(float)));
        reply.rc = vsv_vdb_write_here(&rq, grids.data(), values, reply.err, sizeof reply.err);
        alarm(0);
    }
    const char *c = reinterpret_cast<const char *>(&reply);
    for (size_t left = sizeof reply; left;) {
        const ssize_t k = write(1, c, left);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return 2;
        c += k, left -= (size_t)k;
    }
    return 0;
}

} // namespace

extern "C" int vsv_vdb_helper_main(int argc, char **argv)
{
    /* a crash must end the helper by its signal (the caller reports it),
     * whatever a sanitizer installed at start */
    static const int sigs[] = {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGALRM, SIGXCPU};
    for (int s : sigs)
        std::signal(s, SIG_DFL);
    /* a file size limit is a failed write (EFBIG, reported), as in the
     * tool, not a signal */
    std::signal(SIGXFSZ, SIG_IGN);
    if (argc != 3)
        return 2;
    const uint64_t memory = std::strtoull(argv[2], nullptr, 10);
    if (!std::strcmp(argv[1], "write")) /* the request on stdin, not in shared memory */
        return helper_write(memory);
    struct stat st;
    void *m;
    if (fstat(3, &st) || st.st_size < (off_t)sizeof(shared_head) ||
        (m = mmap(nullptr, (size_t)st.st_size, PROT_READ | PROT_WRITE, MAP_SHARED, 3, 0)) == MAP_FAILED)
        return 2;
    if (!std::strcmp(argv[1], "scan"))
        return helper_scan(m, (size_t)st.st_size, memory);
    if (!std::strcmp(argv[1], "read"))
        return helper_read(m, (size_t)st.st_size, memory);
    return 2;
}
