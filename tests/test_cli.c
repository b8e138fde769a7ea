/* SPDX-License-Identifier: MIT
 * Tests for src/core/cli: each kind's values and ranges, unknown options, missing values,
 * positional arguments, help from the table, callbacks. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/cli.h"

/* The destinations of the test table, reset to their defaults by each parse. */
typedef struct values {
    bool flag;
    bool quiet;
    int gpu_mem;
    int repeat;
    uint64_t count;
    uint64_t points;
    double threshold;
    double any;
    const char *out;
    int mode;
    int samples;
    int width, height;
} values;

static values v;

static const char *const mode_names[] = { "raw", "hpr", "fill", NULL };
static const char *const sample_names[] = { "5", "9", "17", "25", NULL };
static const int sample_values[] = { 5, 9, 17, 25 };

// --size WxH into v.width and v.height.
static sta_status parse_size(const sta_cli_option *option, const char *value, sta_error *err)
{
    values *d = option->dest;
    int w = 0, h = 0, n = 0;
    if (sscanf(value, "%dx%d%n", &w, &h, &n) != 2 || value[n] || w < 1 || h < 1) {
        return sta_cli_fail_value(err, option, value, "WxH");
    }
    d->width = w;
    d->height = h;
    return STA_OK;
}

static void show_size(const sta_cli_option *option, char *out_text, size_t size)
{
    const values *d = option->dest;
    snprintf(out_text, size, "%dx%d", d->width, d->height);
}

// A callback that fails without a message (the parser supplies one).
static sta_status parse_silent(const sta_cli_option *option, const char *value, sta_error *err)
{
    (void)option;
    (void)value;
    (void)err;
    return STA_ERR_ARG;
}

static const sta_cli_option options[] = {
    { .name = "flag", .kind = STA_CLI_FLAG, .dest = &v.flag, .help = "a flag" },
    { .name = "quiet",
      .short_name = 'q',
      .kind = STA_CLI_FLAG,
      .dest = &v.quiet,
      .help = "say less" },
    { .name = "gpu-mem",
      .kind = STA_CLI_INT,
      .dest = &v.gpu_mem,
      .metavar = "MIB",
      .int_min = 16,
      .int_max = 1048576,
      .help = "GPU memory" },
    { .name = "repeat",
      .kind = STA_CLI_INT,
      .dest = &v.repeat,
      .metavar = "R",
      .int_min = 1,
      .int_max = 1000,
      .flags = STA_CLI_ANY_NOTATION,
      .help = "repeats" },
    { .name = "count",
      .kind = STA_CLI_COUNT,
      .dest = &v.count,
      .metavar = "N",
      .help = "any count" },
    { .name = "points",
      .kind = STA_CLI_COUNT,
      .dest = &v.points,
      .metavar = "N",
      .count_min = 1,
      .count_max = UINT64_MAX,
      .flags = STA_CLI_SUFFIX,
      .help = "number of points" },
    { .heading = "numbers:",
      .name = "threshold",
      .kind = STA_CLI_DOUBLE,
      .dest = &v.threshold,
      .metavar = "T",
      .real_min = 0.0,
      .real_max = 1e6,
      .flags = STA_CLI_ABOVE_MIN,
      .help = "a threshold" },
    { .name = "any",
      .kind = STA_CLI_DOUBLE,
      .dest = &v.any,
      .metavar = "X",
      .help = "any finite number",
      .default_text = "the scene's own" },
    { .name = "out",
      .short_name = 'o',
      .kind = STA_CLI_STRING,
      .dest = &v.out,
      .metavar = "FILE",
      .help = "output file" },
    { .name = "mode",
      .kind = STA_CLI_CHOICE,
      .dest = &v.mode,
      .metavar = "MODE",
      .choices = mode_names,
      .help = "what to draw" },
    { .name = "mood",
      .kind = STA_CLI_CHOICE,
      .dest = &v.mode,
      .choices = mode_names,
      .flags = STA_CLI_HIDDEN },
    { .name = "samples",
      .kind = STA_CLI_CHOICE,
      .dest = &v.samples,
      .metavar = "N",
      .choices = sample_names,
      .choice_values = sample_values,
      .help = "sampling scheme" },
    { .name = "size",
      .kind = STA_CLI_CALLBACK,
      .dest = &v,
      .metavar = "WxH",
      .parse = parse_size,
      .show = show_size,
      .help = "image size" },
    { .name = "silent",
      .kind = STA_CLI_CALLBACK,
      .dest = &v,
      .metavar = "X",
      .parse = parse_silent,
      .help = "always refused" },
    { .name = NULL },
};

static const sta_cli cli = { .program = "test-cli",
                             .usage = "usage: test-cli [options] FILE...\n",
                             .epilog = "exit status: 0\n",
                             .options = options };

enum {
    MAX_ARGS = 32
};

static char *argv_buf[MAX_ARGS + 2];
static sta_cli_result result;
static sta_error error;

// Parses "test-cli" followed by `args` (NULL-terminated) with fresh defaults.
static sta_status parse_args(const char *const *args)
{
    memset(&v, 0, sizeof(v));
    v.gpu_mem = 1024;
    v.repeat = 5;
    v.points = 30000000;
    v.threshold = 0.1;
    v.mode = 2;
    v.samples = 9;
    v.width = 1280;
    v.height = 720;
    memset(&error, 0, sizeof(error));
    int argc = 0;
    argv_buf[argc++] = (char *)"test-cli";
    for (int i = 0; args[i]; i++) {
        assert_true(argc <= MAX_ARGS);
        argv_buf[argc++] = (char *)args[i];
    }
    argv_buf[argc] = NULL;
    return sta_cli_parse(&cli, argc, argv_buf, &result, &error);
}

#define PARSE(...) parse_args((const char *const[]){ __VA_ARGS__, NULL })

static void integers_keep_to_their_range(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--gpu-mem", "16"), STA_OK);
    assert_int_equal(v.gpu_mem, 16);
    assert_int_equal(PARSE("--gpu-mem=1048576"), STA_OK);
    assert_int_equal(v.gpu_mem, 1048576);
    assert_int_equal(PARSE("--gpu-mem", "15"), STA_ERR_ARG);
    assert_string_equal(error.message,
                        "--gpu-mem needs a whole number from 16 to 1048576, got '15'");
    assert_int_equal(v.gpu_mem, 1024);
    assert_int_equal(PARSE("--gpu-mem", "1048577"), STA_ERR_ARG);
    assert_int_equal(PARSE("--gpu-mem", "64x"), STA_ERR_ARG);
    assert_non_null(strstr(error.message, "'64x'"));
    assert_int_equal(PARSE("--gpu-mem", ""), STA_ERR_ARG);
    assert_int_equal(PARSE("--gpu-mem", "99999999999999999999"), STA_ERR_ARG);
    assert_int_equal(PARSE("--gpu-mem", "1e3"), STA_ERR_ARG);
    // With STA_CLI_ANY_NOTATION a whole number may be written as a real.
    assert_int_equal(PARSE("--repeat", "1e2"), STA_OK);
    assert_int_equal(v.repeat, 100);
    assert_int_equal(PARSE("--repeat", "7.0"), STA_OK);
    assert_int_equal(v.repeat, 7);
    assert_int_equal(PARSE("--repeat", "2.5"), STA_ERR_ARG);
    assert_int_equal(PARSE("--repeat", "nan"), STA_ERR_ARG);
    assert_int_equal(PARSE("--repeat", "1e300"), STA_ERR_ARG);
    assert_string_equal(error.message, "--repeat needs a whole number from 1 to 1000, got '1e300'");
}

static void counts_refuse_overflow_and_negatives(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--count", "18446744073709551615"), STA_OK);
    assert_true(v.count == UINT64_MAX);
    assert_int_equal(PARSE("--count", "99999999999999999999"), STA_ERR_ARG);
    assert_string_equal(error.message, "--count needs a whole number from 0 to "
                                       "18446744073709551615, got '99999999999999999999'");
    assert_int_equal(PARSE("--count", "-1"), STA_ERR_ARG);
    assert_int_equal(PARSE("--count", " -1"), STA_ERR_ARG);
    assert_int_equal(PARSE("--count", "2k"), STA_ERR_ARG); // no suffix without the flag
    // Suffixes multiply, and the product may not overflow either.
    assert_int_equal(PARSE("--points", "2k"), STA_OK);
    assert_true(v.points == 2000);
    assert_int_equal(PARSE("--points", "3M"), STA_OK);
    assert_true(v.points == 3000000);
    assert_int_equal(PARSE("--points", "4G"), STA_OK);
    assert_true(v.points == 4000000000u);
    assert_int_equal(PARSE("--points", "20000000000G"), STA_ERR_ARG);
    assert_int_equal(PARSE("--points", "12x"), STA_ERR_ARG);
    assert_string_equal(error.message, "--points needs a whole number of at least 1 (suffix k, "
                                       "M or G allowed), got '12x'");
    assert_int_equal(PARSE("--points", "0"), STA_ERR_ARG);
    assert_int_equal(PARSE("--points", "k"), STA_ERR_ARG);
}

static void doubles_refuse_nan_inf_and_open_bounds(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--threshold", "0.25"), STA_OK);
    assert_true(v.threshold == 0.25);
    assert_int_equal(PARSE("--threshold", "1e6"), STA_OK);
    assert_int_equal(PARSE("--threshold", "0"), STA_ERR_ARG);
    assert_string_equal(error.message,
                        "--threshold needs a number above 0 and at most 1e+06, got '0'");
    const char *bad[] = { "nan", "NaN", "inf", "-inf", "infinity", "1e999", "1e6x", "", "1e7" };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        assert_int_equal(PARSE("--threshold", bad[i]), STA_ERR_ARG);
        assert_true(v.threshold == 0.1);
    }
    // No range: any finite number, negative ones too (through "=" or as the next argument).
    assert_int_equal(PARSE("--any=-5.5"), STA_OK);
    assert_true(v.any == -5.5);
    assert_int_equal(PARSE("--any", "-1e300"), STA_OK);
    assert_int_equal(PARSE("--any", "nan"), STA_ERR_ARG);
    assert_string_equal(error.message, "--any needs a finite number, got 'nan'");
    assert_int_equal(PARSE("--any", "-inf"), STA_ERR_ARG);
}

static void choices_store_index_or_value(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--mode", "raw"), STA_OK);
    assert_int_equal(v.mode, 0);
    assert_int_equal(PARSE("--mood", "hpr"), STA_OK); // a hidden alias
    assert_int_equal(v.mode, 1);
    assert_int_equal(PARSE("--samples", "17"), STA_OK);
    assert_int_equal(v.samples, 17);
    assert_int_equal(PARSE("--mode", "RAW"), STA_ERR_ARG);
    assert_string_equal(error.message, "--mode takes raw, hpr or fill, got 'RAW'");
    assert_int_equal(PARSE("--samples", "7"), STA_ERR_ARG);
    assert_string_equal(error.message, "--samples takes 5, 9, 17 or 25, got '7'");
}

static void unknown_options_are_named(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--no-such-option"), STA_ERR_ARG);
    assert_string_equal(error.message, "unknown option --no-such-option (see --help)");
    assert_int_equal(PARSE("file", "--no-such=3"), STA_ERR_ARG);
    assert_string_equal(error.message, "unknown option --no-such (see --help)");
    assert_int_equal(PARSE("-x"), STA_ERR_ARG);
    assert_string_equal(error.message, "unknown option -x (see --help)");
    assert_int_equal(PARSE("-qx"), STA_ERR_ARG);
    assert_string_equal(error.message, "unknown option -x (see --help)");
    // getopt_long's abbreviations are refused: a new option cannot change an old line.
    assert_int_equal(PARSE("--gpu", "64"), STA_ERR_ARG);
    assert_string_equal(error.message, "unknown option --gpu (see --help)");
    assert_int_equal(PARSE("--fla"), STA_ERR_ARG);
    assert_int_equal(PARSE("--he"), STA_ERR_ARG);
    assert_false(result.help);
    assert_int_equal(PARSE("-help"), STA_OK); // -h first: help, as getopt reads it
    assert_true(result.help);
}

static void missing_and_unexpected_values_are_reported(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--gpu-mem"), STA_ERR_ARG);
    assert_string_equal(error.message, "--gpu-mem needs a value (MIB)");
    assert_int_equal(PARSE("file", "-o"), STA_ERR_ARG);
    assert_string_equal(error.message, "-o needs a value (FILE)");
    assert_int_equal(PARSE("--flag=1"), STA_ERR_ARG);
    assert_string_equal(error.message, "--flag takes no value, got '--flag=1'");
    assert_int_equal(PARSE("--help=1"), STA_ERR_ARG);
    // A value is the next argument whatever it looks like.
    assert_int_equal(PARSE("--out", "--flag"), STA_OK);
    assert_string_equal(v.out, "--flag");
    assert_false(v.flag);
    assert_int_equal(PARSE("--out="), STA_OK);
    assert_string_equal(v.out, "");
}

static void positional_arguments_keep_their_order(void **state)
{
    (void)state;
    assert_int_equal(PARSE("a", "--flag", "b", "-o", "x.las", "-", "c"), STA_OK);
    assert_int_equal(result.positional_count, 4);
    assert_ptr_equal(result.positional, argv_buf + 1);
    assert_string_equal(result.positional[0], "a");
    assert_string_equal(result.positional[1], "b");
    assert_string_equal(result.positional[2], "-");
    assert_string_equal(result.positional[3], "c");
    assert_true(v.flag);
    assert_string_equal(v.out, "x.las");
    // "--" ends the options.
    assert_int_equal(PARSE("a", "--", "--flag", "-o"), STA_OK);
    assert_int_equal(result.positional_count, 3);
    assert_string_equal(result.positional[1], "--flag");
    assert_string_equal(result.positional[2], "-o");
    assert_false(v.flag);
    // Short forms: combined, attached, "-o=value".
    assert_int_equal(PARSE("-qo", "y.las"), STA_OK);
    assert_true(v.quiet);
    assert_string_equal(v.out, "y.las");
    assert_int_equal(PARSE("-oz.las"), STA_OK);
    assert_string_equal(v.out, "z.las");
    assert_int_equal(PARSE("-o=w.las"), STA_OK);
    assert_string_equal(v.out, "w.las");
    assert_int_equal(result.positional_count, 0);
    // The last of a repeated option wins.
    assert_int_equal(PARSE("--gpu-mem", "20", "--gpu-mem", "30"), STA_OK);
    assert_int_equal(v.gpu_mem, 30);
    // Nothing at all.
    assert_int_equal(PARSE("--flag"), STA_OK);
    assert_int_equal(result.positional_count, 0);
    char *only[] = { (char *)"test-cli", NULL };
    assert_int_equal(sta_cli_parse(&cli, 1, only, &result, &error), STA_OK);
    assert_int_equal(result.positional_count, 0);
    assert_false(result.help);
}

static void help_wins_and_stores_nothing(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--gpu-mem", "20", "a", "--help"), STA_OK);
    assert_true(result.help);
    assert_int_equal(v.gpu_mem, 1024);
    assert_int_equal(PARSE("--gpu-mem", "1", "-h"), STA_OK); // help before checking values
    assert_true(result.help);
    assert_int_equal(PARSE("-qh"), STA_OK);
    assert_true(result.help);
    assert_false(v.quiet);
    // As a value or after "--" it is no option.
    assert_int_equal(PARSE("--out", "--help"), STA_OK);
    assert_false(result.help);
    assert_string_equal(v.out, "--help");
    assert_int_equal(PARSE("--", "-h"), STA_OK);
    assert_false(result.help);
    assert_int_equal(result.positional_count, 1);
}

static char *help_text(void)
{
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    assert_non_null(f);
    sta_cli_print_help(&cli, f);
    fclose(f);
    return text;
}

static void help_lists_each_option_with_range_and_default(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--flag"), STA_OK); // sets the defaults
    char *text = help_text();
    assert_true(strncmp(text, "usage: test-cli", 15) == 0);
    for (int i = 0; options[i].name; i++) {
        char name[64];
        snprintf(name, sizeof(name), "--%s", options[i].name);
        if (options[i].flags & STA_CLI_HIDDEN) {
            assert_null(strstr(text, name));
        } else {
            assert_non_null(strstr(text, name));
        }
    }
    const char *expected[] = {
        "\noptions:\n  --flag                 a flag\n",
        "  -q, --quiet            say less\n",
        "  --gpu-mem MIB          GPU memory (from 16 to 1048576; default: 1024)\n",
        "(from 1 to 1000; default: 5)",
        "  --count N              any count (default: 0)\n",
        "number of points (at least 1; suffix k, M or G;\n                         default: 30M)\n",
        "\nnumbers:\n  --threshold T",
        "(above 0 and at most 1e+06; default: 0.1)",
        "any finite number (default: the scene's own)",
        "  -o, --out FILE         output file\n",
        "what to draw (raw, hpr or fill; default: fill)",
        "sampling scheme (5, 9, 17 or 25; default: 9)",
        "  --size WxH             image size (default: 1280x720)\n",
        "  -h, --help             print this help and exit\n",
        "\nexit status: 0\n",
    };
    for (size_t i = 0; i < sizeof(expected) / sizeof(expected[0]); i++) {
        if (!strstr(text, expected[i])) {
            fail_msg("help lacks \"%s\" in:\n%s", expected[i], text);
        }
    }
    free(text);
}

static void help_wraps_long_lines(void **state)
{
    (void)state;
    const sta_cli_option table[] = {
        { .name = "a-rather-long-option-name",
          .kind = STA_CLI_STRING,
          .dest = &v.out,
          .metavar = "VALUE",
          .help = "words words words words words words words words words words words words "
                  "words words words words" },
        { .name = NULL },
    };
    const sta_cli c = { .program = "t", .options = table };
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    v.out = NULL;
    sta_cli_print_help(&c, f);
    fclose(f);
    // The option's names take a line of their own; the text wraps before column 80.
    assert_non_null(
        strstr(text, "  --a-rather-long-option-name VALUE\n                         words"));
    for (char *line = text; *line;) {
        size_t n = strcspn(line, "\n");
        assert_true(n < 80);
        line += n + (line[n] == '\n');
    }
    free(text);
}

static void callbacks_store_or_explain(void **state)
{
    (void)state;
    assert_int_equal(PARSE("--size", "640x480"), STA_OK);
    assert_int_equal(v.width, 640);
    assert_int_equal(v.height, 480);
    assert_int_equal(PARSE("--size=12"), STA_ERR_ARG);
    assert_string_equal(error.message, "--size needs WxH, got '12'");
    assert_int_equal(v.width, 1280);
    assert_int_equal(PARSE("--silent", "x"), STA_ERR_ARG);
    assert_string_equal(error.message, "--silent: cannot use 'x'");
    // A callback can read through a copy of its option with a built-in kind.
    sta_cli_option copy = options[2];
    int n = 0;
    copy.dest = &n;
    assert_int_equal(sta_cli_parse_value(&copy, "32", &error), STA_OK);
    assert_int_equal(n, 32);
    assert_int_equal(sta_cli_parse_value(&copy, "8", NULL), STA_ERR_ARG);
    assert_int_equal(n, 32);
}

static void parse_main_returns_exit_codes(void **state)
{
    (void)state;
    char *good[] = { (char *)"test-cli", (char *)"--flag", (char *)"f", NULL };
    assert_int_equal(sta_cli_parse_main(&cli, 3, good, &result), -1);
    assert_int_equal(result.positional_count, 1);
    char *bad[] = { (char *)"test-cli", (char *)"--gpu-mem", (char *)"1", NULL };
    assert_int_equal(sta_cli_parse_main(&cli, 3, bad, &result), 2);
    assert_int_equal(sta_cli_usage_error(&cli, "no %s given", "file"), 2);
}

static void allocation_failure_is_reported(void **state)
{
    (void)state;
    sta_alloc_fail_after(0);
    sta_status s = PARSE("--flag");
    sta_alloc_fail_after(-1);
    assert_int_equal(s, STA_ERR_NOMEM);
    sta_alloc_fail_after(1);
    s = PARSE("--flag");
    sta_alloc_fail_after(-1);
    assert_int_equal(s, STA_ERR_NOMEM);
    assert_false(v.flag);
    assert_int_equal(PARSE("--flag"), STA_OK);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(integers_keep_to_their_range),
    cmocka_unit_test(counts_refuse_overflow_and_negatives),
    cmocka_unit_test(doubles_refuse_nan_inf_and_open_bounds),
    cmocka_unit_test(choices_store_index_or_value),
    cmocka_unit_test(unknown_options_are_named),
    cmocka_unit_test(missing_and_unexpected_values_are_reported),
    cmocka_unit_test(positional_arguments_keep_their_order),
    cmocka_unit_test(help_wins_and_stores_nothing),
    cmocka_unit_test(help_lists_each_option_with_range_and_default),
    cmocka_unit_test(help_wraps_long_lines),
    cmocka_unit_test(callbacks_store_or_explain),
    cmocka_unit_test(parse_main_returns_exit_codes),
    cmocka_unit_test(allocation_failure_is_reported),
};

STA_TEST_MAIN(tests)
