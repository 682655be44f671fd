/* A test double of a full file system, loaded with LD_PRELOAD into a leanfade run: creating a
 * file (open or openat with O_CREAT, creat) anywhere under the absolute path in
 * LEANFADE_TEST_FULL_FOLDER fails with ENOSPC, as on a disk with no room for another file.
 * Reading and writing existing files is left alone. No privileges needed (a tmpfs mount
 * would need them). */
#undef _FORTIFY_SOURCE
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

/* Only names spelled under the folder's absolute path are matched: the tests give the cache
 * folder by its absolute path (XDG_CACHE_HOME), and leanfade names its entries from it. */
static int is_full(const char* path, int flags) {
    const char* folder = getenv("LEANFADE_TEST_FULL_FOLDER");
    if ((flags & O_CREAT) == 0 || folder == NULL || folder[0] != '/' || path == NULL) return 0;
    const size_t length = strlen(folder);
    return strncmp(path, folder, length) == 0 && (path[length] == '/' || path[length] == '\0');
}

static mode_t mode_of(int flags, va_list arguments) {
    return (flags & (O_CREAT | O_TMPFILE)) != 0 ? (mode_t)va_arg(arguments, int) : 0;
}

#define FORWARD_OPEN(name)                                           \
    int name(const char* path, int flags, ...) {                     \
        va_list arguments;                                           \
        va_start(arguments, flags);                                  \
        const mode_t mode = mode_of(flags, arguments);               \
        va_end(arguments);                                           \
        if (is_full(path, flags)) {                                  \
            errno = ENOSPC;                                          \
            return -1;                                               \
        }                                                            \
        int (*real)(const char*, int, ...) =                         \
            (int (*)(const char*, int, ...))dlsym(RTLD_NEXT, #name); \
        return real(path, flags, mode);                              \
    }

#define FORWARD_OPENAT(name)                                              \
    int name(int dirfd, const char* path, int flags, ...) {               \
        va_list arguments;                                                \
        va_start(arguments, flags);                                       \
        const mode_t mode = mode_of(flags, arguments);                    \
        va_end(arguments);                                                \
        if (is_full(path, flags)) {                                       \
            errno = ENOSPC;                                               \
            return -1;                                                    \
        }                                                                 \
        int (*real)(int, const char*, int, ...) =                         \
            (int (*)(int, const char*, int, ...))dlsym(RTLD_NEXT, #name); \
        return real(dirfd, path, flags, mode);                            \
    }

FORWARD_OPEN(open)
FORWARD_OPEN(open64)
FORWARD_OPENAT(openat)
FORWARD_OPENAT(openat64)

int creat(const char* path, mode_t mode) {
    return open(path, O_CREAT | O_WRONLY | O_TRUNC, mode);
}
int creat64(const char* path, mode_t mode) {
    return open(path, O_CREAT | O_WRONLY | O_TRUNC, mode);
}
