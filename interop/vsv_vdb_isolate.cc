// vsv_vdb_isolate.cc — .vdb files read and written by the helper program
// vsv-vdb-reader, the caller's side (vsv_vdb_scan, vsv_vdb_read,
// vsv_vdb_write), talking to it through shared memory (the helper's side:
// vsv_vdb_helper.cc). Nothing here calls OpenVDB: a program that links
// this alone loads neither it nor its logging library.
#include "vsv_vdb.h"
#include "vsv_vdb_internal.h"

extern "C" {
#include "vsv_common.h"
}

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <vector>
#include <fcntl.h>
#include <poll.h>
#include <time.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace
{
void say(char *err, size_t cap, const std::string &s) { std::snprintf(err, cap, "%s", s.c_str()); }
} // namespace

// Reading grids: OpenVDB files carry no checksums and the library trusts
// what it reads, so a damaged file can crash it. Every read runs in the
// helper program vsv-vdb-reader (exec'd: this process may have threads,
// vsv_helper.c), which puts its results in shared memory (a memfd passed as
// its descriptor 3); a helper killed by a signal or by its time limit is a
// "damaged file" error, never a crash or hang of the tool. One reader for a
// sequence stays alive from the first read until the sequence's info is
// freed (or it dies on a damaged file: the next read starts another). It
// reads every grid of the file it is sent; the grids of the file read last
// stay in the memory, so the next grids of that file (a converter asks for
// them one by one) cost nothing.
namespace
{

using namespace vsv_vdb_shm;
using shared_head = vsv_vdb_shm::head;
using grid_status = vsv_vdb_grid_status;

struct file_cache {
    std::mutex mu;
    std::string path;
    const vsv_vdb_info *info = nullptr; /* what the reader and memory are for */
    void *mem = nullptr;
    size_t bytes = 0;
    int memfd = -1;
    int first = 0, count = 0; /* the grids held: info's first .. first + count - 1 */
    int ok = 0;               /* path is held: the file opened, every grid has its status */
    pid_t pid = 0;            /* the reader, and the socket to it */
    int sock = -1;
} cache;

void reader_stop()
{
    if (cache.pid > 0) {
        close(cache.sock);
        int st;
        vsv_helper_reap(cache.pid, 10, &st); /* it exits at the end of its requests */
    }
    cache.pid = 0;
    cache.sock = -1;
}

// Forgets the sequence: stops the reader, unmaps the memory.
void cache_drop()
{
    reader_stop();
    if (cache.mem)
        munmap(cache.mem, cache.bytes);
    if (cache.memfd >= 0)
        close(cache.memfd);
    cache.memfd = -1;
    cache.mem = nullptr;
    cache.bytes = 0;
    cache.info = nullptr;
    cache.path.clear();
}
} // namespace

extern "C" void vsv_vdb_info_free(vsv_vdb_info *info)
{
    {
        std::lock_guard<std::mutex> lock(cache.mu);
        if (cache.info == info)
            cache_drop();
    }
    std::free(info->names);
    std::free(info->units);
    std::free(info->times);
    std::memset(info, 0, sizeof *info);
}

// ------------------------------------------------------------- isolation

namespace
{

// The error for a helper that died reading `what` (wait status st; killed
// by the caller for time when timed_out).
void helper_died(const char *what, uint64_t input, int st, int timed_out, char *err, size_t cap)
{
    const int sig = WIFSIGNALED(st) ? WTERMSIG(st) : 0;
    if (timed_out || sig == SIGXCPU || sig == SIGALRM)
        say(err, cap,
            std::string(what) + ": damaged OpenVDB file (reading it took over " + std::to_string(time_limit(input)) +
                " s)");
    else if (sig == SIGABRT) /* an exception nothing caught: a damaged file, or memory (log4cplus at load) */
        say(err, cap,
            std::string(what) + ": the OpenVDB library failed reading it (signal 6: a damaged OpenVDB file, or out of "
                                "memory)");
    else if (sig)
        say(err, cap,
            std::string(what) + ": damaged OpenVDB file (the OpenVDB library failed reading it, signal " +
                std::to_string(sig) + ")");
    else
        say(err, cap,
            std::string(what) + ": damaged OpenVDB file (its reader exited with status " +
                std::to_string(WIFEXITED(st) ? WEXITSTATUS(st) : -1) + ")");
}

// New shared memory of `bytes`: the memfd (for the helper) and its mapping;
// its pages reserved, so that memory running out is an error here (ENOMEM,
// ENOSPC), not a SIGBUS when a page is first written.
int shared_new(size_t bytes, int *fd, void **mem)
{
    *fd = memfd_create("vsv-vdb", MFD_CLOEXEC);
    if (*fd < 0)
        return -1;
    int rc = ftruncate(*fd, (off_t)bytes);
    if (!rc) {
        const int e = posix_fallocate(*fd, 0, (off_t)bytes);
        if (e && e != EOPNOTSUPP && e != ENOSYS)
            errno = e, rc = -1;
    }
    if (rc || (*mem = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, *fd, 0)) == MAP_FAILED) {
        close(*fd);
        *fd = -1;
        return -1;
    }
    return 0;
}

} // namespace

// ---- the caller's side

extern "C" int vsv_vdb_scan(const char *const *paths, int n, vsv_vdb_info *info, char *err, size_t cap)
{
    std::memset(info, 0, sizeof *info);
    const char *what = n ? paths[0] : "";
    size_t blob = 0;
    for (int i = 0; i < n; i++)
        blob += std::strlen(paths[i]) + 1;
    const size_t bytes = sizeof(shared_head) + (size_t)MAXG * 128 + (size_t)(n > 0 ? n : 1) * sizeof(int64_t) + blob;
    void *mem = nullptr;
    int fd = -1;
    if (shared_new(bytes, &fd, &mem)) {
        say(err, cap, std::string(what) + ": cannot read it: shared memory: " + std::strerror(errno));
        return -1;
    }
    auto *h = static_cast<shared_head *>(mem);
    h->rc = -1;
    h->nfiles = n;
    char *p = static_cast<char *>(mem) + sizeof(shared_head) + (size_t)MAXG * 128 + (size_t)(n > 0 ? n : 1) * 8;
    for (int i = 0; i < n; i++) {
        const size_t len = std::strlen(paths[i]) + 1;
        std::memcpy(p, paths[i], len);
        p += len;
    }
    const uint64_t input = input_bytes(paths, n);
    const std::string memory = std::to_string(64 * input);
    char *argv[] = {const_cast<char *>("vsv-vdb-reader"), const_cast<char *>("scan"),
                    const_cast<char *>(memory.c_str()), nullptr};
    char why[600] = "", out[8];
    int st = 0, rc = -1;
    const int r =
        vsv_helper_run("vsv-vdb-reader", argv, fd, time_limit(input) + 5, out, sizeof out, &st, why, sizeof why);
    close(fd);
    if (r < 0)
        say(err, cap, std::string(what) + ": " + why);
    else if (r > 0 || !WIFEXITED(st) || WEXITSTATUS(st))
        helper_died(what, input, st, r > 0, err, cap);
    else if ((rc = h->rc))
        say(err, cap, h->err[0] ? h->err : "OpenVDB: reading failed");
    else {
        const char *q = static_cast<const char *>(mem) + sizeof(shared_head);
        info->nx = h->nx, info->ny = h->ny, info->nz = h->nz, info->ngrids = h->ngrids;
        for (int a = 0; a < 3; a++)
            info->imin[a] = h->imin[a], info->origin[a] = h->origin[a], info->voxel[a] = h->voxel[a];
        std::memcpy(info->model, h->model, sizeof info->model);
        info->model[sizeof info->model - 1] = 0;
        std::memcpy(info->projection, h->projection, sizeof info->projection);
        info->projection[sizeof info->projection - 1] = 0;
        const int ng = h->ngrids >= 0 && h->ngrids <= MAXG ? h->ngrids : 0;
        info->names = static_cast<char(*)[64]>(std::malloc((size_t)(ng ? ng : 1) * 64));
        info->units = static_cast<char(*)[64]>(std::malloc((size_t)(ng ? ng : 1) * 64));
        info->times = static_cast<int64_t *>(std::malloc((size_t)(n > 0 ? n : 1) * sizeof(int64_t)));
        if (!info->names || !info->units || !info->times) {
            vsv_vdb_info_free(info);
            say(err, cap, "out of memory");
            rc = -1;
        } else {
            info->ngrids = ng;
            std::memcpy(info->names, q, (size_t)ng * 64);
            std::memcpy(info->units, q + (size_t)MAXG * 64, (size_t)ng * 64);
            std::memcpy(info->times, q + (size_t)MAXG * 128, (size_t)n * sizeof(int64_t));
            for (int g = 0; g < ng; g++)
                info->names[g][63] = info->units[g][63] = 0;
        }
    }
    munmap(mem, bytes);
    return rc;
}

extern "C" int vsv_vdb_read(const char *path, const char *name, const vsv_vdb_info *info, float *out, char *err,
                            size_t cap)
{
    int g = 0;
    while (g < info->ngrids && std::strcmp(info->names[g], name))
        g++;
    if (g == info->ngrids) {
        say(err, cap, std::string(path) + ": no grid " + name + " in the sequence");
        return -1;
    }
    if (std::strlen(path) >= sizeof(read_request::path)) {
        say(err, cap, std::string(path) + ": path too long");
        return -1;
    }
    /* every grid of the file at once, unless that is over 1 GiB: then this one */
    const size_t cells = (size_t)info->nx * info->ny * info->nz;
    const bool all = info->ngrids <= MAXG && (size_t)info->ngrids * cells * sizeof(float) <= ((size_t)1 << 30);
    const int first = all ? 0 : g, count = all ? info->ngrids : 1;
    const size_t bytes = read_head_bytes(count) + (size_t)count * cells * sizeof(float);
    std::lock_guard<std::mutex> lock(cache.mu);
    if (cache.info != info || cache.bytes < bytes) {
        cache_drop();
        if (shared_new(bytes, &cache.memfd, &cache.mem)) {
            cache.mem = nullptr;
            say(err, cap, std::string(path) + ": cannot read it: shared memory: " + std::strerror(errno));
            return -1;
        }
        cache.bytes = bytes;
        cache.info = info;
    }
    auto *h = static_cast<shared_head *>(cache.mem);
    const read_layout l = read_parts(cache.mem, count);
    if (cache.path != path || cache.first != first || cache.count != count) {
        cache.path.clear();
        if (cache.pid <= 0) { /* start the reader */
            int sv[2];
            if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv)) {
                say(err, cap, std::string(path) + ": cannot start a reader (" + std::strerror(errno) + ")");
                return -1;
            }
            const std::string memory = std::to_string(8 * (uint64_t)bytes);
            char *argv[] = {const_cast<char *>("vsv-vdb-reader"), const_cast<char *>("read"),
                            const_cast<char *>(memory.c_str()), nullptr};
            char why[600] = "";
            const pid_t pid = vsv_helper_spawn("vsv-vdb-reader", argv, sv[1], sv[1], cache.memfd, why, sizeof why);
            close(sv[1]);
            if (pid < 0) {
                close(sv[0]);
                say(err, cap, std::string(path) + ": " + why);
                return -1;
            }
            cache.pid = pid;
            cache.sock = sv[0];
        }
        std::snprintf(l.rq->path, sizeof l.rq->path, "%s", path);
        l.rq->first = first;
        l.rq->count = count;
        l.rq->nx = info->nx, l.rq->ny = info->ny, l.rq->nz = info->nz;
        for (int a = 0; a < 3; a++)
            l.rq->imin[a] = info->imin[a];
        std::memcpy(l.names, info->names + first, (size_t)count * 64);
        h->rc = -1;
        const uint64_t input = input_bytes(&path, 1);
        char c = 1;
        ssize_t n;
        int ready = 1;
        /* a dead reader is a reply of 0 bytes, not SIGPIPE */
        while ((n = send(cache.sock, &c, 1, MSG_NOSIGNAL)) < 0 && errno == EINTR) {
        }
        if (n == 1 && (ready = vsv_helper_poll(cache.sock, time_limit(input) + 5)) > 0)
            while ((n = read(cache.sock, &c, 1)) < 0 && errno == EINTR) {
            }
        if (n != 1 || ready <= 0) { /* the reader died on this file, or hangs */
            close(cache.sock);
            int st = 0;
            const int killed = vsv_helper_reap(cache.pid, ready <= 0 ? 0 : 10, &st);
            cache.pid = 0;
            cache.sock = -1;
            helper_died(path, input, st, ready <= 0 || killed, err, cap);
            return -1;
        }
        cache.path = path;
        cache.first = first;
        cache.count = count;
        cache.ok = h->rc == 0;
    }
    if (!cache.ok) {
        l.st[0].err[sizeof l.st[0].err - 1] = 0;
        say(err, cap, l.st[0].err);
        return -1;
    }
    if (l.st[g - first].rc) {
        l.st[g - first].err[sizeof l.st[0].err - 1] = 0;
        say(err, cap, l.st[g - first].err);
        return -1;
    }
    std::memcpy(out, l.data + (size_t)(g - first) * cells, cells * sizeof(float));
    return 0;
}

// ------------------------------------------------------------- writing
// OpenVDB writes in the helper too, so that no tool links it (its logging
// library, log4cplus, aborts before main under an address-space limit of
// 155 MB, whatever the tool then does): the grids go to it as a stream of
// dense floats, NaN where a cell is inactive (an EMPTY brick, a no-data or
// code-0 cell); it writes the temporary made and listed here, which is
// synced and renamed here only when it answers that all went well.

namespace
{

// The grid's metadata into the request (as vsv_vdb.h says).
void describe(write_request *rq, write_grid *grids, const vsv_meta *m, int64_t t, const vsv_volume *const *vols, int n)
{
    // the vertical axis: even heights, or (a file of format 1.0, which has
    // no per-column heights) the native levels' mean spacing
    double z0 = m->origin[2], dz = m->spacing[2];
    if (m->vert_kind != VSV_VERT_EVEN && m->levels && m->nz > 1) {
        z0 = m->levels[0];
        dz = (m->levels[m->nz - 1] - m->levels[0]) / (m->nz - 1);
    }
    const double o[3] = {m->origin[0], m->origin[1], z0}, d[3] = {m->spacing[0], m->spacing[1], dz};
    for (int a = 0; a < 3; a++)
        rq->origin[a] = o[a], rq->spacing[a] = d[a];
    vsv_time_format(t, rq->time, sizeof rq->time);
    std::snprintf(rq->model, sizeof rq->model, "%s", m->model);
    std::snprintf(rq->run, sizeof rq->run, "%s", m->run);
    std::snprintf(rq->projection, sizeof rq->projection, "%s lat0=%.10g lon0=%.10g lat1=%.10g lat2=%.10g radius=%.10g",
                  vsv_proj_name(m->proj.kind), m->proj.lat0, m->proj.lon0, m->proj.lat1, m->proj.lat2, m->proj.radius);
    std::snprintf(rq->vertical, sizeof rq->vertical, "%s",
                  m->vert_kind == VSV_VERT_EVEN ? "even heights above sea level, metres"
                                                : "native levels at their mean spacing, metres");
    for (int l = 0; l < n; l++) {
        const vsv_var &var = m->vars[vols[l]->species];
        std::snprintf(grids[l].name, sizeof grids[l].name, "%s", var.name);
        std::snprintf(grids[l].units, sizeof grids[l].units, "%s", var.units);
        std::snprintf(grids[l].description, sizeof grids[l].description, "%s", var.description);
    }
}

// Level k of volume v as dense floats (x fastest), NaN where nothing is.
void plane(const vsv_volume *v, int k, float *out)
{
    const int B = v->brick;
    for (int j = 0; j < v->ny; j++)
        for (int i = 0; i < v->nx; i++) {
            const float *d = v->bricks[i / B + v->bdim[0] * (j / B + v->bdim[1] * (k / B))];
            const float x = d ? d[((size_t)(k % B) * B + j % B) * B + i % B] : NAN; // EMPTY: inactive
            out[(size_t)j * v->nx + i] = x == x && x != v->empty_value ? x : NAN;
        }
}

double seconds()
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

// Sends n bytes on the socket, waiting for room until `end` at most: 0, or
// -1 with errno (EPIPE: the helper is gone; ETIMEDOUT: it stopped reading).
int send_all(int fd, const void *p, size_t n, double end)
{
    const char *c = static_cast<const char *>(p);
    while (n) {
        const ssize_t k = send(fd, c, n, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (k > 0) {
            c += k, n -= (size_t)k;
            continue;
        }
        if (k < 0 && errno == EINTR)
            continue;
        if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            const double left = end - seconds();
            struct pollfd pf = {fd, POLLOUT, 0};
            if (left <= 0 || (poll(&pf, 1, (int)(left * 1000) + 1) == 0 && seconds() >= end)) {
                errno = ETIMEDOUT;
                return -1;
            }
            continue;
        }
        return -1;
    }
    return 0;
}

// Streams the request and reads the reply (r: 0, -1 the helper died or
// broke off, 1 it ran out of time).
int exchange(int sock, const write_request &rq, const std::vector<write_grid> &grids, const vsv_volume *const *vols,
             int n, float *buf, double end, write_reply *reply)
{
    if (send_all(sock, &rq, sizeof rq, end) || send_all(sock, grids.data(), grids.size() * sizeof(write_grid), end))
        return errno == ETIMEDOUT ? 1 : -1;
    const size_t pb = (size_t)rq.nx * rq.ny * sizeof(float);
    for (int l = 0; l < n; l++)
        for (int k = 0; k < rq.nz; k++) {
            plane(vols[l], k, buf);
            if (send_all(sock, buf, pb, end))
                return errno == ETIMEDOUT ? 1 : -1;
        }
    shutdown(sock, SHUT_WR);
    char *c = reinterpret_cast<char *>(reply);
    for (size_t got = 0; got < sizeof *reply;) {
        const int ready = vsv_helper_poll(sock, end - seconds());
        if (ready == 0)
            return 1;
        const ssize_t k = ready > 0 ? read(sock, c + got, sizeof *reply - got) : -1;
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return -1;
        got += (size_t)k;
    }
    return 0;
}

// The error for a writer that did not answer (r: exchange's result, st its
// wait status).
std::string writer_failed(int r, int st, unsigned limit)
{
    if (r > 0)
        return "the OpenVDB writer was still writing after " + std::to_string(limit) + " s: stopped";
    if (WIFSIGNALED(st))
        return "the OpenVDB library died writing it (signal " + std::to_string(WTERMSIG(st)) +
               (WTERMSIG(st) == SIGABRT ? ": out of memory?" : "") + ")";
    return "the OpenVDB writer failed (exit " + std::to_string(WIFEXITED(st) ? WEXITSTATUS(st) : -1) + ")";
}

// Runs the writer on the request: "" when the file is written, else why.
std::string run_writer(const write_request &rq, const std::vector<write_grid> &grids, const vsv_volume *const *vols,
                       int n)
{
    const uint64_t bytes = (uint64_t)n * rq.nx * rq.ny * rq.nz * sizeof(float);
    float *buf = static_cast<float *>(std::malloc((size_t)rq.nx * rq.ny * sizeof(float)));
    int sv[2] = {-1, -1};
    if (!buf)
        return "out of memory";
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv)) {
        std::free(buf);
        return std::string("cannot start the OpenVDB writer: ") + std::strerror(errno);
    }
    const std::string memory = std::to_string(8 * bytes);
    char *argv[] = {const_cast<char *>("vsv-vdb-reader"), const_cast<char *>("write"),
                    const_cast<char *>(memory.c_str()), nullptr};
    char why[600] = "";
    const pid_t pid = vsv_helper_spawn("vsv-vdb-reader", argv, sv[1], sv[1], -1, why, sizeof why);
    close(sv[1]);
    if (pid < 0) {
        close(sv[0]);
        std::free(buf);
        return why;
    }
    const unsigned limit = time_limit(bytes) + 5;
    write_reply reply;
    std::memset(&reply, 0, sizeof reply);
    const int r = exchange(sv[0], rq, grids, vols, n, buf, seconds() + limit, &reply);
    close(sv[0]);
    std::free(buf);
    int st = 0;
    vsv_helper_reap(pid, r > 0 ? 0 : 10, &st); /* (0: stopped now) */
    if (r)
        return writer_failed(r, st, limit);
    reply.err[sizeof reply.err - 1] = 0;
    return reply.rc ? (reply.err[0] ? reply.err : "cannot write") : "";
}

} // namespace

extern "C" int vsv_vdb_write(const char *path, const vsv_meta *m, int64_t t, const vsv_volume *const *vols, int n,
                             char *err, size_t cap)
{
    const std::string at = std::string(path) + ": ";
    if (n < 1 || n > MAXG) {
        say(err, cap, at + (n < 1 ? "no species to write" : "more than 1024 species"));
        return -1;
    }
    write_request rq;
    std::memset(&rq, 0, sizeof rq);
    rq.nx = vols[0]->nx, rq.ny = vols[0]->ny, rq.nz = vols[0]->nz, rq.ngrids = n;
    for (int l = 1; l < n; l++)
        if (vols[l]->nx != rq.nx || vols[l]->ny != rq.ny || vols[l]->nz != rq.nz) {
            say(err, cap, at + "the species' volumes differ in size");
            return -1;
        }
    std::vector<write_grid> grids;
    try {
        grids.resize((size_t)n);
    } catch (const std::bad_alloc &) {
        say(err, cap, at + "out of memory");
        return -1;
    }
    describe(&rq, grids.data(), m, t, vols, n);
    // the temporary beside path, listed (vsv_output.c); the helper writes it
    const int tfd = vsv_output_temp(path, NULL, rq.path, sizeof rq.path);
    if (tfd < 0) {
        say(err, cap, at + "cannot create: " + std::strerror(errno));
        return -1;
    }
    const std::string why = run_writer(rq, grids, vols, n);
    if (!why.empty()) {
        say(err, cap, at + why);
        close(tfd);
        vsv_output_discard(rq.path);
        return -1;
    }
    if (vsv_output_commit(tfd, rq.path, path)) { // synced, then renamed (or removed)
        say(err, cap, at + "cannot write: " + std::strerror(errno));
        return -1;
    }
    return 0;
}

extern "C" int vsv_vdb_probe(const unsigned char *head, size_t n)
{
    // the file starts with the 64-bit magic number 0x56444220 ("VDB "), little-endian
    return n >= 8 && head[0] == 0x20 && head[1] == 0x42 && head[2] == 0x44 && head[3] == 0x56 && !head[4] && !head[5] &&
           !head[6] && !head[7];
}
