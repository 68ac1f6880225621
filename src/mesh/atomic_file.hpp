// A file written under a temporary name and renamed into place, so no partial file is left.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "formats/formats.hpp"

namespace fdmsurf::detail {

// Opens a new temporary file next to `path`; write() buffers, commit() flushes, closes and
// renames it onto `path`. Destroyed without commit(), it removes the temporary file. Every
// failure throws Error(Io, "cannot write <path>: <reason>"). Not copyable.
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
    [[noreturn]] void fail(int error_number);

    std::string path_;
    std::string temp_path_;
    int fd_ = -1;
    std::vector<char> buffer_;
    std::size_t used_ = 0;
    bool committed_ = false;
    bool tracked_ = false;  // in core/temp_files' table, for an interrupt handler
};

}  // namespace fdmsurf::detail
