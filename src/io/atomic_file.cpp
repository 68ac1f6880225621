// A file written under a temporary name and renamed into place, so no partial file is left.
#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <pthread.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <climits>
#include <cstdio>
#include <cstring>
#include <random>

#include "base/temp_files.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {
namespace {

constexpr std::size_t buffer_size = std::size_t{1} << 20;

thread_local CommitGroup* current_group = nullptr;

// Runs `create` (true when it made the file `name`, else errno says why) with SIGINT, SIGTERM
// and SIGHUP blocked on this thread and a TempFileCreation held, and tracks `name` once made:
// an interrupt waits until then, on this thread or another (temp_files.hpp), so its handler
// removes every file this leaves (cli/interrupts.cpp). Returns 0 when made, else the errno.
template <class Create>
int create_tracked(const std::string& name, bool& tracked, Create&& create) {
    sigset_t block, previous;
    sigemptyset(&block);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&block, sig);
    pthread_sigmask(SIG_BLOCK, &block, &previous);
    int error_number = 0;
    {
        const TempFileCreation creating;
        if (create())
            tracked = track_temp_file(name);
        else
            error_number = errno;
    }
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    return error_number;
}

// The random generator of the temporary files' 12-hex-digit suffixes.
std::mt19937_64 suffix_random() {
    std::random_device seed;
    return std::mt19937_64(seed() ^ (std::uint64_t(::getpid()) << 32));
}

unsigned long long random_suffix(std::mt19937_64& random) {
    return static_cast<unsigned long long>(random() & 0xffffffffffffULL);
}

// A hard link to the file at `path`, named as `temp_path` with ".old." for ".tmp." (as long, so
// within NAME_MAX; another random suffix where that name is taken), tracked so that an
// interrupt removes it. Empty when there is no file at `path` (`made` set) or it cannot be
// linked (another file system's rule: it then cannot be put back).
std::string link_backup(const std::string& path, const std::string& temp_path, bool& tracked,
                        bool& made) {
    tracked = made = false;
    std::string name = temp_path;
    std::size_t at = name.rfind(".tmp.");
    if (at == std::string::npos) {
        at = name.size();
        name += ".old.000000000000";
    } else {
        name.replace(at, 5, ".old.");
    }
    std::mt19937_64 random = suffix_random();
    for (int attempt = 0; attempt < 100; ++attempt) {
        if (attempt > 0) {
            char suffix[16];
            std::snprintf(suffix, sizeof suffix, "%012llx", random_suffix(random));
            name.replace(at + 5, std::string::npos, suffix);
        }
        // Made as a temporary file is: an interrupt removes every link it leaves.
        const int link_errno = create_tracked(
            name, tracked, [&] { return ::link(path.c_str(), name.c_str()) == 0; });
        if (link_errno == 0) return name;
        if (link_errno != EEXIST) {
            made = link_errno == ENOENT;
            return {};
        }
    }
    return {};
}

}  // namespace

// `path` with its symbolic links followed to the file they name (which may not exist yet), the
// path itself when it is no link; ELOOP after 40 links.
std::string follow_links(std::string path, int& error) {
    error = 0;
    for (int hop = 0; hop < 40; ++hop) {
        struct stat st;
        if (::lstat(path.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return path;
        std::string target(256, '\0');
        for (;;) {  // st_size is not to be trusted (/proc's links report 64)
            const ssize_t n = ::readlink(path.c_str(), target.data(), target.size());
            if (n < 0) return path;
            if (std::size_t(n) < target.size()) {
                target.resize(std::size_t(n));
                break;
            }
            target.resize(2 * target.size());
        }
        if (!target.empty() && target[0] != '/') {
            const std::size_t slash = path.rfind('/');
            if (slash != std::string::npos) target = path.substr(0, slash + 1) + target;
        }
        path = std::move(target);
    }
    error = ELOOP;
    return path;
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    buffer_.resize(buffer_size);
    struct stat st;
    const bool exists = ::stat(path_.c_str(), &st) == 0;
    if (exists && S_ISDIR(st.st_mode)) fail(EISDIR);
    // A FIFO, a device or a socket, and anything under /dev or /proc (/dev/stdout, /dev/fd/3,
    // whatever they lead to): written through as named, since renaming a file onto them would
    // replace them (or the system's /dev/stdout link), and a regular file behind them (a shell's
    // redirection) is appended to.
    if ((exists && !S_ISREG(st.st_mode)) || path_.starts_with("/dev/") ||
        path_.starts_with("/proc/")) {
        fd_ = ::open(path_.c_str(),
                     O_WRONLY | O_CLOEXEC | (exists && S_ISREG(st.st_mode) ? O_APPEND : 0));
        if (fd_ < 0) fail(errno);
        through_ = true;
        return;
    }
    // A symbolic link: the file it names is replaced (or made), the link stays.
    int link_error = 0;
    path_ = follow_links(std::move(path_), link_error);
    if (link_error != 0) fail(link_error);
    // open(O_EXCL) with a random suffix instead of mkstemp: mkstemp makes the file 0600,
    // while a renamed output should get the usual 0666 & ~umask.
    std::mt19937_64 random = suffix_random();
    // The temporary name is the file's with the suffix, its name cut short where both would
    // exceed the folder's NAME_MAX (a name of 239 to 255 bytes is still written).
    const std::size_t slash = path_.find_last_of('/');
    const std::string folder = slash == std::string::npos ? "." : path_.substr(0, slash + 1);
    long name_max = ::pathconf(folder.c_str(), _PC_NAME_MAX);
    if (name_max <= 0) name_max = NAME_MAX;
    const std::size_t name_length = path_.size() - (slash == std::string::npos ? 0 : slash + 1);
    for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
        char suffix[32];
        const int suffix_length =
            std::snprintf(suffix, sizeof suffix, ".tmp.%012llx", random_suffix(random));
        const std::size_t room = std::size_t(name_max) - std::size_t(suffix_length);
        temp_path_ = name_length > room && name_length <= std::size_t(name_max)
                         ? path_.substr(0, path_.size() - (name_length - room)) + suffix
                         : path_ + suffix;
        // Interrupts wait until the file is open and tracked (create_tracked).
        const int open_errno = create_tracked(temp_path_, tracked_, [&] {
            fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            return fd_ >= 0;
        });
        errno = open_errno;
        if (fd_ < 0 && errno != EEXIST) break;
    }
    if (fd_ < 0) {
        const int error_number = errno;
        temp_path_.clear();  // nothing of ours to remove
        fail(error_number);
    }
    // A file replaced keeps its permission bits (the new one would get 0666 & ~umask); not its
    // set-id or sticky bits, and where the file system refuses, the new file's are kept.
    if (exists) ::fchmod(fd_, st.st_mode & 0777);
}

AtomicFile::~AtomicFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_ && !temp_path_.empty()) ::unlink(temp_path_.c_str());
    if (tracked_) untrack_temp_file(temp_path_);
}

void AtomicFile::write(const void* data, std::size_t size) {
    const char* bytes = static_cast<const char*>(data);
    if (size >= buffer_.size()) {  // a large block goes straight to the file, not copied first
        flush();
        write_through(bytes, size);
        return;
    }
    while (size > 0) {
        if (used_ == buffer_.size()) flush();
        const std::size_t n = std::min(size, buffer_.size() - used_);
        std::memcpy(buffer_.data() + used_, bytes, n);
        used_ += n;
        bytes += n;
        size -= n;
    }
}

void AtomicFile::flush() {
    write_through(buffer_.data(), used_);
    used_ = 0;
}

void AtomicFile::write_through(const char* bytes, std::size_t size) {
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::write(fd_, bytes + done, size - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail(n < 0 ? errno : EIO);
        done += std::size_t(n);
    }
}

void AtomicFile::commit() {
    flush();
    const int fd = fd_;
    fd_ = -1;  // close() releases the descriptor even when it reports an error
    if (::close(fd) != 0) fail(errno);
    committed_ = true;
    if (through_) return;
    if (CommitGroup* group = CommitGroup::current()) {
        group->pending_.push_back({temp_path_, path_, tracked_});  // its to rename or remove
        tracked_ = false;
        return;
    }
    if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
        committed_ = false;
        fail(errno);
    }
    if (tracked_) untrack_temp_file(temp_path_);
    tracked_ = false;
}

CommitGroup::CommitGroup() : outer_(current_group) { current_group = this; }

CommitGroup* CommitGroup::current() { return current_group; }

CommitGroup::~CommitGroup() {
    for (const Pending& p : pending_) {
        ::unlink(p.temp_path.c_str());
        if (p.tracked) untrack_temp_file(p.temp_path);
    }
    if (current_group == this) current_group = outer_;
}

void CommitGroup::commit() {
    // Files committed after this go on as without the group (or into the outer one).
    if (current_group == this) current_group = outer_;
    if (outer_ != nullptr) {  // nested: the outer group renames them, with its own
        outer_->pending_.insert(outer_->pending_.end(), pending_.begin(), pending_.end());
        pending_.clear();
        return;
    }
    for (const Pending& p : pending_) {
        struct stat st;
        if (::stat(p.path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
            throw Error(ErrorCode::Io, "cannot write " + p.path + ": " + std::strerror(EISDIR));
    }
    // Each file replaced is kept under a hard link (link_backup) until every rename has
    // succeeded: a rename that fails puts back what the earlier ones replaced, and removes the
    // files they made.
    struct Renamed {
        std::string path, backup;  // backup empty: no file there, or no link could be made
        bool tracked = false, made = false;  // made: there was no file at `path` before
    };
    std::vector<Renamed> renamed;
    const auto drop_backup = [](const Renamed& r) {
        if (r.backup.empty()) return;
        ::unlink(r.backup.c_str());
        if (r.tracked) untrack_temp_file(r.backup);
    };
    const auto drop_backups = [&renamed, &drop_backup] {
        for (const Renamed& r : renamed) drop_backup(r);
    };
    while (!pending_.empty()) {
        const Pending& p = pending_.front();
        Renamed r;
        r.path = p.path;
        r.backup = link_backup(p.path, p.temp_path, r.tracked, r.made);
        if (std::rename(p.temp_path.c_str(), p.path.c_str()) != 0) {
            const int error_number = errno;
            drop_backup(r);
            std::string kept;  // files that could not be put back, and where their content is
            for (auto it = renamed.rbegin(); it != renamed.rend(); ++it) {
                if (it->made) {
                    ::unlink(it->path.c_str());
                } else if (!it->backup.empty()) {
                    if (it->tracked) untrack_temp_file(it->backup);
                    if (std::rename(it->backup.c_str(), it->path.c_str()) != 0)
                        kept += "; " + it->path + " could not be put back: its former content "
                                "is in " + it->backup;
                    it->backup.clear();  // put back, or left for the user: not dropped
                }
            }
            drop_backups();
            throw Error(ErrorCode::Io,
                        "cannot write " + p.path + ": " + std::strerror(error_number) + kept);
        }
        renamed.push_back(std::move(r));
        if (p.tracked) untrack_temp_file(p.temp_path);
        pending_.erase(pending_.begin());
    }
    drop_backups();
}

void AtomicFile::fail(int error_number) {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    if (!temp_path_.empty()) {
        ::unlink(temp_path_.c_str());
        if (tracked_) untrack_temp_file(temp_path_);
        tracked_ = false;
        temp_path_.clear();
    }
    throw Error(ErrorCode::Io, "cannot write " + path_ + ": " + std::strerror(error_number));
}

}  // namespace fdmsurf::detail
