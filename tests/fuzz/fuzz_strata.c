/* SPDX-License-Identifier: MIT
 * Fuzz target for .strata files: open from memory, decode every node, verify.
 *
 * Each input is opened twice: as a reader would (checksums on, so most mutations
 * stop at a checksum), and with checksums ignored, so that mutated tables and
 * payloads reach the structural checks, zstd and the codec. The target traps when
 * an opened file breaks what open promises (payload ranges inside the file,
 * children inside the table, failures with a message).
 */
#include <stddef.h>
#include <stdint.h>

#include "format/strata_reader.h"

#define CHECK(cond)                                                                                \
 do {                                                                                              \
  if (!(cond)) {                                                                                   \
   __builtin_trap();                                                                               \
  }                                                                                                \
 } while (0)

static void exercise(const sta_strata_reader *r, size_t size)
{
    const sta_strata_info *info = sta_strata_reader_info(r);
    CHECK(info->node_count >= 1 && info->file_size == size);
    sta_strata_decoder *dec = NULL;
    if (sta_strata_decoder_create(&dec, NULL) != STA_OK) {
        return;
    }
    uint64_t points = 0;
    for (uint32_t k = 0; k < info->node_count; k++) {
        const sta_strata_node *n = sta_strata_reader_node(r, k);
        CHECK(n != NULL);
        CHECK(n->payload.offset <= size && n->payload.stored_size <= size - n->payload.offset);
        CHECK(n->child_mask == 0 || (n->first_child > k && n->first_child < info->node_count));
        points += n->point_count;
        sta_error err = { 0 };
        sta_strata_points pts;
        sta_status s = sta_strata_decode_node(r, k, dec, &pts, &err);
        if (s == STA_OK) {
            CHECK(pts.count == n->point_count);
        } else {
            CHECK(err.code == s && err.message[0] != '\0');
        }
    }
    CHECK(points == info->point_count);
    sta_strata_decoder_destroy(dec);
    sta_error err = { 0 };
    sta_status s = sta_strata_verify(r, NULL, NULL, &err);
    CHECK(s == STA_OK || err.message[0] != '\0');
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    for (int pass = 0; pass < 2; pass++) {
        sta_strata_open_options options = { .ignore_checksums = pass == 1,
                                            .max_node_raw_bytes = (uint64_t)1 << 20 };
        sta_strata_reader *r = NULL;
        sta_error err = { 0 };
        sta_status s = sta_strata_open_memory(data, size, "fuzz.strata", &options, &r, &err);
        if (s != STA_OK) {
            CHECK(r == NULL && err.code == s && err.message[0] != '\0');
            continue;
        }
        exercise(r, size);
        sta_strata_close(r);
    }
    return 0;
}
