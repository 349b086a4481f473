/* Operating-system calls that Fortran cannot make portably by itself: the kind of a path (stat), an advisory
 * lock (flock), a flag set by SIGTERM/SIGINT/SIGUSR1, the same-file test, checked writes and memory limits. Called through iso_c_binding by
 * supratrans_system.f90; nothing here runs a shell. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
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

/* Size in bytes of a regular file, -1 if it cannot be known. */
long long supratrans_file_size(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) return -1;
    return (long long)st.st_size;
}

/* Take an exclusive advisory lock on `path` (created if missing) without waiting. Returns the descriptor
 * (>= 0, kept open for as long as the lock is held: the kernel releases it when the process ends, however it
 * ends), -1 if another process holds the lock, -2 if the lock file cannot be opened. */
int supratrans_lock(const char *path)
{
    int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) return -2;
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

/* Release a lock taken by supratrans_lock. */
void supratrans_unlock(int fd)
{
    if (fd >= 0) {
        flock(fd, LOCK_UN);
        close(fd);
    }
}

static volatile sig_atomic_t stop_signal = 0;

static void on_signal(int sig) { stop_signal = sig; }

/* Install the handler: SIGTERM, SIGINT and SIGUSR1 (Slurm's --signal) set the stop flag instead of killing. */
void supratrans_catch_stop_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGUSR1, &sa, NULL);
}

/* The signal that asked the program to stop, 0 if none. */
int supratrans_stop_signal(void) { return (int)stop_signal; }


/* 1 if the two paths name the same existing file (same device and inode), 0 otherwise. */
int supratrans_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0) return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

#include <sys/resource.h>

/* The smaller of the address-space and data-segment limits of this process in bytes, or -1 when unlimited. */
double supratrans_memory_limit(void)
{
    struct rlimit as, data;
    double limit = -1.0;
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) limit = (double)as.rlim_cur;
    if (getrlimit(RLIMIT_DATA, &data) == 0 && data.rlim_cur != RLIM_INFINITY)
        if (limit < 0.0 || (double)data.rlim_cur < limit) limit = (double)data.rlim_cur;
    return limit;
}

/* Write `len` bytes to `path` (created if missing; appended to, or replacing its contents), checking every write(2)
 * and close(2): unlike buffered Fortran I/O, a full disk or an I/O error is reported. 0 on success, -1 on failure. */
int supratrans_write_bytes(const char *path, const char *bytes, long long len, int append)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_CLOEXEC | (append ? O_APPEND : O_TRUNC), 0666);
    if (fd < 0) return -1;
    long long done = 0;
    while (done < len) {
        ssize_t n = write(fd, bytes + done, (size_t)(len - done));
        if (n < 0) {
            if (errno == EINTR) continue;
            close(fd);
            return -1;
        }
        done += n;
    }
    return close(fd) == 0 ? 0 : -1;
}
