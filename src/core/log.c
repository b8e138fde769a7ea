/* SPDX-License-Identifier: MIT
 * Messages for people on stderr. */
#include "core/log.h"

#include <stdarg.h>
#include <stdio.h>
#include <unistd.h>

// Written once by main before threads start; read-only afterwards.
static sta_log_level current_level = STA_LOG_WARN;

void sta_log_set_level(sta_log_level level)
{
    current_level = level;
}

__attribute__((format(printf, 2, 0))) static void emit(const char *prefix, const char *fmt,
                                                       va_list args)
{
    char line[1024];
    vsnprintf(line, sizeof(line), fmt, args);
    fprintf(stderr, "%s%s\n", prefix, line);
}

void sta_log_warn(const char *fmt, ...)
{
    if (current_level < STA_LOG_WARN) {
        return;
    }
    va_list args;
    va_start(args, fmt);
    emit("warning: ", fmt, args);
    va_end(args);
}

void sta_log_info(const char *fmt, ...)
{
    if (current_level < STA_LOG_INFO) {
        return;
    }
    va_list args;
    va_start(args, fmt);
    emit("", fmt, args);
    va_end(args);
}

bool sta_log_is_terminal(void)
{
    return isatty(STDERR_FILENO) != 0;
}
