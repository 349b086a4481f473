/* The git commit the program was built from and whether its tree had uncommitted changes.
 *
 * Preferred: fixed when the program is compiled, so that a run from another directory or after a checkout still
 * records the commit of its build. fpm cannot run git (no build scripts), so the build command passes both as C
 * macros:
 *     sh .ci/with_commit fpm build       (also: fpm test, fpm run, fpm install)
 * sets FPM_CFLAGS="-DSUPRATRANS_COMMIT=<hex id> -DSUPRATRANS_DIRTY=<0|1>". The CMake build writes them into
 * supratrans_build_info.h at every build (cmake/supratrans_build_info.cmake) and defines
 * SUPRATRANS_HAVE_BUILD_INFO_H.
 *
 * Otherwise (plain `fpm build`, `fpm run`: the README's path) the commit is read when the program runs from the
 * `.git` of the source tree it was built from, with C stdio only (no shell, no git process): the tree is where
 * __FILE__ says this file is (fpm passes it relative to the project root, "././src/base/...", so the root is then
 * found as the nearest directory above the executable that holds this very file: fpm's build/<compiler>_<hash>/app/
 * lies inside the tree), `.git` there (a directory, or a file "gitdir: ..." of a worktree), its HEAD and the ref it
 * names (loose, or in packed-refs of the common directory). That commit is HEAD when the program runs, not
 * necessarily the build's: supratrans_host.f90 records it as read at run time, with whether HEAD (or its ref) moved
 * after the executable was written; the dirty flag is then not known (-1): telling it needs git's index and objects.
 * Called through iso_c_binding by supratrans_host.f90. */
#define _GNU_SOURCE
#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

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

/* ------------------------------------------------------------------------------------------------ at run time */

#define SUPRATRANS_PATH_MAX 4096

/* The first line of the file `path` (at most `size` - 1 bytes, without its newline) into `line`; 0 on success. */
static int first_line(const char *path, char *line, size_t size)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    int ok = fgets(line, (int)size, f) != NULL;
    fclose(f);
    if (!ok) return -1;
    size_t n = strcspn(line, "\r\n");
    line[n] = '\0';
    return 0;
}

/* Whether `text` is a git object id: 40 (SHA-1) or 64 (SHA-256) lower-case hexadecimal digits. */
static int is_object_id(const char *text)
{
    size_t n = strlen(text);
    if (n != 40 && n != 64) return 0;
    for (size_t i = 0; i < n; i++) {
        if (!isxdigit((unsigned char)text[i]) || isupper((unsigned char)text[i])) return 0;
    }
    return 1;
}

/* `dir`/`name` into `out` (`name` as is when absolute); 0 when it fits. */
static int join(char *out, size_t size, const char *dir, const char *name)
{
    int n = name[0] == '/' ? snprintf(out, size, "%s", name) : snprintf(out, size, "%s/%s", dir, name);
    return (n < 0 || (size_t)n >= size) ? -1 : 0;
}

/* Whether time `a` is later than time `b`. */
static int later(struct timespec a, struct timespec b)
{
    return a.tv_sec > b.tv_sec || (a.tv_sec == b.tv_sec && a.tv_nsec > b.tv_nsec);
}

/* The latest modification time of `path` into `*latest` (unchanged when it cannot be stat'ed). */
static void note_mtime(const char *path, struct timespec *latest)
{
    struct stat st;
    if (stat(path, &st) == 0 && later(st.st_mtim, *latest)) *latest = st.st_mtim;
}

/* The root of the source tree this file was compiled in, into `root`; 0 when found. */
static int source_root(char *root, size_t size)
{
    const char *file = __FILE__;
    const char *tail = "src/base/supratrans_build_info.c";
    size_t nf = strlen(file), nt = strlen(tail);
    struct stat st;
    if (file[0] == '/') {
        /* an absolute path (CMake, or fpm given one): the root is what precedes src/base/... */
        if (nf <= nt || strcmp(file + nf - nt, tail) != 0 || nf - nt >= size) return -1;
        memcpy(root, file, nf - nt);
        root[nf - nt] = '\0';
        while (strlen(root) > 1 && root[strlen(root) - 1] == '/') root[strlen(root) - 1] = '\0';
        return stat(file, &st) == 0 && S_ISREG(st.st_mode) ? 0 : -1;
    }
    /* relative to the directory fpm compiled in, the project root: find the directory above the executable that
     * holds this file under that relative name */
    while (strncmp(file, "./", 2) == 0) file += 2;
    char exe[SUPRATRANS_PATH_MAX], probe[SUPRATRANS_PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) return -1;
    exe[n] = '\0';
    for (;;) {
        char *slash = strrchr(exe, '/');
        if (!slash) return -1;
        *slash = '\0';
        const char *dir = slash == exe ? "/" : exe;
        if (join(probe, sizeof probe, dir, file) == 0 && stat(probe, &st) == 0 && S_ISREG(st.st_mode)) {
            if (strlen(dir) >= size) return -1;
            strcpy(root, dir);
            return 0;
        }
        if (slash == exe) return -1;
    }
}

/* The commit HEAD names in the git repository of the source tree this program was built from, read now: into
 * `commit` (`csize` bytes) the object id, into `gitdir` (`gsize` bytes) the repository's `.git` as found. Returns
 * 0 when HEAD is older than the executable, 1 when HEAD or the ref it names was written after it (the program may
 * be of an earlier commit), -1 when there is no commit to read (no tree found, no .git, an unborn branch). */
int supratrans_runtime_commit(char *commit, int csize, char *gitdir, int gsize)
{
    char root[SUPRATRANS_PATH_MAX], dotgit[SUPRATRANS_PATH_MAX], git[SUPRATRANS_PATH_MAX];
    char common[SUPRATRANS_PATH_MAX], path[SUPRATRANS_PATH_MAX], line[SUPRATRANS_PATH_MAX];
    struct stat st;
    struct timespec written = {0, 0};

    if (csize <= 0 || gsize <= 0) return -1;
    commit[0] = '\0';
    gitdir[0] = '\0';
    if (source_root(root, sizeof root) != 0) return -1;
    if (join(dotgit, sizeof dotgit, root, ".git") != 0 || stat(dotgit, &st) != 0) return -1;
    if (S_ISDIR(st.st_mode)) {
        strcpy(git, dotgit);
    } else if (S_ISREG(st.st_mode)) {
        /* a worktree or submodule: "gitdir: <path>", relative to the tree's root unless absolute */
        if (first_line(dotgit, line, sizeof line) != 0 || strncmp(line, "gitdir: ", 8) != 0) return -1;
        if (join(git, sizeof git, root, line + 8) != 0) return -1;
    } else {
        return -1;
    }
    /* the refs of a worktree live in the common directory named by `commondir` (relative to the git directory) */
    strcpy(common, git);
    if (join(path, sizeof path, git, "commondir") == 0 && first_line(path, line, sizeof line) == 0 && line[0]) {
        if (join(common, sizeof common, git, line) != 0) return -1;
    }
    if (join(path, sizeof path, git, "HEAD") != 0 || first_line(path, line, sizeof line) != 0) return -1;
    note_mtime(path, &written);
    if (strncmp(line, "ref: ", 5) == 0) {
        char ref[SUPRATRANS_PATH_MAX], id[SUPRATRANS_PATH_MAX];
        snprintf(ref, sizeof ref, "%s", line + 5);
        if (strstr(ref, "..") || ref[0] == '/') return -1;
        id[0] = '\0';
        /* a loose ref: in the git directory (per-worktree refs), then in the common one */
        if (join(path, sizeof path, git, ref) == 0 && first_line(path, id, sizeof id) == 0) {
            note_mtime(path, &written);
        } else if (join(path, sizeof path, common, ref) == 0 && first_line(path, id, sizeof id) == 0) {
            note_mtime(path, &written);
        } else if (join(path, sizeof path, common, "packed-refs") == 0) {
            /* packed-refs: "<id> <refname>" lines, '#' a comment, '^' the peeled object of the tag above */
            FILE *f = fopen(path, "r");
            if (f) {
                while (fgets(line, sizeof line, f)) {
                    line[strcspn(line, "\r\n")] = '\0';
                    char *space = strchr(line, ' ');
                    if (line[0] == '#' || line[0] == '^' || !space) continue;
                    *space = '\0';
                    if (strcmp(space + 1, ref) == 0) {
                        snprintf(id, sizeof id, "%s", line);
                        note_mtime(path, &written);
                        break;
                    }
                }
                fclose(f);
            }
        }
        snprintf(line, sizeof line, "%s", id);
    }
    if (!is_object_id(line) || (int)strlen(line) >= csize || (int)strlen(git) >= gsize) return -1;
    strcpy(commit, line);
    strcpy(gitdir, git);
    {
        char exe[SUPRATRANS_PATH_MAX];
        ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
        if (n <= 0) return 1;
        exe[n] = '\0';
        if (stat(exe, &st) != 0) return 1;
        return later(written, st.st_mtim) ? 1 : 0;
    }
}
