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
    int fd = open(path, O_WRONLY | O_CREAT | O_APPEND | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
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
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
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
