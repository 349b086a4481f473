/* The git commit the program was built from and whether its tree had uncommitted changes, fixed when the program
 * is compiled: the program never reads `.git` when it runs, so a run from another directory or after a checkout
 * still records the commit of its build. Called through iso_c_binding by supratrans_host.f90.
 *
 * fpm cannot run git (no build scripts), so the build command passes both as C macros:
 *     sh .ci/with_commit fpm build       (also: fpm test, fpm run)
 * sets FPM_CFLAGS="-DSUPRATRANS_COMMIT=<hex id> -DSUPRATRANS_DIRTY=<0|1>". The CMake build writes them into
 * supratrans_build_info.h at every build (cmake/supratrans_build_info.cmake) and defines
 * SUPRATRANS_HAVE_BUILD_INFO_H. Built without either (plain `fpm build`, a copy without .git), the commit is
 * empty and the dirty flag -1: the program then records "unknown (built without commit)". */
#include <string.h>

#ifdef SUPRATRANS_HAVE_BUILD_INFO_H
#include "supratrans_build_info.h"
#endif

/* The commit comes as a bare token (a double quote in FPM_CFLAGS makes fpm 0.12 stop silently), made a string
 * here; the Fortran side accepts only 40 or 64 hexadecimal digits. */
#define SUPRATRANS_STRING_(x) #x
#define SUPRATRANS_STRING(x) SUPRATRANS_STRING_(x)

#ifdef SUPRATRANS_COMMIT
static const char build_commit[] = SUPRATRANS_STRING(SUPRATRANS_COMMIT);
#else
static const char build_commit[] = "";
#endif

/* Copy the commit id of the build (empty if none was given) into `buffer` of `size` bytes, null-terminated. */
void supratrans_build_commit(char *buffer, int size)
{
    if (size <= 0) return;
    strncpy(buffer, build_commit, (size_t)size - 1);
    buffer[size - 1] = '\0';
}

/* 1 if the tree the program was built from had uncommitted changes, 0 if it was clean, -1 if not known. */
int supratrans_build_dirty(void)
{
#if defined(SUPRATRANS_COMMIT) && defined(SUPRATRANS_DIRTY)
    return (SUPRATRANS_DIRTY + 0) ? 1 : 0;
#else
    return -1;
#endif
}
