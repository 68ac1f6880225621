// The one gzip reader of every input, structures (structure/text_input.cpp) and meshes
// (io/read_off_msms.cpp) alike: gzip data held in memory inflated with zlib, members one after
// another as gzip allows, a stream that ends early told apart from corrupt data (zlib's gzread
// would hand back a silently shorter file). In io/, the room for files, which structure/ may
// include; it needs nothing but zlib. It throws nothing of its own: each reader words the
// problem in its own messages, which the tests check.
#pragma once

#include <string>
#include <string_view>

namespace fdmsurf::detail {

// True when `data` starts with gzip's magic bytes (1f 8b).
bool is_gzip(std::string_view data);

// Why gzip data could not be inflated.
struct GzipProblem {
    enum class Kind {
        None,
        Setup,        // zlib's inflateInit2 failed
        Corrupt,      // not valid gzip data (zlib's Z_DATA_ERROR)
        Refused,      // inflate refused the stream (Z_NEED_DICT, Z_STREAM_ERROR)
        OutOfMemory,  // inflate could not allocate (Z_MEM_ERROR)
        Truncated,    // the data ends inside a member
    };
    Kind kind = Kind::None;
    std::string zlib_message;  // zlib's own words (z_stream::msg); empty when it gave none
};

// Inflates `gz`, gzip data (by its magic bytes), into `out`: every member, as long as the
// bytes after one start another (by its magic bytes); anything else after a member is ignored,
// as zlib's gzread does. False, with `problem` filled in, when the data is not whole gzip;
// `out` then holds what was inflated before. Inputs of any size (zlib's counts are 32-bit:
// they are fed and drained in pieces of at most 1 GiB).
bool gunzip(std::string_view gz, std::string& out, GzipProblem& problem);

}  // namespace fdmsurf::detail
