/* SPDX-License-Identifier: MIT
 * Shared helpers for the cmocka tests. */
#include "test_support.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

static int case_skipped;
static char tmpdir_path[256];
static char joined[4096];

const char *sta_test_shared_data(void)
{
    static char found[4096];
    const char *env = getenv("STA_SHARED_DATA");
    const char *candidates[] = { env, STA_DEFAULT_SHARED_DATA };
    for (size_t i = 0; i < 2; i++) {
        struct stat st;
        if (candidates[i] && candidates[i][0] && strlen(candidates[i]) < sizeof(found) &&
            stat(candidates[i], &st) == 0 && S_ISDIR(st.st_mode)) {
            memcpy(found, candidates[i], strlen(candidates[i]) + 1);
            return found;
        }
    }
    return NULL;
}

const char *sta_test_shared_path(const char *relative)
{
    const char *root = sta_test_shared_data();
    if (!root) {
        return NULL;
    }
    int n = snprintf(joined, sizeof(joined), "%s/%s", root, relative);
    if (n < 0 || (size_t)n >= sizeof(joined)) {
        fail_msg("path too long: %s/%s", root, relative);
    }
    return joined;
}

static void remove_tree(const char *path)
{
    DIR *dir = opendir(path);
    if (!dir) {
        return;
    }
    struct dirent *entry;
    char child[4096];
    while ((entry = readdir(dir)) != NULL) {
        if (strcmp(entry->d_name, ".") == 0 || strcmp(entry->d_name, "..") == 0) {
            continue;
        }
        int n = snprintf(child, sizeof(child), "%s/%s", path, entry->d_name);
        if (n < 0 || (size_t)n >= sizeof(child)) {
            continue;
        }
        struct stat st;
        if (lstat(child, &st) == 0 && S_ISDIR(st.st_mode)) {
            remove_tree(child);
        } else {
            unlink(child);
        }
    }
    closedir(dir);
    rmdir(path);
}

static void remove_tmpdir(void)
{
    if (tmpdir_path[0]) {
        remove_tree(tmpdir_path);
    }
}

const char *sta_test_tmpdir(void)
{
    if (!tmpdir_path[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(tmpdir_path, sizeof(tmpdir_path), "%s/sta-test-XXXXXX",
                 base && base[0] ? base : "/tmp");
        if (!mkdtemp(tmpdir_path)) {
            fail_msg("cannot create a temporary folder");
        }
        atexit(remove_tmpdir);
    }
    return tmpdir_path;
}

const char *sta_test_tmp_path(const char *name)
{
    int n = snprintf(joined, sizeof(joined), "%s/%s", sta_test_tmpdir(), name);
    if (n < 0 || (size_t)n >= sizeof(joined)) {
        fail_msg("path too long: %s", name);
    }
    return joined;
}

void sta_test_mark_skipped(const char *reason)
{
    case_skipped = 1;
    fprintf(stderr, "SKIPPED: %s\n", reason);
}

uint8_t *sta_test_read_file(const char *path, size_t *out_size)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fail_msg("cannot open %s", path);
    }
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *data = malloc(size > 0 ? (size_t)size : 1);
    assert_non_null(data);
    if (size > 0 && fread(data, 1, (size_t)size, f) != (size_t)size) {
        fail_msg("cannot read %s", path);
    }
    fclose(f);
    *out_size = (size_t)size;
    return data;
}

bool sta_test_files_equal(const char *a, const char *b)
{
    size_t na = 0, nb = 0;
    uint8_t *da = sta_test_read_file(a, &na);
    uint8_t *db = sta_test_read_file(b, &nb);
    bool same = na == nb && memcmp(da, db, na) == 0;
    free(da);
    free(db);
    return same;
}

void sta_test_write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        fail_msg("cannot create %s", path);
    }
    if (size > 0 && fwrite(data, 1, size, f) != size) {
        fail_msg("cannot write %s", path);
    }
    fclose(f);
}

int sta_test_run(const char *group, const struct CMUnitTest *tests, size_t count, int argc,
                 char **argv)
{
    if (argc > 1) {
        // One case by exact name, as ctest registers them.
        for (size_t i = 0; i < count; i++) {
            if (strcmp(tests[i].name, argv[1]) == 0) {
                int failed = _cmocka_run_group_tests(group, &tests[i], 1, NULL, NULL);
                if (failed == 0 && case_skipped) {
                    return 77;
                }
                return failed;
            }
        }
        fprintf(stderr, "no test case named %s in %s\n", argv[1], group);
        return 2;
    }
    return _cmocka_run_group_tests(group, tests, count, NULL, NULL);
}

void sta_test_random_grid(int32_t (*grid)[3], size_t n, const int32_t corner[3], int32_t side,
                          uint32_t seed, bool plane)
{
    uint32_t s = seed;
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            grid[i][a] = corner[a] + (int32_t)(sta_test_next_random(&s) % (uint32_t)side);
        }
        if (plane && i % 2 == 1) {
            grid[i][2] = corner[2] + (grid[i][0] - corner[0]) / 3 + (grid[i][1] - corner[1]) / 5;
        }
        if (i % 5 == 4) {
            memcpy(grid[i], grid[(i / 50) * 5], sizeof(grid[i]));
        }
    }
}

size_t sta_test_pole_side(int64_t (*d)[3], const double centre[3])
{
    const double pi = 3.14159265358979323846;
    size_t n = 0;
    for (int k = 0; k < 21; k++) {
        for (int j = 0; j < 60; j++, n++) {
            double phi = (-80.0 + 160.0 * (double)j / 59.0) * pi / 180.0;
            d[n][0] = (int64_t)llround(centre[0] + 110.0 * cos(phi));
            d[n][1] = (int64_t)llround(centre[1] + 110.0 * sin(phi));
            d[n][2] = (int64_t)llround(centre[2] - 50.0 + 5.0 * k);
        }
    }
    return n;
}

size_t sta_test_tilted_plane(int64_t (*d)[3], double normal[3])
{
    size_t n = 0;
    for (int i = 0; i < 40; i++) {
        for (int j = 0; j < 40; j++, n++) {
            d[n][0] = 10 + 12 * i;
            d[n][1] = 10 + 12 * j;
            d[n][2] = 100 + 3 * i + 2 * j;
        }
    }
    const double up[3] = { -0.25, -1.0 / 6.0, 1.0 };
    double length = sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
    for (int a = 0; a < 3; a++) {
        normal[a] = up[a] / length;
    }
    return n;
}

double sta_test_resident_bytes(void)
{
    long pages = 0, resident = 0;
    FILE *statm = fopen("/proc/self/statm", "r");
    if (!statm) {
        return -1.0;
    }
    int read = fscanf(statm, "%ld %ld", &pages, &resident);
    fclose(statm);
    return read == 2 ? (double)resident * (double)sysconf(_SC_PAGESIZE) : -1.0;
}

double sta_test_peak_growth(double start_bytes)
{
    struct rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    return (double)usage.ru_maxrss * 1024.0 - start_bytes; // maxrss is in KiB on Linux
}
