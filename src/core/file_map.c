/* SPDX-License-Identifier: MIT
 * Read-only memory maps of whole files. */
#include "core/file_map.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/alloc.h"

sta_status sta_file_map_open(const char *path, sta_file_map *out_map, sta_error *err)
{
    memset(out_map, 0, sizeof(*out_map));
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return sta_fail(err, STA_ERR_IO, "%s: cannot stat: %s", path, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return sta_fail(err, STA_ERR_IO, "%s: not a regular file", path);
    }
    char *path_copy = sta_strdup(path);
    if (!path_copy) {
        close(fd);
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    const uint8_t *data = NULL;
    size_t size = (size_t)st.st_size;
    if (size > 0) {
        void *mapped = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (mapped == MAP_FAILED) {
            int e = errno;
            close(fd);
            sta_free(path_copy);
            return sta_fail(err, STA_ERR_IO, "%s: cannot map %zu bytes: %s", path, size,
                            strerror(e));
        }
        data = mapped;
    }
    close(fd);
    out_map->data = data;
    out_map->size = size;
    out_map->path = path_copy;
    out_map->is_mapped = data != NULL;
    return STA_OK;
}

sta_status sta_file_map_wrap(const uint8_t *data, size_t size, const char *path,
                             sta_file_map *out_map, sta_error *err)
{
    memset(out_map, 0, sizeof(*out_map));
    char *copy = sta_strdup(path);
    if (!copy) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    out_map->data = size ? data : NULL;
    out_map->size = size;
    out_map->path = copy;
    return STA_OK;
}

void sta_file_map_drop(const sta_file_map *map, size_t offset, size_t size)
{
    if (!map->is_mapped || offset >= map->size) {
        return;
    }
    size_t end = size > map->size - offset ? map->size : offset + size;
    size_t page = (size_t)sysconf(_SC_PAGESIZE);
    size_t first = (offset + page - 1) / page * page;
    size_t last = end / page * page;
    if (last > first) {
        // Clean file pages: dropping them only costs a re-read if touched again.
        madvise((void *)(map->data + first), last - first, MADV_DONTNEED);
    }
}

void sta_file_map_advise_sequential(const sta_file_map *map)
{
    if (map->is_mapped && map->size > 0) {
        madvise((void *)map->data, map->size, MADV_SEQUENTIAL);
    }
}

void sta_file_map_close(sta_file_map *map)
{
    if (!map->path) {
        return;
    }
    if (map->data && map->is_mapped) {
        munmap((void *)map->data, map->size);
    }
    sta_free(map->path);
    memset(map, 0, sizeof(*map));
}
