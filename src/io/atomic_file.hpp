// A file written under a temporary name and renamed into place, so no partial file is left.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/formats.hpp"

namespace fdmsurf::detail {

class CommitGroup;

// `path` with its symbolic links followed to the file they name (which may not exist yet): where
// an AtomicFile at `path` writes. The path itself when it is no link; `error` ELOOP after 40
// links (else 0).
std::string follow_links(std::string path, int& error);

// Opens a new temporary file next to `path`; write() buffers, commit() flushes, closes and
// renames it onto `path`. Destroyed without commit(), it removes the temporary file. Every
// failure throws Error(Io, "cannot write <path>: <reason>"). Not copyable.
// - A symbolic link at `path` is followed: the file it names is replaced, the link stays (a
//   loop is ELOOP).
// - A FIFO, a device or a socket at `path`, and any path under /dev or /proc (/dev/stdout,
//   /dev/fd/N), is written through as named, with no temporary file (a regular file behind it
//   is appended to): a reader sees what was written before a failure.
// - A folder at `path` is refused at once.
// - A file at `path` keeps its permission bits (rwx, not set-id or sticky; where the file
//   system allows).
// - While a CommitGroup is alive on the calling thread, commit() leaves the renaming to it.
class AtomicFile final : public ByteSink {
public:
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    using ByteSink::write;
    void write(const void* data, std::size_t size) override;
    void commit();

private:
    void flush();
    void write_through(const char* bytes, std::size_t size);
    [[noreturn]] void fail(int error_number);

    std::string path_;       // symbolic links followed
    std::string temp_path_;  // empty when written through (or nothing of ours to remove)
    bool through_ = false;   // a FIFO or a device, written in place
    int fd_ = -1;
    std::vector<char> buffer_;
    std::size_t used_ = 0;
    bool committed_ = false;
    bool tracked_ = false;  // in base/temp_files' table, for an interrupt handler
};

// Files written together: while a group is alive on a thread, each AtomicFile committed there
// is completed under its temporary name, and commit() renames them all into place, after
// checking that none of their paths has become a folder, so that a set of files (MSMS's .vert,
// .face and .area) appears together or not at all. Destroyed without commit() (an exception),
// it removes the temporary files it holds. After commit(), files go on as without it. Groups
// nest: the innermost one takes the files, and its commit() hands them to the outer one. A
// group belongs to the thread that made it: files committed on other threads are not its.
class CommitGroup {
public:
    CommitGroup();
    ~CommitGroup();
    CommitGroup(const CommitGroup&) = delete;
    CommitGroup& operator=(const CommitGroup&) = delete;
    // Renames every file committed under the group into place. A rename that fails throws
    // Error(Io) naming its file, after the files renamed before it were put back as they were
    // (each replaced file is kept under a hard link until all are renamed; one on a file system
    // without hard links stays new) and the files they made removed.
    void commit();

private:
    friend class AtomicFile;
    struct Pending {
        std::string temp_path, path;
        bool tracked;
    };
    static CommitGroup* current();
    std::vector<Pending> pending_;
    CommitGroup* outer_;
};

}  // namespace fdmsurf::detail
