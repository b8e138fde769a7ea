/* SPDX-License-Identifier: MIT
 * Messages for people: warnings and progress on stderr.
 */
#ifndef STA_CORE_LOG_H
#define STA_CORE_LOG_H

#include <stdbool.h>

typedef enum sta_log_level {
    STA_LOG_QUIET = 0, /* errors only (errors are printed by *_main.c, not here) */
    STA_LOG_WARN,      /* default: warnings */
    STA_LOG_INFO,      /* --verbose */
} sta_log_level;

/* Sets the process-wide level; call once from main before starting threads. */
void sta_log_set_level(sta_log_level level);

/* Prints "warning: <message>\n" to stderr unless quiet. Thread-safe (one fprintf). */
void sta_log_warn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Prints "<message>\n" to stderr at INFO level. Thread-safe. */
void sta_log_info(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* True when stderr is a terminal (progress lines are drawn only then). */
bool sta_log_is_terminal(void);

#endif
