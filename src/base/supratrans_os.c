/* Operating-system calls that Fortran cannot make portably by itself: the kind of a path (stat, lstat), an advisory
 * lock (flock), a flag set by SIGTERM/SIGINT/SIGUSR1, the same-file test, checked writes, files created exclusively
 * under unique names and memory limits. Called through iso_c_binding by supratrans_system.f90; nothing here runs a
 * shell.
 *
 * Files on a shared machine: every file this program creates is created with O_CREAT | O_EXCL | O_NOFOLLOW under a
 * name nobody can guess (`<final>.tmp-XXXXXX`, six random letters or digits, retried when taken), written, fsync'ed
 * and renamed onto its final name, so that a symbolic link or any other file planted by another user under a
 * predictable name is never opened for writing; an existing path is never opened for writing by name except the
 * journal appended to (O_NOFOLLOW, regular files only) and the lock file (O_NOFOLLOW, never truncated; removed by
 * its holder only, while held). */
#define _GNU_SOURCE
#include <dirent.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

/* The mode every file of supratrans is created with (reduced further by the umask): rw-r--r--, never writable by
 * group or others whatever the umask allows, so that a file found under one of its names that someone else can
 * write is not one it wrote (see supratrans_own_file). */
#define FILE_MODE 0644

/* Whether `path` is a file this program may trust and delete as its own (lstat: a link is not followed): 0 nothing
 * there, 1 a regular file owned by this user (effective uid) and writable by nobody else (no group or other write
 * bit), 2 not a regular file (a symbolic link, FIFO, device, socket or directory), 3 another user's file (`*uid`
 * its owner), 4 this user's file but writable by group or others (`*mode` its permission bits). A checksum finds
 * damage, not forgery: a journal, snapshot or checkpoint someone else wrote or could have written is never resumed
 * from nor deleted. */
int supratrans_own_file(const char *path, long long *uid, int *mode)
{
    struct stat st;
    *uid = -1;
    *mode = 0;
    if (lstat(path, &st) != 0) return 0;
    *uid = (long long)st.st_uid;
    *mode = (int)(st.st_mode & 07777);
    if (!S_ISREG(st.st_mode)) return 2;
    if (st.st_uid != geteuid()) return 3;
    if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) return 4;
    return 1;
}

/* The first entry of directory `dir` named `prefix` or `prefix-<digits>` (a checkpoint: `<out>.checkpoint`,
 * `<out>.checkpoint-<task>`) that is not this user's own file (supratrans_own_file), its name into `buf` (`size`
 * bytes). Returns that file's code (2, 3 or 4), 0 if every such entry is this user's own. */
int supratrans_foreign_entry(const char *dir, const char *prefix, char *buf, int size)
{
    DIR *d = opendir(dir);
    if (d == NULL) return 0;
    size_t np = strlen(prefix);
    int found = 0;
    struct dirent *entry;
    while (found == 0 && (entry = readdir(d)) != NULL) {
        const char *name = entry->d_name;
        if (strncmp(name, prefix, np) != 0) continue;
        const char *rest = name + np;
        if (*rest != '\0') {
            if (rest[0] != '-' || rest[1] == '\0' || strspn(rest + 1, "0123456789") != strlen(rest + 1)) continue;
        }
        struct stat st;
        if (fstatat(dirfd(d), name, &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
        if (!S_ISREG(st.st_mode)) found = 2;
        else if (st.st_uid != geteuid()) found = 3;
        else if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) found = 4;
        if (found != 0) snprintf(buf, (size_t)size, "%s", name);
    }
    closedir(d);
    return found;
}

/* Kind of a path: 0 missing, 1 regular file, 2 directory, 3 other (FIFO, device, socket). */
int supratrans_path_kind(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) return 0;
    if (S_ISREG(st.st_mode)) return 1;
    if (S_ISDIR(st.st_mode)) return 2;
    return 3;
}

/* Kind of a path itself, a symbolic link not followed (lstat): 0 missing, 1 regular file, 2 directory, 3 other
 * (FIFO, device, socket), 4 a symbolic link (dangling or not). */
int supratrans_link_kind(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0) return 0;
    if (S_ISLNK(st.st_mode)) return 4;
    if (S_ISREG(st.st_mode)) return 1;
    if (S_ISDIR(st.st_mode)) return 2;
    return 3;
}

/* Size in bytes of a regular file, -1 if it cannot be known. */
long long supratrans_file_size(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) return -1;
    return (long long)st.st_size;
}

/* Whether descriptor `fd` and the name `path` (not followed if a link) are the same file. */
static int same_inode(int fd, const char *path)
{
    struct stat a, b;
    if (fstat(fd, &a) != 0 || lstat(path, &b) != 0) return 0;
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

/* Take an exclusive advisory lock on `path` (created if missing) without waiting. Returns the descriptor (>= 0, kept
 * open for as long as the lock is held: the kernel releases it when the process ends, however it ends), -1 if another
 * process holds the lock, -2 if the lock file cannot be opened or is not a regular file (a symbolic link is never
 * followed), -3 if the file system refuses locks (ENOLCK on NFS without a lock manager, EOPNOTSUPP, ENOSYS, ...).
 * `*err` receives errno for -2 and -3. The lock file is never truncated.
 *
 * The holder removes the lock file when it is done (supratrans_unlock_remove), while still holding it. A process
 * that opened the file before that removal may then get the lock of a file that no longer has the name; so a lock
 * counts only once the name still refers to the file locked (same device and inode, checked after flock): else it
 * is dropped and the name opened again (created anew if gone). Two processes thus never both hold "the" lock. */
int supratrans_lock(const char *path, int *err)
{
    *err = 0;
    for (int attempt = 0; attempt < 100; attempt++) {
        int fd = open(path, O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
        if (fd < 0) {
            *err = errno;
            return -2;
        }
        struct stat st;
        if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
            *err = EINVAL;
            close(fd);
            return -2;
        }
        if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
            int e = errno;
            close(fd);
            if (e == EWOULDBLOCK || e == EAGAIN || e == EINTR) return -1;
            *err = e;
            return -3;
        }
        if (same_inode(fd, path)) return fd;
        /* removed (or replaced) by its holder between our open and our flock: that file is no lock any more */
        close(fd);
    }
    return -1;
}

/* Release a lock taken by supratrans_lock. The file stays (see supratrans_unlock_remove). */
void supratrans_unlock(int fd)
{
    if (fd >= 0) {
        flock(fd, LOCK_UN);
        close(fd);
    }
}

/* Remove the lock file `path` and release the lock `fd` taken by supratrans_lock on it: the name is unlinked while
 * the lock is still held, and only if it still names the file this process holds (same device and inode: never a
 * file another process created in its place). A process that opened the old file in between finds, after its flock,
 * that the name no longer refers to it and tries again (supratrans_lock). */
void supratrans_unlock_remove(int fd, const char *path)
{
    if (fd < 0) return;
    if (same_inode(fd, path)) unlink(path);
    flock(fd, LOCK_UN);
    close(fd);
}

/* The text of an errno value (strerror), copied into `buf` of `size` bytes. */
void supratrans_strerror(int err, char *buf, int size)
{
    if (size <= 0) return;
    const char *text = strerror(err);
    snprintf(buf, (size_t)size, "%s", text ? text : "unknown error");
}

/* Set HDF5_USE_FILE_LOCKING=FALSE for this process unless it is set already (the no-lock override: HDF5 would
 * otherwise fail on the same file system that refused our lock). */
void supratrans_hdf5_no_file_locking(void) { setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0); }

static volatile sig_atomic_t stop_signal = 0;

static void on_signal(int sig) { stop_signal = sig; }

/* Install the handler: SIGTERM, SIGINT and SIGUSR1 (Slurm's --signal) set the stop flag instead of killing. The three
 * signals are then unblocked: a process started with them blocked (a parent's mask is inherited across exec) would
 * otherwise never see them, and one already pending is delivered here, setting the flag. */
void supratrans_catch_stop_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGUSR1, &sa, NULL);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGUSR1);
    sigprocmask(SIG_UNBLOCK, &set, NULL);
}

/* Ignore SIGXFSZ: a write beyond the file size limit (ulimit -f) then fails with EFBIG, which every write checks and
 * reports in one line, instead of killing the process (or, under gfortran's backtrace handler, printing a trace). */
void supratrans_ignore_file_size_signal(void) { signal(SIGXFSZ, SIG_IGN); }

/* The signal that asked the program to stop, 0 if none. */
int supratrans_stop_signal(void) { return (int)stop_signal; }

static volatile sig_atomic_t no_memory = 0;

/* Note that a run could not allocate its arrays (any thread; the flag is only ever set). */
void supratrans_note_out_of_memory(void) { no_memory = 1; }

/* 1 once a run could not allocate its arrays. */
int supratrans_out_of_memory(void) { return (int)no_memory; }


/* 1 if the two paths name the same existing file (same device and inode), 0 otherwise. */
int supratrans_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0) return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

#include <sys/resource.h>

/* A limit of this process in bytes, -1 when unlimited: `kind` 1 the address space (RLIMIT_AS, ulimit -v), 2 the
 * data segment (RLIMIT_DATA, ulimit -d). */
double supratrans_memory_limit(int kind)
{
    struct rlimit r;
    if (getrlimit(kind == 1 ? RLIMIT_AS : RLIMIT_DATA, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return -1.0;
    return (double)r.rlim_cur;
}

/* Bytes of address space this process maps now (the first field of /proc/self/statm, in pages), -1 if unknown:
 * what counts against RLIMIT_AS (ulimit -v) before the run allocates anything. */
double supratrans_address_space_used(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    if (f == NULL) return -1.0;
    unsigned long long pages = 0;
    int ok = fscanf(f, "%llu", &pages) == 1;
    fclose(f);
    long page = sysconf(_SC_PAGESIZE);
    if (!ok || page <= 0) return -1.0;
    return (double)pages * (double)page;
}

/* Processors this process may run on (sched_getaffinity: what taskset, cpusets and Slurm's --cpus-per-task leave
 * it), or the processors online when that cannot be read; at least 1. */
int supratrans_usable_cpus(void)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) {
        int n = CPU_COUNT(&set);
        if (n > 0) return n;
    }
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

/* Processor time of the calling thread, in seconds (CLOCK_THREAD_CPUTIME_ID): what one task cost on its thread,
   whatever else the machine runs; -1 when the clock is not available. */
double supratrans_thread_cpu_seconds(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return -1.0;
    return (double)ts.tv_sec + 1.0e-9 * (double)ts.tv_nsec;
}

/* 0 if this process may create files in directory `path` (access(2) with W_OK | X_OK: the permission bits, ACLs and
 * a read-only mount, EROFS, all count), otherwise errno. */
int supratrans_directory_writable(const char *path)
{
    return access(path, W_OK | X_OK) == 0 ? 0 : errno;
}

/* Fill the last 6 characters of `name` with random letters and digits (getrandom; the clock and pid otherwise). */
static void random_suffix(char *name)
{
    static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    unsigned char r[6];
    size_t n = strlen(name);
    if (getrandom(r, sizeof r, 0) != (ssize_t)sizeof r) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        unsigned long long x = (unsigned long long)ts.tv_nsec ^ ((unsigned long long)getpid() << 20) ^
                               (unsigned long long)(size_t)name;
        for (int k = 0; k < 6; k++) {
            r[k] = (unsigned char)(x & 0xff);
            x = x * 6364136223846793005ULL + 1442695040888963407ULL;
            x ^= x >> 29;
        }
    }
    for (int k = 0; k < 6; k++) name[n - 6 + k] = alphabet[r[k] % (sizeof alphabet - 1)];
}

/* A fresh temporary name for `final`: `<final>.tmp-XXXXXX` with six random characters, into `buf` (`size` bytes).
 * The name is only a candidate: it is taken by creating it with O_EXCL (or HDF5's H5F_ACC_EXCL), retried when taken.
 * 0 on success, -1 if the name does not fit. */
int supratrans_temp_name(const char *final, char *buf, int size)
{
    int n = snprintf(buf, (size_t)size, "%s.tmp-XXXXXX", final);
    if (n < 0 || n >= size) return -1;
    random_suffix(buf);
    return 0;
}

/* Append `len` bytes to the journal `path` (created if missing, never through a symbolic link, never anything but a
 * regular file), checking every write(2) and close(2): a full disk or an I/O error is reported. 0 on success,
 * otherwise errno. */
int supratrans_append_bytes(const char *path, const char *bytes, long long len)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_APPEND | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, FILE_MODE);
    if (fd < 0) return errno;
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return EINVAL;
    }
    long long done = 0;
    while (done < len) {
        ssize_t n = write(fd, bytes + done, (size_t)(len - done));
        if (n < 0) {
            if (errno == EINTR) continue;
            int e = errno;
            close(fd);
            return e;
        }
        done += n;
    }
    return close(fd) == 0 ? 0 : errno;
}

/* fsync the directory that holds `path` (so that a rename into it survives a crash); errors are ignored (some file
 * systems cannot sync a directory). */
static void sync_directory_of(const char *path)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    if (slash == NULL) {
        strcpy(dir, ".");
    } else if (slash == path) {
        strcpy(dir, "/");
    } else {
        size_t n = (size_t)(slash - path);
        if (n >= sizeof dir) return;
        memcpy(dir, path, n);
        dir[n] = '\0';
    }
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        fsync(fd);
        close(fd);
    }
}

/* Write `len` bytes as the new contents of `final`, atomically: a fresh `<final>.tmp-XXXXXX` created with
 * O_CREAT | O_EXCL | O_NOFOLLOW (a name taken is retried), every write checked, fsync, close, rename(2) onto `final`
 * (which replaces `final` itself, never the target of a link at `final`). Nothing is left behind on failure.
 * 0 on success, otherwise errno. */
int supratrans_write_file_atomic(const char *final, const char *bytes, long long len)
{
    char tmp[4096];
    int fd = -1;
    for (int attempt = 0; attempt < 100 && fd < 0; attempt++) {
        if (supratrans_temp_name(final, tmp, sizeof tmp) != 0) return ENAMETOOLONG;
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, FILE_MODE);
        if (fd < 0 && errno != EEXIST) return errno;
    }
    if (fd < 0) return EEXIST;
    long long done = 0;
    int e = 0;
    while (done < len) {
        ssize_t n = write(fd, bytes + done, (size_t)(len - done));
        if (n < 0) {
            if (errno == EINTR) continue;
            e = errno;
            break;
        }
        done += n;
    }
    if (e == 0 && fsync(fd) != 0) e = errno;
    if (close(fd) != 0 && e == 0) e = errno;
    if (e == 0 && rename(tmp, final) != 0) e = errno;
    if (e != 0) {
        unlink(tmp);
        return e;
    }
    sync_directory_of(final);
    return 0;
}

/* Make a finished temporary file durable and give it its final name: fsync `tmp` (opened read-only, never through a
 * link), rename(2) it onto `final` (replacing `final` itself, never the target of a link), fsync the directory.
 * 0 on success, otherwise errno (`tmp` is then left for the caller to delete). */
int supratrans_commit_file(const char *tmp, const char *final)
{
    int fd = open(tmp, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return errno;
    int e = 0;
    if (fsync(fd) != 0) e = errno;
    close(fd);
    if (e != 0) return e;
    if (rename(tmp, final) != 0) return errno;
    sync_directory_of(final);
    return 0;
}

/* Delete the temporaries a killed run left behind: the entries of directory `dir` named `<prefix>XXXXXX` (six
 * letters or digits) that are regular files owned by this user (lstat: a link is never followed, another user's
 * file never touched). Call only while holding the output's lock. Returns how many were deleted. */
int supratrans_remove_stale(const char *dir, const char *prefix)
{
    DIR *d = opendir(dir);
    if (d == NULL) return 0;
    size_t np = strlen(prefix);
    int removed = 0;
    struct dirent *entry;
    while ((entry = readdir(d)) != NULL) {
        const char *name = entry->d_name;
        if (strlen(name) != np + 6 || strncmp(name, prefix, np) != 0) continue;
        int ok = 1;
        for (int k = 0; k < 6; k++) {
            char c = name[np + k];
            if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'))) ok = 0;
        }
        if (!ok) continue;
        struct stat st;
        if (fstatat(dirfd(d), name, &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
        if (!S_ISREG(st.st_mode) || st.st_uid != geteuid()) continue;
        if (unlinkat(dirfd(d), name, 0) == 0) removed++;
    }
    closedir(d);
    return removed;
}

/* ---------------------------------------------------------------------------------------------- start-up limits
 *
 * The limits a scheduler sets (RLIMIT_AS: `ulimit -v`, Slurm's VSizeLimit; RLIMIT_DATA: `ulimit -d`; RLIMIT_STACK:
 * `ulimit -s`) act before `main`. The OpenMP build of OpenBLAS (Debian's libopenblas0-openmp) maps one buffer of
 * 128 MiB for each of its threads in its constructor, and retries a failed mmap forever: under a limit that leaves
 * no room for them even `supratrans --version` used to spin at 100% CPU. It takes its thread count from
 * OMP_NUM_THREADS (OPENBLAS_NUM_THREADS is ignored by that build), capped at the processors it counts (the machine's,
 * not the affinity mask's: measured with taskset).
 *
 * An ELF executable's .preinit_array runs before the constructors of every shared library (glibc's _dl_init), so
 * this function can still set the environment those constructors read:
 * - the buffers fit the limits: nothing;
 * - k >= 1 buffers fit: OMP_NUM_THREADS=k, or the threads the program runs anyway if fewer (OpenBLAS's buffers and
 *   the program's threads; no line, so that a failure later is one line; /provenance has the threads);
 * - none fits: one line and exit status 2 (what a memory limit below a run's needs gives), before any work;
 * - merge: its stop signals are caught from here on (see supratrans_catch_stop_signals);
 * - the stack limit is below 8 MiB: OMP_STACKSIZE=8M unless set (libgomp's threads then get stacks of their own size,
 *   not the limit of the main thread's stack, which they inherit otherwise: a worker overflowed 64 KiB), and the soft
 *   stack limit is raised as far as the hard one allows (8 MiB at most); below 1 MiB still: one line, status 2.
 * Only the OpenMP build of OpenBLAS is looked at (openblas_get_parallel() == 2); any other BLAS maps nothing here. */

/* What OpenBLAS (x86_64, BUFFER_SIZE = 32 << 22) maps per thread at start-up, with what mmap adds to it. */
#define OPENBLAS_BUFFER (128.0 * 1048576.0 + 1048576.0)
/* What the rest of the start-up maps after the libraries (libgfortran, libgomp, HDF5), measured 2-6 MiB; with room. */
#define STARTUP_RESERVE (16.0 * 1048576.0)
/* The least stack the main thread must be allowed (ulimit -s): a run's deepest calls (LAPACK) need more than 64 KiB. */
#define MAIN_STACK (1024.0 * 1024.0)
/* The stack the threads of libgomp are given when the stack limit is below it. */
#define THREAD_STACK (8.0 * 1048576.0)

/* A field of /proc/self/status in bytes ("VmSize", "VmData"), -1 if it cannot be read. */
static double status_bytes(const char *field)
{
    FILE *f = fopen("/proc/self/status", "r");
    if (f == NULL) return -1.0;
    char line[256];
    double value = -1.0;
    size_t n = strlen(field);
    while (fgets(line, sizeof line, f) != NULL) {
        if (strncmp(line, field, n) == 0 && line[n] == ':') {
            value = 1024.0 * strtod(line + n + 1, NULL);
            break;
        }
    }
    fclose(f);
    return value;
}

/* The soft limit of `resource` in bytes, -1 when unlimited. */
static double soft_limit(int resource)
{
    struct rlimit r;
    if (getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return -1.0;
    return (double)r.rlim_cur;
}

/* One line on stderr, before anything else of the program runs. */
static void startup_line(const char *text)
{
    ssize_t ignored = write(2, text, strlen(text));
    (void)ignored;
}

/* The value of `name` in the environment `envp` (getenv cannot be used yet: libc sets its environment after this). */
static const char *env_value(char **envp, const char *name)
{
    size_t n = strlen(name);
    for (char **e = envp; e != NULL && *e != NULL; e++) {
        if (strncmp(*e, name, n) == 0 && (*e)[n] == '=') return *e + n + 1;
    }
    return NULL;
}

static void start_within_limits(int argc, char **argv, char **envp)
{
    char line[640];
    int set_stack = 0;
    /* merge catches SIGTERM, SIGINT and SIGUSR1 from its very start, before the libraries' constructors (they take
     * tens of milliseconds: a SIGTERM then used to end it with 143) */
    int merging = argc > 1 && argv[1] != NULL && strcmp(argv[1], "merge") == 0;
    if (merging) supratrans_catch_stop_signals();
    long set_threads = 0;
    double stack = soft_limit(RLIMIT_STACK);
    if (stack >= 0.0 && stack < THREAD_STACK) {
        struct rlimit r;
        if (getrlimit(RLIMIT_STACK, &r) == 0) {
            rlim_t want = (rlim_t)THREAD_STACK;
            if (r.rlim_max != RLIM_INFINITY && r.rlim_max < want) want = r.rlim_max;
            if (want > r.rlim_cur) {
                r.rlim_cur = want;
                setrlimit(RLIMIT_STACK, &r);
            }
        }
        set_stack = env_value(envp, "OMP_STACKSIZE") == NULL && env_value(envp, "GOMP_STACKSIZE") == NULL;
        /* the main thread keeps what the hard limit allows: below MAIN_STACK a run may overflow it inside LAPACK's
         * eigenvalue solvers (measured: SIGSEGV in dlaqr3/dormhr of a continuation under ulimit -s 64, now and then,
         * as the master thread draws that task) */
        double raised = soft_limit(RLIMIT_STACK);
        if (raised >= 0.0 && raised < MAIN_STACK) {
            snprintf(line, sizeof line, "error: supratrans: the stack limit (ulimit -s) of %.0f KiB is below the %.0f "
                     "KiB the main thread may need (LAPACK's eigenvalue solvers, the HDF5 writers): raise it, e.g. "
                     "ulimit -s 8192 (docs/failures.md)\n", raised / 1024.0, MAIN_STACK / 1024.0);
            startup_line(line);
            _exit(2);
        }
    }
    int (*parallel)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "openblas_get_parallel");
    double as = soft_limit(RLIMIT_AS), data = soft_limit(RLIMIT_DATA);
    if (parallel != NULL && parallel() == 2 && (as >= 0.0 || data >= 0.0)) {
        /* OpenBLAS's count: OMP_NUM_THREADS (the first level of a list "4,2"), else all processors, at most the
         * processors it counts, which are not always those of the affinity mask (measured: `taskset -c 0` on this
         * 2-processor machine still mapped two buffers); so the larger count is taken */
        int usable = supratrans_usable_cpus();
        long conf = sysconf(_SC_NPROCESSORS_CONF), online = sysconf(_SC_NPROCESSORS_ONLN);
        long most = usable;
        if (conf > most) most = conf;
        if (online > most) most = online;
        long asked = 0;
        const char *omp = env_value(envp, "OMP_NUM_THREADS");
        if (omp != NULL) asked = strtol(omp, NULL, 10);
        long threads = asked > 0 && asked < most ? asked : most;
        /* what the program runs without the limit: the threads asked, else libgomp's default (the affinity mask) */
        long wanted = asked > 0 ? asked : usable;
        long fit = threads;
        const char *which = NULL;
        double limit = 0.0, used = 0.0;
        double mapped = status_bytes("VmSize");
        long k = (long)((as - mapped - STARTUP_RESERVE) / OPENBLAS_BUFFER);
        if (as >= 0.0 && mapped >= 0.0 && k < fit) {
            fit = k < 0 ? 0 : k;
            which = "address-space limit (ulimit -v)";
            limit = as;
            used = mapped;
        }
        mapped = status_bytes("VmData");
        k = (long)((data - mapped - STARTUP_RESERVE) / OPENBLAS_BUFFER);
        if (data >= 0.0 && mapped >= 0.0 && k < fit) {
            fit = k < 0 ? 0 : k;
            which = "data-segment limit (ulimit -d)";
            limit = data;
            used = mapped;
        }
        if (which != NULL && fit < 1) {
            snprintf(line, sizeof line, "error: supratrans: the %s of %.0f MiB is below what start-up needs: the "
                     "libraries map %.0f MiB and OpenBLAS (OpenMP build) a buffer of 128 MiB, at least %.0f MiB in all "
                     "(it would retry forever); raise the limit, or use a serial BLAS (docs/failures.md)\n",
                     which, limit / 1048576.0, used / 1048576.0,
                     (used + OPENBLAS_BUFFER + STARTUP_RESERVE) / 1048576.0 + 1.0);
            startup_line(line);
            _exit(2);
        }
        /* silently: a line here would be a second line beside a run's own error (one line per failure); the
         * threads run are in every output's /provenance */
        if (which != NULL) set_threads = fit < wanted ? fit : wanted;
    }
    if (!set_stack && set_threads == 0) return;
    /* The environment is read by the libraries' constructors from the array the kernel passed, which cannot grow:
     * the program starts again with the settings added (they then hold, so this happens once). */
    size_t n = 0;
    while (envp != NULL && envp[n] != NULL) n++;
    char **env = calloc(n + 3, sizeof *env);
    static char threads_entry[48];
    if (env == NULL) return;
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (set_threads > 0 && strncmp(envp[i], "OMP_NUM_THREADS=", 16) == 0) continue;
        env[m++] = envp[i];
    }
    if (set_threads > 0) {
        snprintf(threads_entry, sizeof threads_entry, "OMP_NUM_THREADS=%ld", set_threads);
        env[m++] = threads_entry;
    }
    if (set_stack) env[m++] = "OMP_STACKSIZE=8M";
    env[m] = NULL;
    sigset_t stops, before;
    sigemptyset(&stops);
    sigaddset(&stops, SIGTERM);
    sigaddset(&stops, SIGINT);
    sigaddset(&stops, SIGUSR1);
    /* exec resets the handler: merge's stop signals wait, blocked and pending, for the handler of the new image */
    if (merging) sigprocmask(SIG_BLOCK, &stops, &before);
    execve("/proc/self/exe", argv, env);
    if (merging) sigprocmask(SIG_SETMASK, &before, NULL);
    /* exec refused (no /proc): the threads as they are; the check above stands for a retry-forever start-up */
    free(env);
}

/* Run before the constructors of the shared libraries (OpenBLAS's, libgomp's): see start_within_limits. */
__attribute__((section(".preinit_array"), used)) static void (*const supratrans_preinit)(int, char **, char **) =
    start_within_limits;
