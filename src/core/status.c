/* SPDX-License-Identifier: MIT
 * Status codes and error messages. */
#include "core/status.h"

#include <stdio.h>
#include <string.h>

sta_status sta_vfail(sta_error *err, sta_status code, const char *fmt, va_list args)
{
    if (err) {
        err->code = code;
        vsnprintf(err->message, sizeof(err->message), fmt, args);
    }
    return code;
}

sta_status sta_fail(sta_error *err, sta_status code, const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    sta_vfail(err, code, fmt, args);
    va_end(args);
    return code;
}

sta_status sta_error_prefix(sta_error *err, const char *fmt, ...)
{
    if (!err || err->code == STA_OK) {
        return STA_ERR_ARG;
    }
    char prefix[STA_ERROR_MESSAGE_SIZE / 2];
    va_list args;
    va_start(args, fmt);
    vsnprintf(prefix, sizeof(prefix), fmt, args);
    va_end(args);
    // Build "prefix: message" piecewise; the result is cut at the buffer size.
    char joined[STA_ERROR_MESSAGE_SIZE];
    size_t used = strlen(prefix);
    memcpy(joined, prefix, used);
    const char separator[] = ": ";
    for (size_t i = 0; separator[i] && used + 1 < sizeof(joined); i++) {
        joined[used++] = separator[i];
    }
    size_t rest = strlen(err->message);
    if (rest > sizeof(joined) - 1 - used) {
        rest = sizeof(joined) - 1 - used;
    }
    memcpy(joined + used, err->message, rest);
    joined[used + rest] = '\0';
    memcpy(err->message, joined, sizeof(joined));
    return err->code;
}

const char *sta_status_str(sta_status code)
{
    switch (code) {
    case STA_OK:
        return "ok";
    case STA_ERR_ARG:
        return "invalid argument";
    case STA_ERR_NOMEM:
        return "out of memory";
    case STA_ERR_IO:
        return "i/o error";
    case STA_ERR_FORMAT:
        return "format error";
    case STA_ERR_UNSUPPORTED:
        return "unsupported";
    case STA_ERR_GL:
        return "graphics error";
    case STA_ERR_CANCELLED:
        return "cancelled";
    }
    return "unknown status";
}
