#pragma once
// An output file that appears at its final path only when it is complete, whose temporary
// file nobody else can redirect, and which does not outlive its process.
//
// The temporary file lives in the output's directory (so that rename(2) is atomic) and is
// never reached through a name someone else could have planted:
//  * preferably it has no name at all: open(dir, O_TMPFILE). A process killed outright
//    (SIGKILL, a second Ctrl-C) leaves nothing behind; the kernel frees the inode.
//  * where the file system has no O_TMPFILE (NFS, old overlayfs) or /proc is missing, it is
//    created with O_CREAT | O_EXCL | O_NOFOLLOW under an unpredictable name in the same
//    directory, ".<name>.ridge-tmp-<16 random hex digits>" (temporaryNamePrefix()).
// Either way it is flock(LOCK_EX)ed for its whole life, and every new AtomicOutput for the
// same final path first removes the temporaries of that path whose lock is free — their
// owner is dead (SIGKILL of the fallback, or a kill inside commit() between the link and the
// rename). A live owner's file is never removed: its lock is held. (Where the file system has
// no locks at all, nothing is locked and nothing is removed.)
//
// Writers write through fd(), or through temporaryPath() when a library insists on a path.
// commit() fsyncs the file, names it and renames it over the final path, then fsyncs the
// directory. Destroyed without commit() — an exception, a cancelled build — the temporary
// file disappears and nothing changes at the final path. A final path that is a symlink is
// replaced by the new file (rename replaces the link itself), never written through; callers
// refuse outputs that are inputs first (file_identity.h). A final path that is a FIFO, a
// character or block device or a socket, or a symlink to one, is refused (checked when the
// object is made and again at commit): it is never replaced by a regular file.
//
// Not thread-safe: one object, one thread at a time.
//
// Test hook: with RIDGE_TEST_NAMED_TEMPORARIES=1 in the environment the named fallback is
// used even where O_TMPFILE works, so that tests cover the path taken on NFS.
#include <string>

namespace ridge {

class AtomicOutput {
  public:
    // Creates the temporary file (and removes dead owners' ones, see above). Throws
    // Error("FINAL: cannot write: REASON") when the directory is missing or not writable,
    // or FINAL is a directory or a special file ("it is a FIFO: ..."). Cost: one directory scan of
    // the output's directory.
    explicit AtomicOutput(std::string final_path);
    // Without commit(): the temporary file is unlinked (named) or just closed (unnamed).
    ~AtomicOutput();
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    // The temporary file, open read-write (O_CLOEXEC), owned by this object until it dies:
    // do not close it; dup() it for stdio (fdopen). -1 after commit().
    int fd() const { return fd_; }
    // A path that opens this very temporary file, for libraries that only take names (GDAL,
    // PLplot): "/proc/self/fd/N", a magic link that reopens this inode and is never resolved
    // through a directory, so nobody can swap the file behind it; the temporary file's own
    // name only where /proc is unavailable (then the file is a named one).
    const std::string& temporaryPath() const { return open_path_; }
    const std::string& finalPath() const { return final_path_; }
    // True while the temporary file has no name (O_TMPFILE), i.e. nothing can be left behind.
    bool unnamed() const { return fd_ >= 0 && temp_name_.empty(); }

    // fsyncs the temporary file, renames it over the final path and fsyncs the directory.
    // Throws Error naming the final path on failure (e.g. "FINAL: cannot write: No space left
    // on device"), and then nothing is left at the final path that was not there before.
    // Call at most once.
    void commit();

    // ".<name>.ridge-tmp-": how temporary files of a final path named <name> begin (the name
    // is cut to 200 bytes so that the whole fits in NAME_MAX).
    static std::string temporaryNamePrefix(const std::string& final_name);

  private:
    // Throws Error("FINAL: cannot write: WHAT: strerror(error)"), without the reason for 0.
    [[noreturn]] void fail(const std::string& what, int error) const;
    // Throws unless the final path is absent, a regular file or a symlink that does not lead
    // to a FIFO, device or socket.
    void refuseSpecialFile() const;
    void openTemporary();
    void openNamed();
    void giveUnnamedAName();
    void syncDirectory();

    std::string final_path_;
    std::string dir_path_;   // the output's directory, for messages
    std::string final_name_; // the final path's last component, relative to dir_fd_
    int dir_fd_ = -1;
    int fd_ = -1;
    std::string temp_name_; // in dir_fd_; empty while the file is unnamed
    std::string open_path_;
    bool committed_ = false;
};

// Throws Error("PATH: cannot write: REASON") when a file cannot be created at `path` (its
// directory is missing or read-only, `path` is a directory), leaving nothing behind: for
// commands to check their outputs before long work rather than after it. The probe is an
// AtomicOutput abandoned at once (no predictable probe name).
void checkOutputWritable(const std::string& path);

// Writes `text` to `path` through an AtomicOutput (reports, JSON). Throws Error naming the
// path when it cannot be written.
void writeFileAtomically(const std::string& path, const std::string& text);

} // namespace ridge
