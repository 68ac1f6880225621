// Standard output of the fdmsurf program: summaries written with the reason of a failed write
// kept, so that a summary that could not be printed (a closed pipe) fails the run as in
// coreutils; and a stream for a mesh or picture written to it (-o -).
#pragma once

#include <cstdio>
#include <streambuf>
#include <string>

namespace fdmsurf::cli {

// The name of standard output in messages.
inline constexpr const char* kStdoutName = "standard output";

// `text` written to `stream`, the reason of a failed write kept as a flush's is: a text longer
// than the stream's buffer fails inside the write, and the later flush knows only that it did.
void put_noting_errors(const std::string& text, std::FILE* stream);
// Flushes `stream`, the reason of a failure on stdout kept for check_stdout.
void flush_noting_errors(std::FILE* stream);

// `code`, or with a summary that could not be written to stdout (flushed here) an error line
// and exit 3 when the run had succeeded otherwise.
int check_stdout(int code);

// Standard output as a stream for write_mesh, straight to descriptor 1 (stdio is not used for
// it): a failed write, a closed pipe among them (SIGPIPE is ignored), throws the Error that
// names its reason, and the stream passes it on (badbit is in its exception mask).
class StdoutBuffer final : public std::streambuf {
protected:
    std::streamsize xsputn(const char* data, std::streamsize size) override;
    int_type overflow(int_type c) override;
};

}  // namespace fdmsurf::cli
