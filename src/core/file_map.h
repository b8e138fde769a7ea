/* SPDX-License-Identifier: MIT
 * Read-only memory maps of whole files.
 */
#ifndef STA_CORE_FILE_MAP_H
#define STA_CORE_FILE_MAP_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* A read-only view of a whole file. Zero-initialise; sta_file_map_close of a zeroed
 * struct is a no-op. The bytes are const and valid until close. */
typedef struct sta_file_map {
    const uint8_t *data; /* file contents; NULL for an empty file */
    size_t size;         /* bytes */
    char *path;          /* owned copy of the path, for messages */
    int is_mapped;       /* 1 when data came from mmap and must be unmapped */
} sta_file_map;

/* Maps `path` read-only. An empty file gives data == NULL and size == 0.
 * Errors: STA_ERR_IO naming the file and the system's reason. */
sta_status sta_file_map_open(const char *path, sta_file_map *out_map, sta_error *err);

/* Wraps caller-owned bytes as a map without copying (for fuzzers and tests); `path`
 * is only used in messages. The caller keeps `data` alive until close. */
sta_status sta_file_map_wrap(const uint8_t *data, size_t size, const char *path,
                             sta_file_map *out_map, sta_error *err);

/* Tells the kernel the bytes [offset, offset + size) will not be read again soon, so
 * their pages leave this process's resident set (streaming readers call it behind
 * them to keep memory bounded). Only whole pages inside the range are dropped; a
 * later read of them still works (it faults them in again). No-op for wrapped maps. */
void sta_file_map_drop(const sta_file_map *map, size_t offset, size_t size);

/* Asks the kernel to read ahead sequentially (no-op for wrapped maps). */
void sta_file_map_advise_sequential(const sta_file_map *map);

/* Unmaps and clears the struct. */
void sta_file_map_close(sta_file_map *map);

#endif
