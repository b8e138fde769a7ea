/* SPDX-License-Identifier: MIT
 * Fuzz target for the LAZ decoder behind the LAS reader: opens the bytes, reads every
 * point in batches of 500, seeks into the middle and back to the start and reads
 * again. Decoding errors are allowed (damaged chunks), but a failed call must leave a
 * message naming the input, reads must keep their promises (counts, first indices,
 * field ranges), and nothing may crash, leak or hang.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "core/log.h"
#include "io/cloud.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(condition)                                                                           \
 do {                                                                                              \
  if (!(condition)) {                                                                              \
   __builtin_trap();                                                                               \
  }                                                                                                \
 } while (0)

static void check_batch(const sta_point_batch *batch)
{
    for (size_t i = 0; i < batch->count; i++) {
        const sta_point *p = &batch->points[i];
        CHECK(p->return_number < 16 && p->number_of_returns < 16);
        CHECK(p->scan_direction_flag < 2 && p->edge_of_flight_line < 2);
    }
}

// Reads to the end or the first error; returns the points read.
static uint64_t read_on(sta_cloud_reader *reader, sta_point_batch *batch, uint64_t from)
{
    uint64_t total = from;
    for (;;) {
        sta_error err = { 0 };
        if (sta_cloud_read(reader, batch, &err) != STA_OK) {
            CHECK(err.message[0] != '\0' && strstr(err.message, "fuzz.laz"));
            return total;
        }
        if (batch->count == 0) {
            return total;
        }
        CHECK(batch->first_index == total);
        check_batch(batch);
        total += batch->count;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sta_log_set_level(STA_LOG_QUIET); // warnings about broken files are expected here
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    if (sta_cloud_open_memory(data, size, "fuzz.laz", NULL, &reader, &err) != STA_OK) {
        CHECK(reader == NULL);
        CHECK(err.code != STA_OK && err.message[0] != '\0');
        return 0;
    }
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    CHECK(info->point_format >= 0 && info->point_format <= 10);
    sta_point_batch batch = { 0 };
    if (sta_point_batch_init(&batch, 500, info->extra_size, &err) != STA_OK) {
        sta_cloud_close(reader);
        return 0;
    }
    uint64_t total = read_on(reader, &batch, 0);
    CHECK(total <= info->point_count);
    uint64_t middle = info->point_count / 2;
    CHECK(sta_cloud_seek(reader, middle, &err) == STA_OK);
    (void)read_on(reader, &batch, middle);
    CHECK(sta_cloud_seek(reader, 0, &err) == STA_OK);
    CHECK(read_on(reader, &batch, 0) == total); // decoding is deterministic
    CHECK(sta_cloud_seek(reader, info->point_count + 1, &err) == STA_ERR_ARG);
    sta_point_batch_release(&batch);
    sta_cloud_close(reader);
    return 0;
}
