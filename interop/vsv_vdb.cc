// vsv_vdb.cc — the OpenVDB calls behind vsv_vdb.h (C++17 over libopenvdb),
// made only in the helper program vsv-vdb-reader (vsv_vdb_helper.cc), the
// one program that links OpenVDB. Every call is wrapped: exceptions become
// "FILE: what" errors.
#include "vsv_vdb.h"
#include "vsv_vdb_internal.h"

#include <openvdb/openvdb.h>
#include <tbb/global_control.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <string>
#include <fcntl.h>
#include <unistd.h>

namespace
{

void say(char *err, size_t cap, const std::string &s) { std::snprintf(err, cap, "%s", s.c_str()); }

// OpenVDB runs on TBB; the grids here are small and read or written once, so
// every call runs on the calling thread alone: no worker threads left behind
// at exit.
struct one_thread {
    tbb::global_control gc{tbb::global_control::max_allowed_parallelism, 1};
};

std::string meta_string(const openvdb::MetaMap &m, const char *key)
{
    auto v = m.getMetadata<openvdb::StringMetadata>(key);
    return v ? v->value() : std::string();
}

// io::File::write opens its own std::ofstream and never looks at its state
// after writing: a full disk left a short file and exit 0. Archive's
// protected writer takes a stream of ours, whose state then shows a failed
// write (badbit) and a failed close (failbit).
struct checked_archive : openvdb::io::Archive {
    void put(std::ostream &os, const openvdb::GridPtrVec &grids, const openvdb::MetaMap &meta) const
    {
        write(os, grids, /*seekable=*/true, meta); // as io::File writes
    }
};

} // namespace

// ------------------------------------------------------------- writing
// In this process: the helper vsv-vdb-reader calls it (vsv_vdb_helper.cc)
// for vsv_vdb_write (vsv_vdb_isolate.cc), which made the file and commits it

int vsv_vdb_write_here(const vsv_vdb_shm::write_request *rq, const vsv_vdb_shm::write_grid *grids, const float *values,
                       char *err, size_t cap)
{
    // the caller's temporary, opened without O_CREAT: this process never
    // makes a file by name (after the caller is gone nothing can appear)
    const int fd = open(rq->path, O_WRONLY | O_TRUNC | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        say(err, cap, std::string("cannot write: ") + std::strerror(errno));
        return -1;
    }
    const std::string target = "/proc/self/fd/" + std::to_string(fd);
    const size_t cells = (size_t)rq->nx * rq->ny * rq->nz;
    try {
        const one_thread serial;
        openvdb::initialize();
        openvdb::math::Mat4d mat = openvdb::math::Mat4d::identity();
        mat.setToScale(openvdb::Vec3d(rq->spacing[0], rq->spacing[1], rq->spacing[2]));
        mat.setTranslation(openvdb::Vec3d(rq->origin[0], rq->origin[1], rq->origin[2]));
        const auto xf = openvdb::math::Transform::createLinearTransform(mat);
        openvdb::GridPtrVec out;
        for (int l = 0; l < rq->ngrids; l++) {
            const vsv_vdb_shm::write_grid &gr = grids[l];
            auto g = openvdb::FloatGrid::create(0.0f);
            g->setName(std::string(gr.name, strnlen(gr.name, sizeof gr.name)));
            g->setGridClass(openvdb::GRID_FOG_VOLUME);
            g->setTransform(xf->copy());
            g->insertMeta("units", openvdb::StringMetadata(std::string(gr.units, strnlen(gr.units, sizeof gr.units))));
            g->insertMeta("description", openvdb::StringMetadata(std::string(
                                             gr.description, strnlen(gr.description, sizeof gr.description))));
            auto acc = g->getAccessor();
            const float *v = values + (size_t)l * cells;
            for (int k = 0; k < rq->nz; k++)
                for (int j = 0; j < rq->ny; j++)
                    for (int i = 0; i < rq->nx; i++) {
                        const float x = v[((size_t)k * rq->ny + j) * rq->nx + i];
                        if (x == x) // NaN: inactive
                            acc.setValueOn(openvdb::Coord(i, j, k), x);
                    }
            out.push_back(g);
        }
        openvdb::MetaMap meta;
        const auto text = [](const char *s, size_t n) {
            return openvdb::StringMetadata(std::string(s, strnlen(s, n)));
        };
        meta.insertMeta("time", text(rq->time, sizeof rq->time));
        meta.insertMeta("source_model", text(rq->model, sizeof rq->model));
        meta.insertMeta("run", text(rq->run, sizeof rq->run));
        meta.insertMeta("projection", text(rq->projection, sizeof rq->projection));
        meta.insertMeta("vertical", text(rq->vertical, sizeof rq->vertical));
        // the whole grid's index box, [0, grid_size - 1]: a reader keeps the
        // model's domain (and a step with nothing active is still a grid)
        meta.insertMeta("grid_size", openvdb::Vec3IMetadata(openvdb::Vec3i(rq->nx, rq->ny, rq->nz)));
        // through a stream of ours, its state checked after the last write
        // and after the close (the writes' errno is not kept by the stream:
        // the caller's sync names the cause when it fails the same way)
        errno = 0;
        std::ofstream os(target, std::ios_base::out | std::ios_base::binary | std::ios_base::trunc);
        if (os)
            checked_archive().put(os, out, meta);
        if (os)
            os.flush();
        const bool wrote = os.good();
        os.close();
        if (!wrote || os.fail()) {
            const int e = errno;
            close(fd);
            say(err, cap, std::string("cannot write") + (e ? std::string(": ") + std::strerror(e) : ""));
            return -1;
        }
        close(fd);
        return 0;
    } catch (const std::bad_alloc &) {
        close(fd);
        say(err, cap, "out of memory in the OpenVDB writer");
        return -1;
    } catch (const std::exception &e) {
        close(fd);
        say(err, cap, std::string("OpenVDB: ") + e.what());
        return -1;
    }
}

// ------------------------------------------------------------- reading
// In this process: the helper vsv-vdb-reader calls these (vsv_vdb_isolate.cc)

int vsv_vdb_scan_here(const char *const *paths, int n, vsv_vdb_info *info, char *err, size_t cap)
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
            if (fm) { // a Vesuvius file's whole grid (vsv_vdb_write_here)
                auto size = fm->getMetadata<openvdb::Vec3IMetadata>("grid_size");
                if (size && size->value().x() > 0 && size->value().y() > 0 && size->value().z() > 0)
                    box.expand(
                        openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(size->value()) - openvdb::Coord(1)));
            }
            if (f == 0 && fm) {
                std::snprintf(info->model, sizeof info->model, "%s", meta_string(*fm, "source_model").c_str());
                std::snprintf(info->projection, sizeof info->projection, "%s", meta_string(*fm, "projection").c_str());
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
                    say(err, cap,
                        at + ": grid " + g->getName() + ": only axis-aligned, scaled and translated grids are read");
                    vsv_vdb_info_free(info);
                    return -1;
                }
                const openvdb::Vec3d vs(ex[0], ey[1], ez[2]);
                if (voxel == openvdb::Vec3d(0)) {
                    voxel = vs;
                    origin0 = o;
                } else if ((vs - voxel).length() > 1e-9 * voxel.length() ||
                           (o - origin0).length() > 1e-6 * voxel.length()) {
                    say(err, cap,
                        at + ": grid " + g->getName() + ": voxel size or lattice differs from the first grid's");
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
    } catch (const std::bad_alloc &) { // memory, or a damaged size asking for more than the helper's limit
        say(err, cap, at + ": not a readable OpenVDB file, or out of memory reading it (std::bad_alloc)");
        vsv_vdb_info_free(info);
        return -1;
    } catch (const std::exception &e) {
        say(err, cap, at + ": not a readable OpenVDB file (" + e.what() + ")");
        vsv_vdb_info_free(info);
        return -1;
    }
    if (!info->ngrids || box.empty()) {
        say(err, cap,
            std::string(n ? paths[0] : "") + (info->ngrids ? ": no float grid with active voxels" : ": no float grid") +
                " in the " + (n == 1 ? "file" : "sequence"));
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
static int read_grid(openvdb::io::File &file, const char *path, const char *name, const vsv_vdb_info *info, float *out,
                     char *err, size_t cap)
{
    const size_t nx = info->nx, ny = info->ny, nz = info->nz;
    try {
        if (!file.hasGrid(name)) { // missing from this step: nothing there
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
            it.getBoundingBox(bb); // a voxel, or a whole tile
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
    } catch (const std::bad_alloc &) {
        say(err, cap,
            std::string(path) + ": not a readable OpenVDB file, or out of memory reading grid " + name +
                " (std::bad_alloc)");
        return -1;
    } catch (const std::exception &e) {
        say(err, cap, std::string(path) + ": not a readable OpenVDB file (" + e.what() + ")");
        return -1;
    }
}

int vsv_vdb_read_here(const char *path, const vsv_vdb_info *info, const char (*names)[64], int count, float *out,
                      vsv_vdb_grid_status *st)
{
    const size_t cells = (size_t)info->nx * info->ny * info->nz;
    try {
        const one_thread serial;
        openvdb::initialize();
        openvdb::io::File file(path);
        file.open(false);
        for (int g = 0; g < count; g++)
            st[g].rc = read_grid(file, path, names[g], info, out + g * cells, st[g].err, sizeof st[g].err);
        file.close();
        return 0;
    } catch (const std::bad_alloc &) {
        say(st[0].err, sizeof st[0].err,
            std::string(path) + ": not a readable OpenVDB file, or out of memory reading it (std::bad_alloc)");
        return -1;
    } catch (const std::exception &e) {
        say(st[0].err, sizeof st[0].err, std::string(path) + ": not a readable OpenVDB file (" + e.what() + ")");
        return -1;
    }
}
