/* vsv_nc_file.c — the netCDF files the readers hold open. libnetcdf (and
 * HDF5 under it) reads past a file's end as zeros: a file cut while it is
 * being read would give zeros as values. Beside each file libnetcdf opens,
 * a descriptor of our own on the same file remembers its size at the open;
 * after each read the file's size now says whether it shrank (as the mapped
 * model readers' vsv_input_cut). A file replaced by another under its name
 * does not matter: both descriptors keep the one opened. */
#include "vsv_source_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <netcdf.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
    int nc, fd;
    off_t size;
} held;

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static held *files;
static size_t nfiles, cap;

/* Adds (nc, fd, size) to the files held: 0, or -1 out of memory. */
static int hold(int nc, int fd, off_t size)
{
    pthread_mutex_lock(&lock);
    if (nfiles == cap) {
        const size_t n = cap ? 2 * cap : 8;
        held *f = realloc(files, n * sizeof *f);
        if (!f) {
            pthread_mutex_unlock(&lock);
            return -1;
        }
        files = f, cap = n;
    }
    files[nfiles++] = (held){nc, fd, size};
    pthread_mutex_unlock(&lock);
    return 0;
}

int vsv_nc_open(vsv_source *s, int *nc)
{
    const int fd = open(s->path, O_RDONLY | O_CLOEXEC);
    struct stat st, now;
    if (fd < 0 || fstat(fd, &st)) {
        const int e = errno;
        if (fd >= 0)
            close(fd);
        return vsv_source_fail(s, VSV_EIO, "cannot open: %s", strerror(e));
    }
    const int rc = nc_open(s->path, NC_NOWRITE, nc);
    if (rc) {
        close(fd);
        return vsv_source_fail(s, VSV_ECORRUPT, "netCDF: %s (opening it)", nc_strerror(rc));
    }
    /* libnetcdf opened the name again: the same file, or refused */
    if (stat(s->path, &now) || now.st_dev != st.st_dev || now.st_ino != st.st_ino) {
        nc_close(*nc);
        close(fd);
        return vsv_source_fail(s, VSV_EIO, "replaced by another file while it was being opened");
    }
    if (hold(*nc, fd, st.st_size)) {
        nc_close(*nc);
        close(fd);
        return VSV_ENOMEM;
    }
    return 0;
}

int vsv_nc_cut(int nc)
{
    int cut = 0;
    struct stat st;
    pthread_mutex_lock(&lock);
    for (size_t i = 0; i < nfiles; i++)
        if (files[i].nc == nc)
            cut = !fstat(files[i].fd, &st) && st.st_size < files[i].size;
    pthread_mutex_unlock(&lock);
    return cut;
}

void vsv_nc_close(int nc)
{
    pthread_mutex_lock(&lock);
    for (size_t i = 0; i < nfiles; i++)
        if (files[i].nc == nc) {
            close(files[i].fd);
            files[i] = files[--nfiles];
            break;
        }
    if (!nfiles) {
        free(files);
        files = NULL, cap = 0;
    }
    pthread_mutex_unlock(&lock);
    nc_close(nc);
}
