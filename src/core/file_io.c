/* SPDX-License-Identifier: MIT
 * Whole reads and writes at an offset. */
#include "core/file_io.h"

#include <errno.h>
#include <string.h>
#include <unistd.h>

sta_status sta_pwrite_all(int fd, const void *data, size_t size, uint64_t offset, const char *path,
                          sta_error *err)
{
    const uint8_t *p = data;
    while (size > 0) {
        ssize_t n = pwrite(fd, p, size, (off_t)offset);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return sta_fail(err, STA_ERR_IO, "%s: cannot write %zu bytes at %llu: %s", path, size,
                            (unsigned long long)offset, n < 0 ? strerror(errno) : "disk full");
        }
        p += n;
        size -= (size_t)n;
        offset += (uint64_t)n;
    }
    return STA_OK;
}

sta_status sta_pread_all(int fd, void *data, size_t size, uint64_t offset, const char *path,
                         sta_error *err)
{
    uint8_t *p = data;
    while (size > 0) {
        ssize_t n = pread(fd, p, size, (off_t)offset);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return sta_fail(err, STA_ERR_IO, "%s: cannot read %zu bytes at %llu: %s", path, size,
                            (unsigned long long)offset,
                            n < 0 ? strerror(errno) : "unexpected end of file");
        }
        p += n;
        size -= (size_t)n;
        offset += (uint64_t)n;
    }
    return STA_OK;
}
