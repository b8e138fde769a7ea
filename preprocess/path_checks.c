/* SPDX-License-Identifier: MIT
 * The converter's path checks (see path_checks.h). Inputs are compared by device and
 * inode after sorting, so thousands of tiles cost n log n, not n².
 */
#include "path_checks.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/alloc.h"

typedef struct file_id {
    dev_t device;
    ino_t inode;
    size_t index; /* position on the command line */
} file_id;

static int compare_ids(const void *a, const void *b)
{
    const file_id *x = a, *y = b;
    if (x->device != y->device) {
        return x->device < y->device ? -1 : 1;
    }
    if (x->inode != y->inode) {
        return x->inode < y->inode ? -1 : 1;
    }
    return x->index < y->index ? -1 : x->index > y->index ? 1 : 0;
}

sta_status sta_path_checks_run(const char *const *inputs, size_t input_count, const char *output,
                               bool force, sta_error *err)
{
    struct stat out_st;
    bool output_exists = stat(output, &out_st) == 0;
    if (output_exists && S_ISDIR(out_st.st_mode)) {
        return sta_fail(err, STA_ERR_ARG, "%s: the output is a folder; give a file name", output);
    }
    file_id *ids = sta_alloc_array(input_count ? input_count : 1, sizeof(*ids));
    if (!ids) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu inputs", input_count);
    }
    sta_status status = STA_OK;
    size_t known = 0;
    for (size_t i = 0; i < input_count && status == STA_OK; i++) {
        struct stat st;
        if (stat(inputs[i], &st) != 0) {
            continue; // the reader reports it with its own message
        }
        if (output_exists && st.st_dev == out_st.st_dev && st.st_ino == out_st.st_ino) {
            status = sta_fail(err, STA_ERR_ARG,
                              "%s: the output is the input %s (the same file); refusing to "
                              "overwrite an input, even with --force",
                              output, inputs[i]);
        }
        ids[known++] = (file_id){ st.st_dev, st.st_ino, i };
    }
    if (status == STA_OK && output_exists && !force) {
        status =
            sta_fail(err, STA_ERR_ARG, "%s: already exists (use --force to overwrite)", output);
    }
    if (status == STA_OK && known > 1) {
        qsort(ids, known, sizeof(*ids), compare_ids);
        for (size_t i = 1; i < known; i++) {
            if (ids[i].device == ids[i - 1].device && ids[i].inode == ids[i - 1].inode) {
                status = sta_fail(err, STA_ERR_ARG,
                                  "%s and %s are the same file: an input given twice would "
                                  "store its points twice",
                                  inputs[ids[i - 1].index], inputs[ids[i].index]);
                break;
            }
        }
    }
    sta_free(ids);
    return status;
}
