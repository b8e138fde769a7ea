/* SPDX-License-Identifier: MIT
 * Whole reads and writes at an offset (pread/pwrite until done, EINTR retried), with
 * errors naming the file.
 */
#ifndef STA_CORE_FILE_IO_H
#define STA_CORE_FILE_IO_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* Writes all `size` bytes at `offset`. Errors: STA_ERR_IO naming `path` (disk full
 * included). Thread-safe for disjoint ranges. */
sta_status sta_pwrite_all(int fd, const void *data, size_t size, uint64_t offset, const char *path,
                          sta_error *err);

/* Reads exactly `size` bytes at `offset`. Errors: STA_ERR_IO naming `path` (an early
 * end of file included). */
sta_status sta_pread_all(int fd, void *data, size_t size, uint64_t offset, const char *path,
                         sta_error *err);

#endif
