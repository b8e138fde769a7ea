/* SPDX-License-Identifier: MIT
 * Replays a fuzz corpus through a fuzz target without libFuzzer, so ctest runs it on
 * every build. For each file in the given folders it feeds the whole file, every
 * truncation (each prefix length), and single-byte corruptions at a spread of
 * positions. A crash, a sanitizer report or a hang fails the test; the target itself
 * decides what is a bug (it may assert on inconsistent results).
 */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

// Feed a heap copy of exactly `size` bytes so ASan catches any read past the end.
static void feed(const uint8_t *data, size_t size)
{
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy) {
        fprintf(stderr, "replay: out of memory\n");
        exit(2);
    }
    if (size) {
        memcpy(copy, data, size);
    }
    LLVMFuzzerTestOneInput(copy, size);
    free(copy);
}

static int replay_file(const char *path, unsigned long *inputs)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "replay: cannot open %s\n", path);
        return 1;
    }
    fseek(f, 0, SEEK_END);
    long length = ftell(f);
    fseek(f, 0, SEEK_SET);
    size_t size = length > 0 ? (size_t)length : 0;
    uint8_t *data = malloc(size ? size : 1);
    if (!data || (size && fread(data, 1, size, f) != size)) {
        fprintf(stderr, "replay: cannot read %s\n", path);
        fclose(f);
        free(data);
        return 1;
    }
    fclose(f);

    for (size_t n = 0; n <= size; n++) {
        feed(data, n);
        (*inputs)++;
    }
    // Single-byte corruptions: every byte of the first 512 (headers live there), then
    // about 256 positions spread over the rest; each flipped to a few telling values.
    static const uint8_t values[] = { 0x00, 0xff, 0x80, 0x7f };
    size_t stride = size > 512 ? (size - 512) / 256 + 1 : 1;
    for (size_t pos = 0; pos < size; pos += (pos < 512 ? 1 : stride)) {
        uint8_t saved = data[pos];
        for (size_t v = 0; v < sizeof(values); v++) {
            data[pos] = values[v];
            feed(data, size);
            (*inputs)++;
        }
        data[pos] = (uint8_t)(saved ^ 0x5a);
        feed(data, size);
        (*inputs)++;
        data[pos] = saved;
    }
    free(data);
    return 0;
}

int main(int argc, char **argv)
{
    unsigned long inputs = 0, files = 0;
    int failures = 0;
    for (int i = 1; i < argc; i++) {
        DIR *dir = opendir(argv[i]);
        if (!dir) {
            fprintf(stderr, "replay: cannot open corpus folder %s\n", argv[i]);
            return 1;
        }
        struct dirent *entry;
        char path[4096];
        while ((entry = readdir(dir)) != NULL) {
            if (entry->d_name[0] == '.') {
                continue;
            }
            snprintf(path, sizeof(path), "%s/%s", argv[i], entry->d_name);
            struct stat st;
            if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) {
                continue;
            }
            failures += replay_file(path, &inputs);
            files++;
        }
        closedir(dir);
    }
    if (files == 0) {
        fprintf(stderr, "replay: no corpus files found\n");
        return 1;
    }
    printf("replay: %lu files, %lu inputs, no crash\n", files, inputs);
    return failures ? 1 : 0;
}
