/* SPDX-License-Identifier: MIT
 * Status codes and error messages that travel with each call.
 *
 * Every action returns a sta_status and takes a `sta_error *err` last (may be NULL).
 * The message names the file, the field and the values involved, so a caller can
 * print it as it is. There is no shared last-error slot: threads cannot clobber it.
 */
#ifndef STA_CORE_STATUS_H
#define STA_CORE_STATUS_H

#include <stdarg.h>

typedef enum sta_status {
    STA_OK = 0,
    STA_ERR_ARG,         /* the caller passed something invalid */
    STA_ERR_NOMEM,       /* an allocation failed or a memory budget was exceeded */
    STA_ERR_IO,          /* the operating system refused a read, write or map */
    STA_ERR_FORMAT,      /* a file is broken, truncated or lies about itself */
    STA_ERR_UNSUPPORTED, /* a valid file uses something we do not (yet) read */
    STA_ERR_GL,          /* the OpenGL or EGL driver failed */
    STA_ERR_CANCELLED,   /* the user stopped the work */
} sta_status;

#define STA_ERROR_MESSAGE_SIZE 512

/* An error filled in by the call that failed. Zero-initialise before use. */
typedef struct sta_error {
    sta_status code;                      /* STA_OK until a call fails */
    char message[STA_ERROR_MESSAGE_SIZE]; /* NUL-terminated, human readable */
} sta_error;

/* Sets err (when not NULL) to `code` and the formatted message; returns `code`, so a
 * caller writes `return sta_fail(err, STA_ERR_FORMAT, "%s: ...", path, ...);`. */
sta_status sta_fail(sta_error *err, sta_status code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Like sta_fail but with a va_list. */
sta_status sta_vfail(sta_error *err, sta_status code, const char *fmt, va_list args)
    __attribute__((format(printf, 3, 0)));

/* Prefixes err's message with the formatted text and ": " (for adding context such as
 * a file name); returns err's code (STA_ERR_ARG when err is NULL or holds no error). */
sta_status sta_error_prefix(sta_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* A short constant name for the code ("format error", ...). Never NULL. */
const char *sta_status_str(sta_status code);

#endif
