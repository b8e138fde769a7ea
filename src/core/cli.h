/* SPDX-License-Identifier: MIT
 * Command lines from one table of options, on top of libc's getopt_long.
 *
 * A program declares a table: per option its long name, an optional short letter, the
 * kind of value, where the value goes, the accepted range or names, and help text.
 * sta_cli_parse fills the destinations, refuses a bad value with a message naming the
 * option, the value and what is accepted, and collects the positional arguments;
 * sta_cli_print_help writes --help's option list from the same table. A default is the
 * value the destination holds before parsing, so it is written once (where the program
 * initialises its settings) and help shows it from there.
 *
 * Command-line rules, the same for every program: options and positional arguments may
 * be mixed, positional arguments keep their order, "--" ends the options, "--name=value"
 * is "--name value" and "-o=value" is "-o value", short flags combine ("-qo x"), a
 * value may begin with '-' ("--look -5,0,0,0,0"), long names are spelled out in full
 * (getopt's abbreviations are refused, so a new option never changes an old command
 * line), an option given twice keeps the last value, and -h/--help is always there.
 *
 * Design: getopt_long keeps its state in globals (optind, optarg), so parsing is not
 * thread-safe: call it from main (or a test) before starting threads.
 */
#ifndef STA_CORE_CLI_H
#define STA_CORE_CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "core/status.h"

/* What an option's value is, and so what `dest` points to. */
typedef enum sta_cli_kind {
    STA_CLI_FLAG = 0, /* bool: set to true; the option takes no value */
    STA_CLI_INT,      /* int: a whole number in [int_min, int_max] */
    STA_CLI_COUNT,    /* uint64_t: an unsigned whole number in [count_min, count_max] */
    STA_CLI_DOUBLE,   /* double: a finite number in [real_min, real_max] (see flags) */
    STA_CLI_STRING,   /* const char *: the value itself, borrowed from argv */
    STA_CLI_CHOICE,   /* int: one of `choices`, stored as its index or choice_values[i] */
    STA_CLI_CALLBACK, /* anything: `parse` reads the value and stores it in dest */
} sta_cli_kind;

/* Option flags (sta_cli_option.flags). */
enum {
    STA_CLI_SUFFIX = 1u << 0,       /* COUNT: a k/K, M or G suffix multiplies by 10^3, 6, 9 */
    STA_CLI_ANY_NOTATION = 1u << 1, /* INT: also a whole number written as a real (1e3, 5.0) */
    STA_CLI_ABOVE_MIN = 1u << 2,    /* DOUBLE: real_min itself is refused (open lower bound) */
    STA_CLI_BELOW_MAX = 1u << 3,    /* DOUBLE: real_max itself is refused (open upper bound) */
    STA_CLI_HIDDEN = 1u << 4,       /* not listed in help (an alias such as --color) */
};

typedef struct sta_cli_option sta_cli_option;

/* Reads `value` for a STA_CLI_CALLBACK option and stores it through option->dest.
 * Returns STA_OK, or fails with a message naming the option and the value (see
 * sta_cli_fail_value); nothing is stored then. */
typedef sta_status (*sta_cli_parse_fn)(const sta_cli_option *option, const char *value,
                                       sta_error *err);

/* Writes the current value behind option->dest as help shows a default (NUL-terminated,
 * at most `size` bytes); writes "" when there is no default to show. */
typedef void (*sta_cli_show_fn)(const sta_cli_option *option, char *out_text, size_t size);

/* One option. Designated initializers; unused fields stay zero. */
struct sta_cli_option {
    const char *name;           /* long name without "--"; NULL ends the table */
    char short_name;            /* 'o' for -o, or 0; never 'h' (help) */
    sta_cli_kind kind;          /* what dest points to */
    void *dest;                 /* borrowed; its value before parsing is the default */
    const char *metavar;        /* the value in help and messages ("FILE.png"); NULL: "VALUE" */
    const char *help;           /* what it does; range, names and default are added */
    const char *heading;        /* help: a section title printed before this option, or NULL */
    int int_min, int_max;       /* INT range, inclusive; both 0: any int */
    uint64_t count_min;         /* COUNT range, inclusive; both 0: any uint64_t */
    uint64_t count_max;         /* (count_max >= count_min) */
    double real_min, real_max;  /* DOUBLE range (flags open it); both 0: any finite number */
    const char *const *choices; /* CHOICE: the accepted names, NULL-terminated */
    const int *choice_values;   /* CHOICE: the value stored per name; NULL: its index */
    sta_cli_parse_fn parse;     /* CALLBACK: reads the value */
    sta_cli_show_fn show;       /* CALLBACK: help's default from dest; NULL: none shown */
    const char *default_text;   /* help: the default in words ("all cores"); replaces the
                                   one read from dest */
    unsigned flags;             /* STA_CLI_* flags above */
};

/* A program's command line. */
typedef struct sta_cli {
    const char *program;           /* "strata-view": starts every message */
    const char *usage;             /* help before the options: "usage: ...\n\n...\n" */
    const char *epilog;            /* help after the options, or NULL */
    const char *hint;              /* a line printed after each usage error, or NULL */
    const sta_cli_option *options; /* the table, ended by an entry with name NULL */
} sta_cli;

/* What sta_cli_parse found besides the options. */
typedef struct sta_cli_result {
    bool help;            /* -h or --help: nothing was stored; show the help, exit 0 */
    int positional_count; /* positional arguments, in order, in positional[0 .. count) */
    char **positional;    /* argv + 1 (argv's pointers are reordered; strings untouched) */
} sta_cli_result;

/* Parses argv[1 .. argc) against cli's table: stores each option's value through its
 * dest (the last one wins when an option repeats) and moves the positional arguments to
 * the front, argv[1 .. out->positional_count]. When -h or --help is anywhere among the
 * options, nothing is stored and out->help is set. Fails with STA_ERR_ARG on an unknown
 * option, a missing or unexpected value, or a value out of range (the message names the
 * option, the value and what is accepted; options before it may have been stored), and
 * with STA_ERR_NOMEM. Not thread-safe (getopt_long). */
sta_status sta_cli_parse(const sta_cli *cli, int argc, char **argv, sta_cli_result *out,
                         sta_error *err);

/* Parses and reports, for main: returns -1 to go on, 0 after printing the help to stdout,
 * and 2 after printing "PROGRAM: message" (and cli->hint) to stderr. */
int sta_cli_parse_main(const sta_cli *cli, int argc, char **argv, sta_cli_result *out);

/* Reads `value` as `option` would on the command line and stores it through option->dest
 * (a callback can parse through a copy of its option with another kind and dest). */
sta_status sta_cli_parse_value(const sta_cli_option *option, const char *value, sta_error *err);

/* Fails with STA_ERR_ARG and "--NAME needs EXPECTED, got 'VALUE'", the style of every
 * value error; for callbacks. Returns STA_ERR_ARG. */
sta_status sta_cli_fail_value(sta_error *err, const sta_cli_option *option, const char *value,
                              const char *expected);

/* Prints "PROGRAM: message\n" and cli->hint to stderr; returns 2 (bad usage), for the
 * checks a program makes after parsing ("no scene given"). */
int sta_cli_usage_error(const sta_cli *cli, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* Writes the whole help: cli->usage, the option list (each option's names and metavar,
 * its help wrapped at 80 columns, then its range or names and its default read from
 * dest), -h/--help, and cli->epilog. */
void sta_cli_print_help(const sta_cli *cli, FILE *out);

#endif
