/* SPDX-License-Identifier: MIT
 * Fuzz target for the LAS reader: opens the bytes (strict and salvaging), reads every
 * point in batches of 1000, seeks to the middle and reads again, and touches every
 * info field. Traps on results that contradict the reader's own promises (a failed
 * open without a message, counts that do not add up, extra dimensions outside the
 * extra bytes, decoded fields out of their bit ranges).
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

static size_t touch_info(const sta_cloud_info *info, size_t size)
{
    size_t sum =
        strlen(info->path) + strlen(info->system_identifier) + strlen(info->generating_software);
    for (size_t i = 0; i < info->vlr_count; i++) {
        const sta_vlr_info *vlr = &info->vlrs[i];
        sum += strlen(vlr->user_id) + strlen(vlr->description) + vlr->record_id;
        // Every listed record lies whole inside the input.
        CHECK(vlr->data_offset <= size && vlr->length <= size - vlr->data_offset);
        // VLRs come first, EVLRs after.
        CHECK(i == 0 || !info->vlrs[i - 1].is_extended || vlr->is_extended);
    }
    for (size_t i = 0; i < info->extra_dim_count; i++) {
        const sta_extra_dim *dim = &info->extra_dims[i];
        sum += strlen(dim->name) + strlen(dim->description);
        CHECK(dim->size_bytes > 0);
        CHECK(dim->offset_bytes + dim->size_bytes <= info->extra_size);
        CHECK(i == 0 || dim->offset_bytes >= info->extra_dims[i - 1].offset_bytes +
                                                 info->extra_dims[i - 1].size_bytes);
        CHECK(dim->component_count >= 1 && dim->component_count <= 3);
    }
    if (info->crs_wkt) {
        sum += strlen(info->crs_wkt);
    }
    CHECK(info->point_format >= 0 && info->point_format <= 10);
    CHECK(info->record_length >= 20 && info->extra_size < info->record_length);
    CHECK(info->point_count + info->skipped_point_count == info->header_point_count);
    for (int axis = 0; axis < 3; axis++) {
        CHECK(info->grid.scale[axis] > 0.0);
    }
    return sum;
}

static void check_batch(const sta_point_batch *batch)
{
    for (size_t i = 0; i < batch->count; i++) {
        const sta_point *p = &batch->points[i];
        CHECK(p->return_number < 16 && p->number_of_returns < 16);
        CHECK(p->classification_flags < 16 && p->scanner_channel < 4);
        CHECK(p->scan_direction_flag < 2 && p->edge_of_flight_line < 2);
    }
}

static void exercise(const uint8_t *data, size_t size, bool salvage)
{
    sta_read_options options = { .salvage_truncated = salvage };
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    if (sta_cloud_open_memory(data, size, "fuzz.las", &options, &reader, &err) != STA_OK) {
        CHECK(reader == NULL);
        CHECK(err.code != STA_OK && err.message[0] != '\0');
        return;
    }
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    CHECK(salvage || info->skipped_point_count == 0);
    volatile size_t sink = touch_info(info, size);
    (void)sink;

    // Huge records make batches huge; fewer points per batch keep the fuzzer fast.
    size_t capacity = info->extra_size > 1024 ? 16 : 1000;
    sta_point_batch batch = { 0 };
    if (sta_point_batch_init(&batch, capacity, info->extra_size, &err) != STA_OK) {
        sta_cloud_close(reader);
        return;
    }
    uint64_t total = 0;
    for (;;) {
        CHECK(sta_cloud_read(reader, &batch, &err) == STA_OK);
        if (batch.count == 0) {
            break;
        }
        CHECK(batch.first_index == total);
        check_batch(&batch);
        total += batch.count;
    }
    CHECK(total == info->point_count);

    uint64_t middle = info->point_count / 2;
    CHECK(sta_cloud_seek(reader, middle, &err) == STA_OK);
    CHECK(sta_cloud_read(reader, &batch, &err) == STA_OK);
    CHECK(batch.first_index == middle);
    CHECK(batch.count ==
          (info->point_count - middle < capacity ? info->point_count - middle : capacity));
    check_batch(&batch);
    CHECK(sta_cloud_seek(reader, info->point_count + 1, &err) == STA_ERR_ARG);

    sta_point_batch_release(&batch);
    sta_cloud_close(reader);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sta_log_set_level(STA_LOG_QUIET); // warnings about broken files are expected here
    exercise(data, size, false);
    exercise(data, size, true);
    return 0;
}
