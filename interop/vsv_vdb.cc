// vsv_vdb.cc — the OpenVDB shim behind vsv_vdb.h (C++17 over libopenvdb).
// Every OpenVDB call is wrapped: exceptions become "FILE: what" errors.
#include "vsv_vdb.h"

#include <openvdb/openvdb.h>
#include <tbb/global_control.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>


namespace {

void say(char *err, size_t cap, const std::string &s) { std::snprintf(err, cap, "%s", s.c_str()); }

// OpenVDB runs on TBB; the grids here are small and read or written once, so
// every call runs on the calling thread alone: no worker threads left behind
// at exit or alive across the fork below.
struct one_thread {
    tbb::global_control gc{tbb::global_control::max_allowed_parallelism, 1};
};

std::string iso(int64_t t)
{
    char buf[64];
    vsv_time_format(t, buf, sizeof buf);
    return buf;
}

std::string meta_string(const openvdb::MetaMap &m, const char *key)
{
    auto v = m.getMetadata<openvdb::StringMetadata>(key);
    return v ? v->value() : std::string();
}

}  // namespace

extern "C" int vsv_vdb_write(const char *path, const vsv_meta *m, int64_t t, const vsv_volume *const *vols, int n,
                             char *err, size_t cap)
{
    const std::string tmp = std::string(path) + ".tmp." + std::to_string(getpid());
    try {
        const one_thread serial;
        openvdb::initialize();
        // the vertical axis: even heights, or (a file of format 1.0, which has
        // no per-column heights) the native levels' mean spacing
        double z0 = m->origin[2], dz = m->spacing[2];
        if (m->vert_kind != VSV_VERT_EVEN && m->levels && m->nz > 1) {
            z0 = m->levels[0];
            dz = (m->levels[m->nz - 1] - m->levels[0]) / (m->nz - 1);
        }
        openvdb::math::Mat4d mat = openvdb::math::Mat4d::identity();
        mat.setToScale(openvdb::Vec3d(m->spacing[0], m->spacing[1], dz));
        mat.setTranslation(openvdb::Vec3d(m->origin[0], m->origin[1], z0));
        const auto xf = openvdb::math::Transform::createLinearTransform(mat);
        openvdb::GridPtrVec grids;
        for (int l = 0; l < n; l++) {
            const vsv_volume *v = vols[l];
            const vsv_var &var = m->vars[v->species];
            auto g = openvdb::FloatGrid::create(0.0f);
            g->setName(var.name);
            g->setGridClass(openvdb::GRID_FOG_VOLUME);
            g->setTransform(xf->copy());
            g->insertMeta("units", openvdb::StringMetadata(var.units));
            g->insertMeta("description", openvdb::StringMetadata(var.description));
            auto acc = g->getAccessor();
            const int B = v->brick;
            for (int b = 0; b < v->nbricks; b++) {
                const float *d = v->bricks[b];
                if (!d)
                    continue;  // EMPTY: stays inactive
                const int bi = b % v->bdim[0], bj = b / v->bdim[0] % v->bdim[1], bk = b / (v->bdim[0] * v->bdim[1]);
                for (int k = 0; k < B && bk * B + k < v->nz; k++)
                    for (int j = 0; j < B && bj * B + j < v->ny; j++)
                        for (int i = 0; i < B && bi * B + i < v->nx; i++) {
                            const float x = d[((size_t)k * B + j) * B + i];
                            if (x == x && x != v->empty_value)
                                acc.setValueOn(openvdb::Coord(bi * B + i, bj * B + j, bk * B + k), x);
                        }
            }
            grids.push_back(g);
        }
        openvdb::MetaMap meta;
        meta.insertMeta("time", openvdb::StringMetadata(iso(t)));
        meta.insertMeta("source_model", openvdb::StringMetadata(m->model));
        meta.insertMeta("run", openvdb::StringMetadata(m->run));
        char proj[256];
        std::snprintf(proj, sizeof proj, "%s lat0=%.10g lon0=%.10g lat1=%.10g lat2=%.10g radius=%.10g",
                      vsv_proj_name(m->proj.kind), m->proj.lat0, m->proj.lon0, m->proj.lat1, m->proj.lat2,
                      m->proj.radius);
        meta.insertMeta("projection", openvdb::StringMetadata(proj));
        meta.insertMeta("vertical", openvdb::StringMetadata(m->vert_kind == VSV_VERT_EVEN
                                                                ? "even heights above sea level, metres"
                                                                : "native levels at their mean spacing, metres"));
        openvdb::io::File file(tmp);
        file.write(grids, meta);
        file.close();
        if (std::rename(tmp.c_str(), path)) {
            std::remove(tmp.c_str());
            say(err, cap, std::string(path) + ": cannot write: " + std::strerror(errno));
            return -1;
        }
        return 0;
    } catch (const std::exception &e) {
        std::remove(tmp.c_str());
        say(err, cap, std::string(path) + ": OpenVDB: " + e.what());
        return -1;
    }
}

extern "C" int vsv_vdb_probe(const unsigned char *head, size_t n)
{
    // the file starts with the 64-bit magic number 0x56444220 ("VDB "), little-endian
    return n >= 8 && head[0] == 0x20 && head[1] == 0x42 && head[2] == 0x44 && head[3] == 0x56 && !head[4] &&
           !head[5] && !head[6] && !head[7];
}

// Reading grids: one reader child for a sequence, alive from the first read
// until the sequence's info is freed (or it dies on a damaged file: the next
// read starts another). It reads every grid of the file it is sent into the
// shared memory; the grids of the file read last stay there, so the next
// grids of that file (a converter asks for them one by one) cost nothing.
namespace {
struct file_cache {
    std::mutex mu;
    std::string path;
    const vsv_vdb_info *info = nullptr; /* what the reader and memory are for */
    void *mem = nullptr;
    size_t bytes = 0;
    int first = 0, count = 0; /* the grids held: info's first .. first + count - 1 */
    int ok = 0;               /* path is held: the file opened, every grid has its status */
    pid_t pid = 0;            /* the reader, and its request and reply pipes */
    int req = -1, rep = -1;
} cache;

void reader_stop()
{
    if (cache.pid > 0) {
        close(cache.req);
        close(cache.rep);
        int st;
        while (waitpid(cache.pid, &st, 0) < 0 && errno == EINTR) {
        }
    }
    cache.pid = 0;
    cache.req = cache.rep = -1;
}

// Forgets the sequence: stops the reader, unmaps the memory.
void cache_drop()
{
    reader_stop();
    if (cache.mem)
        munmap(cache.mem, cache.bytes);
    cache.mem = nullptr;
    cache.bytes = 0;
    cache.info = nullptr;
    cache.path.clear();
}
}  // namespace

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

static int scan_impl(const char *const *paths, int n, vsv_vdb_info *info, char *err, size_t cap)
{
    std::memset(info, 0, sizeof *info);
    openvdb::CoordBBox box;
    openvdb::Vec3d voxel(0), origin0(0);
    std::string at;
    try {
        const one_thread serial;
        openvdb::initialize();
        info->times = static_cast<int64_t *>(std::calloc((size_t)(n ? n : 1), sizeof(int64_t)));
        for (int f = 0; f < n; f++) {
            at = paths[f];
            openvdb::io::File file(paths[f]);
            file.open(false);
            auto fm = file.getMetadata();
            const std::string when = fm ? meta_string(*fm, "time") : std::string();
            int64_t t;
            info->times[f] = !when.empty() && !vsv_time_parse(when.c_str(), &t) ? t : INT64_MIN;
            if (f == 0 && fm) {
                std::snprintf(info->model, sizeof info->model, "%s", meta_string(*fm, "source_model").c_str());
                std::snprintf(info->projection, sizeof info->projection, "%s",
                              meta_string(*fm, "projection").c_str());
            }
            auto grids = file.readAllGridMetadata();
            for (const auto &g : *grids) {
                if (!g->isType<openvdb::FloatGrid>())
                    continue;
                // an axis-aligned scale and translation: cell centres on a lattice
                const auto &xf = g->transform();
                const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0, 0, 0));
                const openvdb::Vec3d ex = xf.indexToWorld(openvdb::Vec3d(1, 0, 0)) - o,
                                     ey = xf.indexToWorld(openvdb::Vec3d(0, 1, 0)) - o,
                                     ez = xf.indexToWorld(openvdb::Vec3d(0, 0, 1)) - o;
                if (!xf.isLinear() || std::fabs(ex[1]) + std::fabs(ex[2]) > 1e-9 * std::fabs(ex[0]) ||
                    std::fabs(ey[0]) + std::fabs(ey[2]) > 1e-9 * std::fabs(ey[1]) ||
                    std::fabs(ez[0]) + std::fabs(ez[1]) > 1e-9 * std::fabs(ez[2]) || !(ex[0] > 0) || !(ey[1] > 0) ||
                    !(ez[2] > 0)) {
                    say(err, cap, at + ": grid " + g->getName() + ": only axis-aligned, scaled and translated grids are read");
                    vsv_vdb_info_free(info);
                    return -1;
                }
                const openvdb::Vec3d vs(ex[0], ey[1], ez[2]);
                if (voxel == openvdb::Vec3d(0)) {
                    voxel = vs;
                    origin0 = o;
                } else if ((vs - voxel).length() > 1e-9 * voxel.length() ||
                           (o - origin0).length() > 1e-6 * voxel.length()) {
                    say(err, cap, at + ": grid " + g->getName() + ": voxel size or lattice differs from the first grid's");
                    vsv_vdb_info_free(info);
                    return -1;
                }
                openvdb::CoordBBox gb;
                auto mn = g->getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MIN);
                auto mx = g->getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MAX);
                if (mn && mx) {
                    gb = openvdb::CoordBBox(openvdb::Coord(mn->value()), openvdb::Coord(mx->value()));
                } else {
                    gb = file.readGrid(g->getName())->evalActiveVoxelBoundingBox();
                }
                if (!gb.empty())
                    box.expand(gb);
                int known = 0;
                for (int i = 0; i < info->ngrids; i++)
                    known |= g->getName() == info->names[i];
                if (!known) {
                    const int k = info->ngrids++;
                    info->names = static_cast<char(*)[64]>(std::realloc(info->names, (size_t)info->ngrids * 64));
                    info->units = static_cast<char(*)[64]>(std::realloc(info->units, (size_t)info->ngrids * 64));
                    std::snprintf(info->names[k], 64, "%s", g->getName().c_str());
                    std::snprintf(info->units[k], 64, "%s", meta_string(*g, "units").c_str());
                }
            }
            file.close();
        }
    } catch (const std::exception &e) {
        say(err, cap, at + ": not a readable OpenVDB file (" + e.what() + ")");
        vsv_vdb_info_free(info);
        return -1;
    }
    if (!info->ngrids || box.empty()) {
        say(err, cap, std::string(n ? paths[0] : "") + ": no float grid with active voxels in the sequence");
        vsv_vdb_info_free(info);
        return -1;
    }
    const openvdb::Coord d = box.dim();
    info->nx = d.x(), info->ny = d.y(), info->nz = d.z();
    for (int a = 0; a < 3; a++) {
        info->imin[a] = box.min()[a];
        info->voxel[a] = voxel[a];
        info->origin[a] = origin0[a] + box.min()[a] * voxel[a];
    }
    return 0;
}

// Grid `name` of an open file onto info's grid.
static int read_grid(openvdb::io::File &file, const char *path, const char *name, const vsv_vdb_info *info,
                     float *out, char *err, size_t cap)
{
    const size_t nx = info->nx, ny = info->ny, nz = info->nz;
    try {
        if (!file.hasGrid(name)) {  // missing from this step: nothing there
            std::memset(out, 0, nx * ny * nz * sizeof(float));
            return 0;
        }
        auto g = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(name));
        if (!g) {
            say(err, cap, std::string(path) + ": grid " + name + " is not a float grid");
            return -1;
        }
        const float bg = g->background();
        for (size_t c = 0; c < nx * ny * nz; c++)
            out[c] = bg;
        const openvdb::Coord lo((int)info->imin[0], (int)info->imin[1], (int)info->imin[2]);
        const openvdb::CoordBBox dom(lo, lo + openvdb::Coord((int)nx - 1, (int)ny - 1, (int)nz - 1));
        for (auto it = g->cbeginValueOn(); it; ++it) {
            openvdb::CoordBBox bb;
            it.getBoundingBox(bb);  // a voxel, or a whole tile
            bb.intersect(dom);
            if (bb.empty())
                continue;
            const float v = *it;
            for (int k = bb.min().z(); k <= bb.max().z(); k++)
                for (int j = bb.min().y(); j <= bb.max().y(); j++)
                    for (int i = bb.min().x(); i <= bb.max().x(); i++)
                        out[((size_t)(k - lo.z()) * ny + (j - lo.y())) * nx + (i - lo.x())] = v;
        }
        return 0;
    } catch (const std::exception &e) {
        say(err, cap, std::string(path) + ": not a readable OpenVDB file (" + e.what() + ")");
        return -1;
    }
}

// Grids first .. first+count-1 of info from one file: out holds them one
// after the other, st one status per grid. 0 when the file opened (each grid
// then has its own status), else -1 with the reason in st[0].
struct grid_status {
    int rc;
    char err[252];
};

static int read_all_impl(const char *path, const vsv_vdb_info *info, int first, int count, float *out,
                         grid_status *st)
{
    const size_t cells = (size_t)info->nx * info->ny * info->nz;
    try {
        const one_thread serial;
        openvdb::initialize();
        openvdb::io::File file(path);
        file.open(false);
        for (int g = 0; g < count; g++)
            st[g].rc =
                read_grid(file, path, info->names[first + g], info, out + g * cells, st[g].err, sizeof st[g].err);
        file.close();
        return 0;
    } catch (const std::exception &e) {
        say(st[0].err, sizeof st[0].err, std::string(path) + ": not a readable OpenVDB file (" + e.what() + ")");
        return -1;
    }
}

// ------------------------------------------------------------- isolation
// OpenVDB files carry no checksums and the library trusts what it reads: a
// damaged file can crash it. Reading therefore runs in a forked child that
// writes its results into shared memory; a child killed by a signal is a
// "damaged file" error, never a crash of the tool.

namespace {

struct shared_head {
    int rc, nx, ny, nz, ngrids, nfiles;
    int64_t imin[3];
    double origin[3], voxel[3];
    char model[64], projection[256], err[1024];
};

// Seconds a child may spend on `input` bytes of files: 20, plus one per 4 MB
// (OpenVDB reads ~100 MB/s).
unsigned time_limit(uint64_t input) { return 20u + (unsigned)(input / (4u << 20)); }

// A new child: quiet (the library's complaints about a damaged file, and no
// pipe of the caller held open) and bounded, since a damaged file can also
// send the library into reading gigabytes or looping: CPU time for `input`
// bytes, also as wall-clock time (0: none; the reader times each file itself
// with alarm) and, outside
// AddressSanitizer builds (whose shadow memory is address space), memory of
// 1 GiB + `memory` more than it has; both far above what good files need.
void child_setup(uint64_t input, uint64_t memory)
{
    const int fd = open("/dev/null", O_RDWR);
    if (fd >= 0)
        for (int k = 0; k < 3; k++)
            dup2(fd, k);
    struct rlimit rl;
    if (input) {
        rl.rlim_cur = rl.rlim_max = time_limit(input);
        setrlimit(RLIMIT_CPU, &rl);
        /* and wall-clock time: a child stuck without spending CPU (a lock
         * held at the fork by another thread) must not hang the caller */
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

// The error for a child that died reading `what` (wait status st).
void child_died(const char *what, uint64_t input, int st, char *err, size_t cap)
{
    const int sig = WIFSIGNALED(st) ? WTERMSIG(st) : 0;
    if (sig == SIGXCPU || sig == SIGALRM)
        say(err, cap, std::string(what) + ": damaged OpenVDB file (reading it took over " +
                          std::to_string(time_limit(input)) + " s)");
    else
        say(err, cap, std::string(what) + ": damaged OpenVDB file (the OpenVDB library failed reading it, signal " +
                          std::to_string(sig) + ")");
}

// Total size of the files (what a child reads).
uint64_t input_bytes(const char *const *paths, int n)
{
    uint64_t t = 0;
    for (int i = 0; i < n; i++) {
        struct stat st;
        if (stat(paths[i], &st) == 0)
            t += (uint64_t)st.st_size;
    }
    return t;
}

// Runs fn in a child with `bytes` of new shared memory, returned in *mem; 0,
// or -1 with err set.
template <class F>
int isolated(size_t bytes, const char *what, uint64_t input, F fn, void **mem, char *err, size_t cap)
{
    void *m = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) {
        say(err, cap, std::string(what) + ": out of memory");
        return -1;
    }
#ifdef __SANITIZE_ADDRESS__
    /* GCC 12's AddressSanitizer allocator is not fork-safe: a child forked
     * while another thread allocates (log4cplus, loaded with OpenVDB, starts
     * four threads at load) can wait for ever on its lock. The sanitizer
     * build reads in process; isolation is tested in the plain build. */
    (void)input;
    fn(m);
    *mem = m;
    return 0;
#endif
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) {
        munmap(m, bytes);
        say(err, cap, std::string(what) + ": cannot fork to read it");
        return -1;
    }
    if (pid == 0) {
        child_setup(input, 64 * input);
        _exit(fn(m) ? 1 : 0);
    }
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(st)) {
        munmap(m, bytes);
        child_died(what, input, st, err, cap);
        return -1;
    }
    *mem = m;
    return 0;
}

}  // namespace

extern "C" int vsv_vdb_scan(const char *const *paths, int n, vsv_vdb_info *info, char *err, size_t cap)
{
    enum { MAXG = 1024 };
    const size_t bytes = sizeof(shared_head) + (size_t)MAXG * 128 + (size_t)(n > 0 ? n : 1) * sizeof(int64_t);
    void *mem = nullptr;
    std::memset(info, 0, sizeof *info);
    if (isolated(bytes, n ? paths[0] : "", input_bytes(paths, n), [&](void *m) {
            auto *h = static_cast<shared_head *>(m);
            vsv_vdb_info in;
            h->rc = scan_impl(paths, n, &in, h->err, sizeof h->err);
            if (h->rc)
                return 1;
            struct freed {
                vsv_vdb_info *p;
                ~freed() { vsv_vdb_info_free(p); }
            } own{&in};
            if (in.ngrids > MAXG) {
                std::snprintf(h->err, sizeof h->err, "%s: more than %d grids", paths[0], (int)MAXG);
                h->rc = -1;
                return 1;
            }
            h->nx = in.nx, h->ny = in.ny, h->nz = in.nz, h->ngrids = in.ngrids, h->nfiles = n;
            for (int a = 0; a < 3; a++)
                h->imin[a] = in.imin[a], h->origin[a] = in.origin[a], h->voxel[a] = in.voxel[a];
            std::memcpy(h->model, in.model, sizeof h->model);
            std::memcpy(h->projection, in.projection, sizeof h->projection);
            char *p = static_cast<char *>(m) + sizeof(shared_head);
            std::memcpy(p, in.names, (size_t)in.ngrids * 64);
            std::memcpy(p + (size_t)MAXG * 64, in.units, (size_t)in.ngrids * 64);
            std::memcpy(p + (size_t)MAXG * 128, in.times, (size_t)n * sizeof(int64_t));
            return 0;
        }, &mem, err, cap))
        return -1;
    auto *h = static_cast<shared_head *>(mem);
    int rc = h->rc;
    if (rc) {
        say(err, cap, h->err[0] ? h->err : "OpenVDB: reading failed");
    } else {
        const char *p = static_cast<const char *>(mem) + sizeof(shared_head);
        info->nx = h->nx, info->ny = h->ny, info->nz = h->nz, info->ngrids = h->ngrids;
        for (int a = 0; a < 3; a++)
            info->imin[a] = h->imin[a], info->origin[a] = h->origin[a], info->voxel[a] = h->voxel[a];
        std::memcpy(info->model, h->model, sizeof info->model);
        std::memcpy(info->projection, h->projection, sizeof info->projection);
        info->names = static_cast<char(*)[64]>(std::malloc((size_t)h->ngrids * 64));
        info->units = static_cast<char(*)[64]>(std::malloc((size_t)h->ngrids * 64));
        info->times = static_cast<int64_t *>(std::malloc((size_t)(n > 0 ? n : 1) * sizeof(int64_t)));
        if (!info->names || !info->units || !info->times) {
            vsv_vdb_info_free(info);
            say(err, cap, "out of memory");
            rc = -1;
        } else {
            std::memcpy(info->names, p, (size_t)h->ngrids * 64);
            std::memcpy(info->units, p + (size_t)MAXG * 64, (size_t)h->ngrids * 64);
            std::memcpy(info->times, p + (size_t)MAXG * 128, (size_t)n * sizeof(int64_t));
        }
    }
    munmap(mem, bytes);
    return rc;
}


// The request the reader finds in shared memory before a byte on its pipe.
struct read_request {
    char path[4096];
    int first, count;
};

#ifndef __SANITIZE_ADDRESS__
// The reader child: waits for requests, answers each with a byte; exits when
// the request pipe closes.
[[noreturn]] static void reader_main(const vsv_vdb_info *info, void *m, size_t sbytes, int req, int rep)
{
    auto *h = static_cast<shared_head *>(m);
    auto *rq = reinterpret_cast<read_request *>(h + 1);
    for (;;) {
        char c;
        ssize_t n;
        while ((n = read(req, &c, 1)) < 0 && errno == EINTR) {
        }
        if (n != 1)
            _exit(0);
        const char *const one[1] = {rq->path};
        alarm(time_limit(input_bytes(one, 1))); /* a damaged file must not hang */
        auto *st = reinterpret_cast<grid_status *>(rq + 1);
        h->rc = read_all_impl(rq->path, info, rq->first, rq->count,
                              reinterpret_cast<float *>(static_cast<char *>(m) + sbytes), st);
        alarm(0);
        while (write(rep, &c, 1) < 0 && errno == EINTR) {
        }
    }
}

#endif

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
    const bool all = (size_t)info->ngrids * cells * sizeof(float) <= ((size_t)1 << 30);
    const int first = all ? 0 : g, count = all ? info->ngrids : 1;
    const size_t sbytes = sizeof(shared_head) + sizeof(read_request) + (size_t)count * sizeof(grid_status);
    const size_t bytes = sbytes + (size_t)count * cells * sizeof(float);
    std::lock_guard<std::mutex> lock(cache.mu);
    auto *h = static_cast<shared_head *>(cache.mem);
    if (cache.info != info || cache.bytes < bytes) {
        cache_drop();
        void *m = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED) {
            say(err, cap, std::string(path) + ": out of memory");
            return -1;
        }
        cache.mem = m;
        cache.bytes = bytes;
        cache.info = info;
        h = static_cast<shared_head *>(m);
    }
    if (cache.path != path || cache.first != first || cache.count != count) {
        cache.path.clear();
#ifdef __SANITIZE_ADDRESS__
        /* in process, as in isolated() above */
        h->rc = read_all_impl(path, info, first, count, reinterpret_cast<float *>(static_cast<char *>(cache.mem) + sbytes),
                              reinterpret_cast<grid_status *>(reinterpret_cast<read_request *>(h + 1) + 1));
#else
        if (cache.pid <= 0) { /* start the reader */
            int q[2], r[2];
            if (pipe2(q, O_CLOEXEC) || pipe2(r, O_CLOEXEC)) {
                say(err, cap, std::string(path) + ": cannot start a reader (" + std::strerror(errno) + ")");
                return -1;
            }
            std::fflush(nullptr);
            const pid_t pid = fork();
            if (pid == 0) {
                close(q[1]);
                close(r[0]);
                child_setup(0, 8 * (uint64_t)bytes);
                reader_main(info, cache.mem, sbytes, q[0], r[1]);
            }
            close(q[0]);
            close(r[1]);
            if (pid < 0) {
                close(q[1]);
                close(r[0]);
                say(err, cap, std::string(path) + ": cannot fork to read it");
                return -1;
            }
            cache.pid = pid;
            cache.req = q[1];
            cache.rep = r[0];
        }
        auto *rq = reinterpret_cast<read_request *>(h + 1);
        std::snprintf(rq->path, sizeof rq->path, "%s", path);
        rq->first = first;
        rq->count = count;
        h->rc = -1;
        char c = 1;
        ssize_t n;
        struct sigaction quiet = {}, old;
        quiet.sa_handler = SIG_IGN;
        sigaction(SIGPIPE, &quiet, &old); /* a dead reader is a reply of 0 bytes, not a signal */
        while ((n = write(cache.req, &c, 1)) < 0 && errno == EINTR) {
        }
        if (n == 1)
            while ((n = read(cache.rep, &c, 1)) < 0 && errno == EINTR) {
            }
        sigaction(SIGPIPE, &old, nullptr);
        if (n != 1) { /* the reader died on this file */
            close(cache.req);
            close(cache.rep);
            int st = 0;
            while (waitpid(cache.pid, &st, 0) < 0 && errno == EINTR) {
            }
            cache.pid = 0;
            cache.req = cache.rep = -1;
            child_died(path, input_bytes(&path, 1), st, err, cap);
            return -1;
        }
#endif
        cache.path = path;
        cache.first = first;
        cache.count = count;
        cache.ok = h->rc == 0;
    }
    const auto *st = reinterpret_cast<const grid_status *>(reinterpret_cast<const read_request *>(h + 1) + 1);
    if (!cache.ok) {
        say(err, cap, st[0].err);
        return -1;
    }
    if (st[g - first].rc) {
        say(err, cap, st[g - first].err);
        return -1;
    }
    std::memcpy(out, static_cast<const char *>(cache.mem) + sbytes + (g - first) * cells * sizeof(float),
                cells * sizeof(float));
    return 0;
}
