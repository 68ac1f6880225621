// Standard output of the fdmsurf program: summaries written and flushed with the reason of the
// first failure kept, the exit code of a run whose summary was lost, and the stream a mesh or
// picture is written to standard output through.
#include "cli/standard_output.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "cli/messages.hpp"
#include "cli/options.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::cli {
namespace {

// errno of the first failed flush of stdout (0: none): by the time check_stdout flushes the
// stream again, the error flag is all that is left of it.
int stdout_errno = 0;

void note_error(std::FILE* stream) {
    if (stream == stdout && stdout_errno == 0) stdout_errno = errno != 0 ? errno : EIO;
}

}  // namespace

void flush_noting_errors(std::FILE* stream) {
    errno = 0;
    if (std::fflush(stream) != 0) note_error(stream);
}

void put_noting_errors(const std::string& text, std::FILE* stream) {
    errno = 0;
    if (std::fwrite(text.data(), 1, text.size(), stream) != text.size()) note_error(stream);
}

// A summary that could not be printed (stdout a closed pipe) fails the run, as in coreutils.
int check_stdout(int code) {
    errno = 0;
    const bool flushed = std::fflush(stdout) == 0;
    // The reason of the first failed flush (a summary flushed earlier), else of this one.
    const int error_number = stdout_errno != 0 ? stdout_errno : errno != 0 ? errno : EIO;
    if (flushed && !std::ferror(stdout)) return code;
    if (code == kExitOk) {
        print_error(std::string("cannot write ") + kStdoutName + ": " +
                    std::strerror(error_number));
        return kExitInput;
    }
    return code;
}

std::streamsize StdoutBuffer::xsputn(const char* data, std::streamsize size) {
    std::streamsize done = 0;
    while (done < size) {
        const ssize_t n = ::write(STDOUT_FILENO, data + done, std::size_t(size - done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int error_number = n < 0 ? errno : EIO;
            throw Error(ErrorCode::Io, std::string("cannot write ") + kStdoutName + ": " +
                                           std::strerror(error_number) +
                                           (error_number == EPIPE
                                                ? " (the reading end of the pipe was closed; "
                                                  "the output is incomplete)"
                                                : ""));
        }
        done += n;
    }
    return size;
}

StdoutBuffer::int_type StdoutBuffer::overflow(int_type c) {
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
        const char byte = traits_type::to_char_type(c);
        xsputn(&byte, 1);
    }
    return traits_type::not_eof(c);
}

}  // namespace fdmsurf::cli
