#include "ridge/core/atomic_output.h"

#include "ridge/core/error.h"

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <dirent.h>
#include <fcntl.h>
#include <filesystem>
#include <random>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

namespace ridge {

namespace {

// Longest part of the final name kept in a temporary name: 1 + 200 + 11 + 16 < NAME_MAX.
constexpr size_t kMaxNameInPrefix = 200;
constexpr int kNameAttempts = 16;
// An unlocked, empty temporary younger than this may be in the instant between its
// O_CREAT|O_EXCL and its flock (the fallback cannot create and lock in one step), so the
// cleanup leaves it alone; the owner's next write or a later cleanup settles it. Files that
// hold data were necessarily locked by their owner before, so a free lock on them means a
// dead owner whatever their age.
constexpr time_t kCreationGraceSeconds = 60;

bool namedTemporariesForced()
{
    const char* v = std::getenv("RIDGE_TEST_NAMED_TEMPORARIES");
    return v && *v && std::strcmp(v, "0") != 0;
}

// 16 hex digits from the kernel's CSPRNG: a name nobody can plant in advance (the pid was).
std::string randomSuffix()
{
    uint64_t bits = 0;
    if (::getrandom(&bits, sizeof bits, 0) != static_cast<ssize_t>(sizeof bits)) {
        std::random_device rd;
        bits = (uint64_t{rd()} << 32) ^ rd();
    }
    static constexpr char kHex[] = "0123456789abcdef";
    std::string s(16, '0');
    for (int k = 0; k < 16; ++k)
        s[k] = kHex[(bits >> (4 * k)) & 0xf];
    return s;
}

bool sameFile(const struct stat& a, const struct stat& b)
{
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

// "/proc/self/fd/N" when that magic link reaches `fd`'s own inode; empty without /proc.
std::string procPathOf(int fd)
{
    const std::string path = "/proc/self/fd/" + std::to_string(fd);
    struct stat via_proc = {}, direct = {};
    if (::stat(path.c_str(), &via_proc) != 0 || ::fstat(fd, &direct) != 0 ||
        !sameFile(via_proc, direct))
        return {};
    return path;
}

// Removes `name` from `dir_fd` if it is a regular file whose flock is free (its owner died).
// Never follows a symlink, never blocks on a FIFO or opens a device: the name is lstat'ed
// first, opened O_NOFOLLOW | O_NONBLOCK, and unlinked only while it still names the file
// that was locked.
void removeIfOwnerDead(int dir_fd, const char* name, time_t now)
{
    struct stat seen {};
    if (::fstatat(dir_fd, name, &seen, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(seen.st_mode))
        return;
    if (seen.st_size == 0 && now - seen.st_ctime < kCreationGraceSeconds)
        return;
    const int fd =
        ::openat(dir_fd, name, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0)
        return;
    struct stat opened {};
    if (::fstat(fd, &opened) == 0 && S_ISREG(opened.st_mode) && sameFile(opened, seen) &&
        ::flock(fd, LOCK_EX | LOCK_NB) == 0) {
        struct stat again {};
        if (::fstatat(dir_fd, name, &again, AT_SYMLINK_NOFOLLOW) == 0 && sameFile(again, opened))
            ::unlinkat(dir_fd, name, 0);
    }
    ::close(fd); // releases the lock
}

// Temporaries of the same final path left by dead processes. Cost: one readdir of the
// directory; only names with the prefix are looked at.
void removeDeadTemporaries(int dir_fd, const std::string& prefix)
{
    const int scan_fd = ::openat(dir_fd, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (scan_fd < 0)
        return;
    DIR* dir = ::fdopendir(scan_fd);
    if (!dir) {
        ::close(scan_fd);
        return;
    }
    const time_t now = std::time(nullptr);
    while (const dirent* entry = ::readdir(dir))
        if (std::strncmp(entry->d_name, prefix.c_str(), prefix.size()) == 0)
            removeIfOwnerDead(dir_fd, entry->d_name, now);
    ::closedir(dir);
}

// O_TMPFILE is missing from the kernel (EISDIR: old kernels see O_DIRECTORY | O_RDWR) or
// from the file system (EOPNOTSUPP; EINVAL on some).
bool tmpfileUnsupported(int error)
{
    return error == EOPNOTSUPP || error == EISDIR || error == EINVAL;
}

// "a FIFO", "a character device" ...; null for a regular file, a directory or a symlink.
const char* specialKind(mode_t mode)
{
    if (S_ISFIFO(mode))
        return "a FIFO";
    if (S_ISCHR(mode))
        return "a character device";
    if (S_ISBLK(mode))
        return "a block device";
    if (S_ISSOCK(mode))
        return "a socket";
    return nullptr;
}

} // namespace

std::string AtomicOutput::temporaryNamePrefix(const std::string& final_name)
{
    // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "." + std::string.
    std::string prefix(1, '.');
    prefix.append(final_name, 0, kMaxNameInPrefix);
    prefix.append(".ridge-tmp-");
    return prefix;
}

AtomicOutput::AtomicOutput(std::string final_path) : final_path_(std::move(final_path))
{
    const std::filesystem::path p(final_path_);
    final_name_ = p.filename().string();
    dir_path_ = p.has_parent_path() ? p.parent_path().string() : ".";
    if (final_name_.empty() || final_name_ == "." || final_name_ == "..")
        fail("not a file name", 0);
    dir_fd_ = ::open(dir_path_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir_fd_ < 0)
        fail("directory " + dir_path_, errno);
    try {
        struct stat st {};
        if (::fstatat(dir_fd_, final_name_.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 &&
            S_ISDIR(st.st_mode))
            fail("it is a directory", 0);
        refuseSpecialFile();
        removeDeadTemporaries(dir_fd_, temporaryNamePrefix(final_name_));
        openTemporary();
    } catch (...) {
        if (fd_ >= 0)
            ::close(fd_);
        if (!temp_name_.empty())
            ::unlinkat(dir_fd_, temp_name_.c_str(), 0);
        ::close(dir_fd_);
        throw;
    }
}

AtomicOutput::~AtomicOutput()
{
    // Unlink before closing, so that the name never exists without its lock.
    if (!committed_ && fd_ >= 0 && !temp_name_.empty())
        ::unlinkat(dir_fd_, temp_name_.c_str(), 0);
    if (fd_ >= 0)
        ::close(fd_);
    if (dir_fd_ >= 0)
        ::close(dir_fd_);
}

void AtomicOutput::fail(const std::string& what, int error) const
{
    throw Error(final_path_ + ": cannot write: " + what +
                (error ? std::string(": ") + std::strerror(error) : std::string()));
}

void AtomicOutput::refuseSpecialFile() const
{
    // The rename would put a regular file in place of the FIFO, device or socket (as root,
    // `-o /dev/null` would replace /dev/null), and a symlink to one (`-o /dev/stdout`) names
    // a stream, not a file that can be replaced whole. Regular files, directories (refused
    // above) and symlinks to regular files or to nothing are the rest.
    struct stat st {};
    if (::fstatat(dir_fd_, final_name_.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0)
        return;
    const char* kind = specialKind(st.st_mode);
    std::string what = kind ? std::string("it is ") + kind : std::string();
    if (!kind && S_ISLNK(st.st_mode) && ::fstatat(dir_fd_, final_name_.c_str(), &st, 0) == 0 &&
        (kind = specialKind(st.st_mode)) != nullptr)
        what = std::string("it is a symlink to ") + kind;
    if (kind)
        fail(what + ": outputs are written only to regular files, and a FIFO, device or socket "
                    "is never replaced (write to a file, then copy it there)",
             0);
}

void AtomicOutput::openTemporary()
{
    if (!namedTemporariesForced()) {
        fd_ = ::openat(dir_fd_, ".", O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
        if (fd_ < 0 && !tmpfileUnsupported(errno))
            fail("directory " + dir_path_, errno);
        if (fd_ >= 0) {
            open_path_ = procPathOf(fd_);
            // Without /proc an unnamed file could neither be named at commit (linkat with
            // AT_EMPTY_PATH needs CAP_DAC_READ_SEARCH) nor be handed to GDAL: use a named one.
            if (open_path_.empty()) {
                ::close(fd_);
                fd_ = -1;
            }
        }
    }
    if (fd_ < 0)
        openNamed();
    // Unnamed files need the lock too: commit() gives them a name before the rename.
    // Blocking: only a cleanup scan can hold it, for the instant of one fstat.
    while (::flock(fd_, LOCK_EX) != 0) {
        if (errno == EINTR)
            continue;
        // A file system without locks (NFS without lockd): the output is still written; only
        // the cleanup of dead owners' files is lost there, since it unlinks nothing it could
        // not lock either.
        if (errno == ENOLCK || errno == EOPNOTSUPP || errno == ENOSYS)
            break;
        fail("cannot lock the temporary file", errno);
    }
}

void AtomicOutput::openNamed()
{
    const std::string prefix = temporaryNamePrefix(final_name_);
    for (int attempt = 0; attempt < kNameAttempts; ++attempt) {
        const std::string name = prefix + randomSuffix();
        // O_EXCL: fails on any existing name, a planted symlink included (never followed).
        fd_ = ::openat(dir_fd_, name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC,
                       0666);
        if (fd_ >= 0) {
            temp_name_ = name;
            const std::string proc = procPathOf(fd_);
            open_path_ = proc.empty() ? (std::filesystem::path(dir_path_) / name).string() : proc;
            return;
        }
        if (errno != EEXIST)
            fail("directory " + dir_path_, errno);
    }
    fail("no free temporary name in " + dir_path_, EEXIST);
}

// linkat cannot replace an existing name, so the unnamed file is first linked under a fresh
// unpredictable temporary name (locked: a cleanup leaves it alone), then renamed.
void AtomicOutput::giveUnnamedAName()
{
    const std::string prefix = temporaryNamePrefix(final_name_);
    for (int attempt = 0; attempt < kNameAttempts; ++attempt) {
        const std::string name = prefix + randomSuffix();
        if (::linkat(AT_FDCWD, open_path_.c_str(), dir_fd_, name.c_str(), AT_SYMLINK_FOLLOW) == 0) {
            temp_name_ = name;
            return;
        }
        if (errno != EEXIST)
            fail("cannot link the temporary file", errno);
    }
    fail("no free temporary name in " + dir_path_, EEXIST);
}

void AtomicOutput::syncDirectory()
{
    // Makes the rename durable. Some file systems cannot fsync a directory (EINVAL): there is
    // nothing more to do on those.
    if (::fsync(dir_fd_) != 0 && errno != EINVAL && errno != EROFS)
        fail("written, but the directory " + dir_path_ + " cannot be synced", errno);
}

void AtomicOutput::commit()
{
    if (committed_ || fd_ < 0)
        throw Error(final_path_ + ": internal error: output committed twice");
    // fsync before rename so that a crash after the rename cannot expose an empty file; it
    // is also where delayed write errors (EIO, ENOSPC, EDQUOT) surface.
    if (::fsync(fd_) != 0)
        fail("fsync", errno);
    // Again at the last moment: a special file may have appeared at the final path during
    // the work (the window that remains is the rename's own instant).
    refuseSpecialFile();
    if (temp_name_.empty())
        giveUnnamedAName();
    if (::renameat(dir_fd_, temp_name_.c_str(), dir_fd_, final_name_.c_str()) != 0)
        fail("rename", errno); // the destructor unlinks the temporary name
    committed_ = true;
    temp_name_.clear();
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0 && errno != EINTR)
        fail("close", errno);
    syncDirectory();
}

void checkOutputWritable(const std::string& path)
{
    const AtomicOutput probe(path);
}

void writeFileAtomically(const std::string& path, const std::string& text)
{
    AtomicOutput output(path);
    const char* data = text.data();
    size_t left = text.size();
    while (left > 0) {
        const ssize_t n = ::write(output.fd(), data, left);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            throw Error(path + ": cannot write: " + std::strerror(n < 0 ? errno : EIO));
        data += n;
        left -= static_cast<size_t>(n);
    }
    output.commit();
}

} // namespace ridge
