// A file written under a temporary name and renamed into place, so no partial file is left.
#include "mesh/atomic_file.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>

#include "core/temp_files.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {
namespace {

constexpr std::size_t buffer_size = std::size_t{1} << 20;

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    // open(O_EXCL) with a random suffix instead of mkstemp: mkstemp makes the file 0600,
    // while a renamed output should get the usual 0666 & ~umask.
    std::random_device seed;
    std::mt19937_64 random(seed() ^ (std::uint64_t(::getpid()) << 32));
    for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
        char suffix[32];
        std::snprintf(suffix, sizeof suffix, ".tmp.%012llx",
                      static_cast<unsigned long long>(random() & 0xffffffffffffULL));
        temp_path_ = path_ + suffix;
        // Interrupts wait until the file is open and tracked, so an interrupt handler removes
        // every temporary file it leaves (cli/interrupts.cpp).
        sigset_t block, previous;
        sigemptyset(&block);
        for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&block, sig);
        pthread_sigmask(SIG_BLOCK, &block, &previous);
        int open_errno = 0;
        {
            // ... and an interrupt handled on another thread waits for it (temp_files.hpp).
            const TempFileCreation creating;
            fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            open_errno = errno;
            if (fd_ >= 0) tracked_ = track_temp_file(temp_path_);
        }
        pthread_sigmask(SIG_SETMASK, &previous, nullptr);
        errno = open_errno;
        if (fd_ < 0 && errno != EEXIST) break;
    }
    if (fd_ < 0) {
        const int error_number = errno;
        temp_path_.clear();  // nothing of ours to remove
        fail(error_number);
    }
    buffer_.resize(buffer_size);
}

AtomicFile::~AtomicFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_ && !temp_path_.empty()) ::unlink(temp_path_.c_str());
    if (tracked_) untrack_temp_file(temp_path_);
}

void AtomicFile::write(const void* data, std::size_t size) {
    const char* bytes = static_cast<const char*>(data);
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
    std::size_t done = 0;
    while (done < used_) {
        const ssize_t n = ::write(fd_, buffer_.data() + done, used_ - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail(n < 0 ? errno : EIO);
        done += std::size_t(n);
    }
    used_ = 0;
}

void AtomicFile::commit() {
    flush();
    const int fd = fd_;
    fd_ = -1;  // close() releases the descriptor even when it reports an error
    if (::close(fd) != 0) fail(errno);
    if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) fail(errno);
    committed_ = true;
    if (tracked_) untrack_temp_file(temp_path_);
    tracked_ = false;
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
