/* SPDX-License-Identifier: MIT
 * Command lines from one table of options, on top of libc's getopt_long (see cli.h).
 *
 * Design: the table becomes getopt_long's long options (value LONG_VAL_BASE + index) and
 * short option string ("-:" first: positional arguments come back in order as code 1, and
 * a missing value as ':'). argv is scanned twice: once for -h/--help only (so help shows
 * the defaults untouched and wins wherever it stands), then to store the values.
 */
#include "core/cli.h"

#include <ctype.h>
#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

enum {
    LONG_VAL_BASE = 0x1000, /* getopt_long's value for table entry i: LONG_VAL_BASE + i */
    HELP_VAL = 0x0fff,      /* getopt_long's value for --help */
    NOT_SPELLED_OUT = -2,   /* next_option: an abbreviated long name */
    HELP_COLUMN = 25,       /* help text starts in this column (0-based) */
    HELP_WIDTH = 80,        /* help lines end before this column */
    TEXT_SIZE = 1024,       /* one option's help line, before wrapping */
};

typedef struct scan {
    const sta_cli *cli;
    int argc;
    char **argv;
    struct option *longs; /* the table, --help, a zero entry */
    char *shorts;         /* "-:", each short letter (':' when it takes a value), "h" */
    int element;          /* argv index of the element holding the last option */
} scan;

static int option_count(const sta_cli *cli)
{
    int n = 0;
    while (cli->options && cli->options[n].name) {
        n++;
    }
    return n;
}

static bool takes_value(const sta_cli_option *o)
{
    return o->kind != STA_CLI_FLAG;
}

static sta_status scan_init(scan *s, const sta_cli *cli, int argc, char **argv, sta_error *err)
{
    memset(s, 0, sizeof(*s));
    s->cli = cli;
    s->argc = argc;
    s->argv = argv;
    int n = option_count(cli);
    s->longs = sta_alloc_array((size_t)n + 2, sizeof(*s->longs));
    s->shorts = sta_alloc_array((size_t)n * 2 + 4, 1);
    if (!s->longs || !s->shorts) {
        sta_free(s->longs);
        sta_free(s->shorts);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %d options", n);
    }
    char *p = s->shorts;
    *p++ = '-';
    *p++ = ':';
    for (int i = 0; i < n; i++) {
        const sta_cli_option *o = &cli->options[i];
        s->longs[i] = (struct option){ o->name, takes_value(o) ? required_argument : no_argument,
                                       NULL, LONG_VAL_BASE + i };
        if (o->short_name) {
            *p++ = o->short_name;
            if (takes_value(o)) {
                *p++ = ':';
            }
        }
    }
    s->longs[n] = (struct option){ "help", no_argument, NULL, HELP_VAL };
    s->longs[n + 1] = (struct option){ NULL, 0, NULL, 0 };
    *p++ = 'h';
    *p = '\0';
    return STA_OK;
}

static void scan_release(scan *s)
{
    sta_free(s->longs);
    sta_free(s->shorts);
    memset(s, 0, sizeof(*s));
}

static const char *long_name(const scan *s, int val)
{
    if (val == HELP_VAL) {
        return "help";
    }
    return val >= LONG_VAL_BASE ? s->cli->options[val - LONG_VAL_BASE].name : NULL;
}

// True when `element` is "--NAME" or "--NAME=...", not an abbreviation of NAME.
static bool is_spelled_out(const char *element, const char *name)
{
    size_t n = strlen(name);
    return strncmp(element, "--", 2) == 0 && strncmp(element + 2, name, n) == 0 &&
           (element[2 + n] == '\0' || element[2 + n] == '=');
}

// getopt_long's next code, or NOT_SPELLED_OUT when a long name was abbreviated.
static int next_option(scan *s)
{
    s->element = optind == 0 ? 1 : optind; // optind 0: getopt starts at argv[1]
    int c = getopt_long(s->argc, s->argv, s->shorts, s->longs, NULL);
    int val = c == '?' || c == ':' ? optopt : c;
    const char *name = long_name(s, val);
    if (name && s->element < s->argc && strncmp(s->argv[s->element], "--", 2) == 0 &&
        !is_spelled_out(s->argv[s->element], name)) {
        return NOT_SPELLED_OUT;
    }
    return c;
}

static int short_index(const sta_cli *cli, int letter)
{
    for (int i = 0; cli->options[i].name; i++) {
        if (cli->options[i].short_name == letter) {
            return i;
        }
    }
    return -1;
}

// The option's value: optarg, without the '=' of "-o=value".
static const char *option_value(const scan *s, bool is_short)
{
    const char *v = optarg;
    bool separate = s->element + 1 < s->argc && v == s->argv[s->element + 1];
    if (is_short && v && !separate && v[0] == '=') {
        v++;
    }
    return v;
}

static sta_status fail_unknown(const scan *s, int c, sta_error *err)
{
    const char *see = s->cli->hint ? "" : " (see --help)";
    if (c == '?' && optopt > 0 && optopt < HELP_VAL) {
        return sta_fail(err, STA_ERR_ARG, "unknown option -%c%s", optopt, see);
    }
    if (c == '?' && long_name(s, optopt)) {
        return sta_fail(err, STA_ERR_ARG, "--%s takes no value, got '%s'", long_name(s, optopt),
                        s->argv[s->element]);
    }
    const char *e = s->element < s->argc ? s->argv[s->element] : "";
    const char *eq = strchr(e, '=');
    int n = eq ? (int)(eq - e) : (int)strlen(e);
    return sta_fail(err, STA_ERR_ARG, "unknown option %.*s%s", n, e, see);
}

static sta_status fail_missing(const scan *s, sta_error *err)
{
    const sta_cli_option *o = NULL;
    char spelled[8] = "";
    if (optopt >= LONG_VAL_BASE) {
        o = &s->cli->options[optopt - LONG_VAL_BASE];
    } else if (optopt > 0 && short_index(s->cli, optopt) >= 0) {
        o = &s->cli->options[short_index(s->cli, optopt)];
        snprintf(spelled, sizeof(spelled), "-%c", optopt);
    }
    if (!o) {
        return sta_fail(err, STA_ERR_ARG, "an option needs a value");
    }
    const char *metavar = o->metavar ? o->metavar : "VALUE";
    if (spelled[0]) {
        return sta_fail(err, STA_ERR_ARG, "%s needs a value (%s)", spelled, metavar);
    }
    return sta_fail(err, STA_ERR_ARG, "--%s needs a value (%s)", o->name, metavar);
}

// One pass over argv. Without `store` it only looks for -h/--help.
static sta_status scan_argv(scan *s, bool store, sta_cli_result *out, sta_error *err)
{
    optind = 0; // glibc: 0 starts a new scan (and reads the option string afresh)
    opterr = 0;
    int count = 0;
    for (;;) {
        int c = next_option(s);
        if (c == -1) {
            break;
        }
        if (c == 'h' || c == HELP_VAL) {
            out->help = true;
            return STA_OK;
        }
        if (!store) {
            continue;
        }
        if (c == 1) {
            s->argv[1 + count++] = optarg; // never ahead of the element getopt is reading
        } else if (c == '?' || c == NOT_SPELLED_OUT) {
            return fail_unknown(s, c, err);
        } else if (c == ':') {
            return fail_missing(s, err);
        } else {
            bool is_short = c < LONG_VAL_BASE;
            int i = is_short ? short_index(s->cli, c) : c - LONG_VAL_BASE;
            sta_status status =
                sta_cli_parse_value(&s->cli->options[i], option_value(s, is_short), err);
            if (status != STA_OK) {
                return status;
            }
        }
    }
    // After "--" getopt stops; the rest is positional.
    while (store && optind < s->argc) {
        s->argv[1 + count++] = s->argv[optind++];
    }
    out->positional_count = count;
    return STA_OK;
}

sta_status sta_cli_parse(const sta_cli *cli, int argc, char **argv, sta_cli_result *out,
                         sta_error *err)
{
    memset(out, 0, sizeof(*out));
    out->positional = argc > 0 ? argv + 1 : argv;
    if (argc < 2) {
        return STA_OK;
    }
    scan s;
    sta_status status = scan_init(&s, cli, argc, argv, err);
    if (status != STA_OK) {
        return status;
    }
    status = scan_argv(&s, false, out, err);
    if (status == STA_OK && !out->help) {
        status = scan_argv(&s, true, out, err);
    }
    scan_release(&s);
    return status;
}

int sta_cli_parse_main(const sta_cli *cli, int argc, char **argv, sta_cli_result *out)
{
    sta_error err = { 0 };
    sta_status status = sta_cli_parse(cli, argc, argv, out, &err);
    if (status != STA_OK) {
        return sta_cli_usage_error(cli, "%s", err.message);
    }
    if (out->help) {
        sta_cli_print_help(cli, stdout);
        return 0;
    }
    return -1;
}

int sta_cli_usage_error(const sta_cli *cli, const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    fprintf(stderr, "%s: ", cli->program);
    vfprintf(stderr, fmt, args);
    fputc('\n', stderr);
    if (cli->hint) {
        fprintf(stderr, "%s\n", cli->hint);
    }
    va_end(args);
    return 2;
}

sta_status sta_cli_fail_value(sta_error *err, const sta_cli_option *option, const char *value,
                              const char *expected)
{
    return sta_fail(err, STA_ERR_ARG, "--%s needs %s, got '%s'", option->name, expected,
                    value ? value : "");
}

/* Ranges and names as text (shared by messages and help) */

static void int_range(const sta_cli_option *o, int *lo, int *hi)
{
    bool any = o->int_min == 0 && o->int_max == 0;
    *lo = any ? INT_MIN : o->int_min;
    *hi = any ? INT_MAX : o->int_max;
}

static void count_range(const sta_cli_option *o, uint64_t *lo, uint64_t *hi)
{
    bool any = o->count_min == 0 && o->count_max == 0;
    *lo = any ? 0 : o->count_min;
    *hi = any ? UINT64_MAX : o->count_max;
}

static void real_range(const sta_cli_option *o, double *lo, double *hi)
{
    bool any = o->real_min == 0.0 && o->real_max == 0.0;
    *lo = any ? -HUGE_VAL : o->real_min;
    *hi = any ? HUGE_VAL : o->real_max;
}

static bool real_in_range(const sta_cli_option *o, double v)
{
    double lo, hi;
    real_range(o, &lo, &hi);
    bool above = (o->flags & STA_CLI_ABOVE_MIN) ? v > lo : v >= lo;
    bool below = (o->flags & STA_CLI_BELOW_MAX) ? v < hi : v <= hi;
    return isfinite(v) && above && below;
}

// "from 16 to 1048576", "of at least 1", ... ; "" when any value of the type goes.
static void range_text(const sta_cli_option *o, bool in_help, char *out, size_t size)
{
    out[0] = '\0';
    if (o->kind == STA_CLI_INT) {
        int lo, hi;
        int_range(o, &lo, &hi);
        if (lo != INT_MIN || hi != INT_MAX) {
            snprintf(out, size, "from %d to %d", lo, hi);
        }
    } else if (o->kind == STA_CLI_COUNT) {
        uint64_t lo, hi;
        count_range(o, &lo, &hi);
        if (hi == UINT64_MAX && lo > 0) {
            snprintf(out, size, "%s%" PRIu64, in_help ? "at least " : "of at least ", lo);
        } else if (!in_help || lo > 0 || hi < UINT64_MAX) {
            snprintf(out, size, "from %" PRIu64 " to %" PRIu64, lo, hi);
        }
    } else if (o->kind == STA_CLI_DOUBLE) {
        double lo, hi;
        real_range(o, &lo, &hi);
        bool open_lo = o->flags & STA_CLI_ABOVE_MIN, open_hi = o->flags & STA_CLI_BELOW_MAX;
        char lower[64] = "", upper[64] = "";
        if (isfinite(lo)) {
            snprintf(lower, sizeof(lower), "%s %g", open_lo ? "above" : "at least", lo);
        }
        if (isfinite(hi)) {
            snprintf(upper, sizeof(upper), "%s %g", open_hi ? "below" : "at most", hi);
        }
        if (lower[0] && upper[0] && !open_lo && !open_hi) {
            snprintf(out, size, "from %g to %g", lo, hi);
        } else {
            snprintf(out, size, "%s%s%s", lower, lower[0] && upper[0] ? " and " : "", upper);
        }
    }
}

// "a, b or c" from a NULL-terminated list.
static void choice_text(const sta_cli_option *o, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; o->choices && o->choices[i] && used < size; i++) {
        const char *sep = i == 0 ? "" : o->choices[i + 1] ? ", " : " or ";
        int n = snprintf(out + used, size - used, "%s%s", sep, o->choices[i]);
        used += n > 0 ? (size_t)n : 0;
    }
}

/* Reading values */

static sta_status fail_number(const sta_cli_option *o, const char *value, const char *what,
                              sta_error *err)
{
    char range[128], expected[256];
    range_text(o, false, range, sizeof(range));
    bool suffix = o->kind == STA_CLI_COUNT && (o->flags & STA_CLI_SUFFIX);
    snprintf(expected, sizeof(expected), "%s%s%s%s", what, range[0] ? " " : "", range,
             suffix ? " (suffix k, M or G allowed)" : "");
    return sta_cli_fail_value(err, o, value, expected);
}

static sta_status read_int(const sta_cli_option *o, const char *text, sta_error *err)
{
    int lo, hi;
    int_range(o, &lo, &hi);
    char *end = NULL;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    bool ok = end != text && *end == '\0' && errno == 0;
    if (!ok && (o->flags & STA_CLI_ANY_NOTATION)) {
        double d = strtod(text, &end);
        // NaN fails every comparison; the range check keeps the cast defined.
        ok = end != text && *end == '\0' && d == floor(d) && d >= lo && d <= hi;
        v = ok ? (long long)d : 0;
    }
    if (!ok || v < lo || v > hi) {
        return fail_number(o, text, "a whole number", err);
    }
    *(int *)o->dest = (int)v;
    return STA_OK;
}

static sta_status read_count(const sta_cli_option *o, const char *text, sta_error *err)
{
    uint64_t lo, hi;
    count_range(o, &lo, &hi);
    const char *p = text;
    while (isspace((unsigned char)*p)) {
        p++;
    }
    char *end = NULL;
    errno = 0;
    unsigned long long v = *p != '-' ? strtoull(p, &end, 10) : 0;
    bool ok = end && end != p && errno == 0; // ERANGE: more than 2^64 - 1
    uint64_t factor = 1;
    if (ok && (o->flags & STA_CLI_SUFFIX)) {
        factor = *end == 'k' || *end == 'K' ? 1000u
                 : *end == 'M'              ? 1000000u
                 : *end == 'G'              ? 1000000000u
                                            : 1u;
        end += factor > 1;
    }
    ok = ok && *end == '\0' && (v == 0 || factor <= UINT64_MAX / v);
    if (!ok || v * factor < lo || v * factor > hi) {
        return fail_number(o, text, "a whole number", err);
    }
    *(uint64_t *)o->dest = (uint64_t)v * factor;
    return STA_OK;
}

static sta_status read_double(const sta_cli_option *o, const char *text, sta_error *err)
{
    char *end = NULL;
    double v = strtod(text, &end); // underflow gives 0 or a subnormal: range-checked below
    if (end == text || *end != '\0' || !real_in_range(o, v)) {
        double lo, hi;
        real_range(o, &lo, &hi);
        bool any = !isfinite(lo) && !isfinite(hi);
        return fail_number(o, text, any ? "a finite number" : "a number", err);
    }
    *(double *)o->dest = v;
    return STA_OK;
}

static sta_status read_choice(const sta_cli_option *o, const char *text, sta_error *err)
{
    for (int i = 0; o->choices && o->choices[i]; i++) {
        if (strcmp(text, o->choices[i]) == 0) {
            *(int *)o->dest = o->choice_values ? o->choice_values[i] : i;
            return STA_OK;
        }
    }
    char names[512];
    choice_text(o, names, sizeof(names));
    return sta_fail(err, STA_ERR_ARG, "--%s takes %s, got '%s'", o->name, names, text);
}

sta_status sta_cli_parse_value(const sta_cli_option *option, const char *value, sta_error *err)
{
    if (option->kind != STA_CLI_FLAG && !value) {
        return sta_fail(err, STA_ERR_ARG, "--%s needs a value", option->name);
    }
    switch (option->kind) {
    case STA_CLI_FLAG:
        *(bool *)option->dest = true;
        return STA_OK;
    case STA_CLI_INT:
        return read_int(option, value, err);
    case STA_CLI_COUNT:
        return read_count(option, value, err);
    case STA_CLI_DOUBLE:
        return read_double(option, value, err);
    case STA_CLI_STRING:
        *(const char **)option->dest = value;
        return STA_OK;
    case STA_CLI_CHOICE:
        return read_choice(option, value, err);
    case STA_CLI_CALLBACK:
        break;
    }
    sta_error e = { 0 };
    sta_status status =
        option->parse ? option->parse(option, value, &e) : sta_fail(&e, STA_ERR_ARG, "no parser");
    if (status != STA_OK && !e.message[0]) {
        sta_fail(&e, status, "--%s: cannot use '%s'", option->name, value);
    }
    if (status != STA_OK && err) {
        *err = e;
    }
    return status;
}

/* Help */

// The default help shows: from default_text, or read from dest when it is a valid value.
static void default_text(const sta_cli_option *o, char *out, size_t size)
{
    out[0] = '\0';
    if (o->default_text) {
        snprintf(out, size, "%s", o->default_text);
        return;
    }
    switch (o->kind) {
    case STA_CLI_FLAG:
        break;
    case STA_CLI_INT: {
        int lo, hi, v = *(const int *)o->dest;
        int_range(o, &lo, &hi);
        if (v >= lo && v <= hi) {
            snprintf(out, size, "%d", v);
        }
        break;
    }
    case STA_CLI_COUNT: {
        uint64_t lo, hi, v = *(const uint64_t *)o->dest;
        count_range(o, &lo, &hi);
        static const char suffixes[] = { 'G', 'M', 'k' };
        static const uint64_t factors[] = { 1000000000u, 1000000u, 1000u };
        for (int i = 0; i < 3 && (o->flags & STA_CLI_SUFFIX) && v; i++) {
            if (v % factors[i] == 0) {
                snprintf(out, size, "%" PRIu64 "%c", v / factors[i], suffixes[i]);
                break;
            }
        }
        if (!out[0]) {
            snprintf(out, size, "%" PRIu64, v);
        }
        if (v < lo || v > hi) {
            out[0] = '\0';
        }
        break;
    }
    case STA_CLI_DOUBLE: {
        double v = *(const double *)o->dest;
        if (real_in_range(o, v)) {
            snprintf(out, size, "%g", v);
        }
        break;
    }
    case STA_CLI_STRING: {
        const char *v = *(const char *const *)o->dest;
        snprintf(out, size, "%s", v ? v : "");
        break;
    }
    case STA_CLI_CHOICE: {
        int v = *(const int *)o->dest;
        for (int i = 0; o->choices && o->choices[i]; i++) {
            if ((o->choice_values ? o->choice_values[i] : i) == v) {
                snprintf(out, size, "%s", o->choices[i]);
            }
        }
        break;
    }
    case STA_CLI_CALLBACK:
        if (o->show) {
            o->show(o, out, size);
        }
        break;
    }
}

// Writes `text` from column `col`, wrapping at HELP_WIDTH to column HELP_COLUMN; '\n'
// in text starts a new line.
static void print_wrapped(FILE *out, const char *text, int col)
{
    const char *p = text;
    bool line_start = true;
    while (*p) {
        if (*p == '\n') {
            fprintf(out, "\n%*s", HELP_COLUMN, "");
            col = HELP_COLUMN;
            line_start = true;
            p++;
            continue;
        }
        if (*p == ' ') {
            p++;
            continue;
        }
        int n = (int)strcspn(p, " \n");
        if (!line_start && col + 1 + n > HELP_WIDTH) {
            fprintf(out, "\n%*s", HELP_COLUMN, "");
            col = HELP_COLUMN;
            line_start = true;
        }
        if (!line_start) {
            fputc(' ', out);
            col++;
        }
        fprintf(out, "%.*s", n, p);
        col += n;
        line_start = false;
        p += n;
    }
    fputc('\n', out);
}

static void print_entry(FILE *out, char short_name, const char *name, const char *metavar,
                        const char *text)
{
    char left[128], letter[8] = "";
    if (short_name) {
        snprintf(letter, sizeof(letter), "-%c, ", short_name);
    }
    snprintf(left, sizeof(left), "  %s--%s%s%s", letter, name, metavar ? " " : "",
             metavar ? metavar : "");
    int n = (int)strlen(left);
    fputs(left, out);
    if (n > HELP_COLUMN - 2) {
        fprintf(out, "\n%*s", HELP_COLUMN, "");
    } else {
        fprintf(out, "%*s", HELP_COLUMN - n, "");
    }
    print_wrapped(out, text, HELP_COLUMN);
}

static void print_option(FILE *out, const sta_cli_option *o)
{
    char range[128], names[512], def[256], text[TEXT_SIZE];
    range_text(o, true, range, sizeof(range));
    names[0] = '\0';
    if (o->kind == STA_CLI_CHOICE) {
        choice_text(o, names, sizeof(names));
    }
    default_text(o, def, sizeof(def));
    bool suffix = o->kind == STA_CLI_COUNT && (o->flags & STA_CLI_SUFFIX);
    // The details in brackets: range or names, suffixes, default; "; " between them.
    const char *parts[4] = { range[0] ? range : NULL, names[0] ? names : NULL,
                             suffix ? "suffix k, M or G" : NULL, NULL };
    char defpart[300];
    if (def[0]) {
        snprintf(defpart, sizeof(defpart), "default: %s", def);
        parts[3] = defpart;
    }
    size_t used = (size_t)snprintf(text, sizeof(text), "%s", o->help ? o->help : "");
    bool open = false;
    for (int i = 0; i < 4 && used < sizeof(text); i++) {
        if (!parts[i]) {
            continue;
        }
        int n = snprintf(text + used, sizeof(text) - used, "%s%s", open ? "; " : " (", parts[i]);
        used += n > 0 ? (size_t)n : 0;
        open = true;
    }
    if (open && used < sizeof(text)) {
        snprintf(text + used, sizeof(text) - used, ")");
    }
    const char *metavar = takes_value(o) ? (o->metavar ? o->metavar : "VALUE") : NULL;
    print_entry(out, o->short_name, o->name, metavar, text);
}

void sta_cli_print_help(const sta_cli *cli, FILE *out)
{
    if (cli->usage) {
        fputs(cli->usage, out);
    }
    bool first = true;
    for (int i = 0; cli->options && cli->options[i].name; i++) {
        const sta_cli_option *o = &cli->options[i];
        if (o->flags & STA_CLI_HIDDEN) {
            continue;
        }
        if (o->heading || first) {
            fprintf(out, "\n%s\n", o->heading ? o->heading : "options:");
        }
        first = false;
        print_option(out, o);
    }
    if (first) {
        fputs("\noptions:\n", out);
    }
    print_entry(out, 'h', "help", NULL, "print this help and exit");
    if (cli->epilog) {
        fprintf(out, "\n%s", cli->epilog);
    }
}
