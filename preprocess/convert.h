/* SPDX-License-Identifier: MIT
 * strata-convert as a library call: inputs in, one .strata file out.
 *
 * Design: out of core in five phases (DESIGN.md §3): scan inputs, count and plan
 * chunks, distribute points into one temporary file, index chunks in parallel
 * (workers compress and append node payloads as they finish), merge the top of the
 * tree above the chunks, then write the node table and header. Peak memory is set
 * by `memory_mib`: it bounds the write buffers and the number of chunks indexed at
 * once, and decides whether the distributed records stay in memory instead of going
 * through compressed temporary runs (not the chunk size, which depends on the input
 * only, so that the output does not depend on the budget). The same inputs and options give the
 * same bytes whatever `threads` and `memory_mib`.
 */
#ifndef STA_PREPROCESS_CONVERT_H
#define STA_PREPROCESS_CONVERT_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "knn_normals.h"

/* Defaults (the grid's is STA_STRATA_DEFAULT_CELLS). The zstd level is the
 * converter's own, below the format's STA_STRATA_DEFAULT_ZSTD_LEVEL (3): level 1
 * takes about 12 % less CPU for the whole conversion and gives a 4 % larger file on
 * the 20 M street (docs/DECISIONS.md). */
#define STA_CONVERT_DEFAULT_MEMORY_MIB     2048 /* the least default budget */
#define STA_CONVERT_DEFAULT_MEMORY_MAX_MIB 16384
#define STA_CONVERT_DEFAULT_LEAF_CAPACITY  32768
#define STA_CONVERT_DEFAULT_ZSTD_LEVEL     1

/* compress_level value that stores node payloads uncompressed (`--compress 0`). */
#define STA_CONVERT_STORE (-1)

/* Config: zero means default (sta_convert_options_defaults). */
typedef struct sta_convert_options {
    const char *const *inputs; /* LAS / PLY paths */
    size_t input_count;
    const char *output;   /* .strata path; written under a temporary name first */
    int threads;          /* 0: all cores */
    size_t memory_mib;    /* 0: sta_convert_default_memory_mib of the machine's memory;
                             budget for the process (one chunk's need is used, with a
                             warning, when larger) */
    const char *tmp_dir;  /* NULL: the output's folder */
    int compress_level;   /* 0: STA_CONVERT_DEFAULT_ZSTD_LEVEL; 1..19 zstd; STA_CONVERT_STORE */
    int grid_cells;       /* 0: STA_STRATA_DEFAULT_CELLS; a power of two, 16..1024 */
    size_t leaf_capacity; /* 0: STA_CONVERT_DEFAULT_LEAF_CAPACITY points before a split */
    size_t chunk_points;  /* 0: from the point count; tests force small chunks */
    bool runs_on_disk;    /* distribute through the temporary runs even when the records
                             fit in memory (tests and benchmarks; the output is the same) */
    bool force;           /* overwrite an existing output */
    bool keep_extra;      /* keep LAS extra dimensions (--attributes extra) */
    bool salvage;         /* read what is complete of truncated inputs */
    bool normals;         /* compute a normal and splat radius per point (SPLAT attribute) */
    int knn;              /* 0: STA_NORMALS_DEFAULT_K neighbours for --normals */
    sta_normals_method normals_method; /* 0: STA_NORMALS_MOMENTS (knn_normals.h) */
    bool progress;                     /* draw a progress line (only on a terminal) */
    const char *mirrors; /* mirror file: flag ghost points in the MIRROR attribute (keeps
                            every point; docs/MIRRORS.md), or NULL */
    atomic_bool *cancel; /* set from a signal handler to stop; may be NULL */
} sta_convert_options;

/* The default --memory on a machine with `ram_mib` MiB of physical memory (0: unknown):
 * a quarter of it, within STA_CONVERT_DEFAULT_MEMORY_MIB..STA_CONVERT_DEFAULT_MEMORY_MAX_MIB
 * (the RAM, or a container's memory limit when lower).
 * The budget sets how many chunks are indexed at once: at 2048 MiB about two, so a
 * 16-core machine converted a 20 M street with --normals no faster on 16 threads than
 * on 2; with 8 GiB 3.1x faster (docs/BENCHMARKS.md, "The viewer on a GPU"). The output
 * does not depend on it. */
size_t sta_convert_default_memory_mib(uint64_t ram_mib);

/* A cgroup memory limit file's text ("4294967296\n", or "max\n" for none) in MiB; 0 for
 * none or unreadable. The default --memory takes the smaller of the RAM and this limit,
 * so a container's limit bounds it. */
uint64_t sta_convert_memory_limit_mib(const char *text);

/* Fills the zero fields of `options` with their defaults (threads: the cores; the
 * rest: the constants above). */
void sta_convert_options_defaults(sta_convert_options *options);

/* What the conversion did, for the closing summary and benchmarks. */
typedef struct sta_convert_report {
    uint64_t point_count;
    uint32_t node_count;
    size_t chunk_count;
    int max_level;
    uint64_t raw_bytes;     /* node payloads before compression */
    uint64_t stored_bytes;  /* node payloads in the file */
    uint64_t temp_bytes;    /* temporary disk at its peak (both temporary files) */
    bool records_in_memory; /* the distributed records fit --memory: no temporary runs */
    double seconds_count;   /* per phase, wall clock */
    double seconds_distribute;
    double seconds_index;
    double seconds_merge;
    double seconds_finish;
    double seconds_total;
    double cpu_count; /* per phase, CPU time of all threads (as seconds_*) */
    double cpu_distribute;
    double cpu_index;
    double cpu_merge;
    double cpu_finish;
    double seconds_halo;          /* --normals: the halo pass (inside seconds_distribute's phase) */
    uint64_t normals_degenerate;  /* --normals: points given the fallback normal */
    uint64_t normals_beyond_halo; /* --normals: neighbourhoods wider than the halo */
    uint64_t normals_widened;     /* --normals: neighbourhoods widened beyond K */
    uint64_t normals_widened_exact; /* of which the exact widest K nearest, not a box */
    bool normals_trajectory;        /* --normals: walls faced the scanner path (GPS time) */
    int up_axis;                    /* STA_STRATA_UP_* written to the header */
    char up_why[256];               /* how it was decided (sta_inputs_up_axis) */

    /* --normals: the workers' normals heap together (memory_governor.h), the most one
     * chunk's normals took (its halo included), the chunks that ran alone and the seconds
     * workers waited for the pool or for a chunk alone (summed over them). */
    size_t normals_pool_bytes;
    size_t normals_chunk_peak_bytes;
    size_t normals_alone;
    double normals_waited_s;
} sta_convert_report;

/* Runs the whole conversion. On any failure no output and no temporary file is left
 * behind. `report` may be NULL. */
sta_status sta_convert(const sta_convert_options *options, sta_convert_report *report,
                       sta_error *err);

/* Sets the process's heap (glibc's malloc) to keep what it is given back: one arena for
 * all threads, blocks up to 32 MiB from it rather than mapped apart, and freed memory not
 * returned to the system. The index phase allocates and frees its chunks' arrays (the
 * normals' above all) once a chunk; without this, each chunk's arrays are new pages that
 * fault in again (a fifth of a --normals run's time was the kernel's). Peak memory is
 * that of the largest chunks at once, as before. Process-wide: call it once, before any
 * thread starts (strata-convert's main does). Returns false where the C library refused a
 * setting (the conversion is the same either way, only slower). */
bool sta_convert_keep_heap(void);

#endif
