// The one gzip reader of every input (see gzip_input.hpp): zlib's inflate over data in memory.
#include "io/gzip_input.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstddef>

namespace fdmsurf::detail {

bool is_gzip(std::string_view data) {
    return data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f &&
           static_cast<unsigned char>(data[1]) == 0x8b;
}

bool gunzip(std::string_view gz, std::string& out, GzipProblem& problem) {
    using Kind = GzipProblem::Kind;
    problem = GzipProblem{};
    z_stream zs{};
    if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) {
        problem.kind = Kind::Setup;
        return false;
    }
    struct Guard {
        z_stream* zs;
        ~Guard() { inflateEnd(zs); }
    } guard{&zs};
    auto fail = [&](Kind kind) {
        problem.kind = kind;
        if (zs.msg) problem.zlib_message = zs.msg;
        return false;
    };

    constexpr std::size_t kPiece = std::size_t{1} << 30;  // avail_in and avail_out are 32-bit
    std::size_t in_pos = 0;
    bool at_member_end = false;
    for (;;) {
        if (zs.avail_in == 0 && in_pos < gz.size()) {
            const std::size_t piece = std::min(gz.size() - in_pos, kPiece);
            zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(gz.data() + in_pos));
            zs.avail_in = static_cast<uInt>(piece);
            in_pos += piece;
        }
        if (at_member_end) {
            // Concatenated members are legal gzip; anything else after the end is ignored.
            if (zs.avail_in < 2 ||
                !is_gzip(std::string_view(reinterpret_cast<const char*>(zs.next_in), zs.avail_in)))
                break;
            inflateReset(&zs);
            at_member_end = false;
        }
        // Room for at least as much as the compressed size (or 256 KiB) at a time.
        const std::size_t old_size = out.size();
        const std::size_t chunk = std::min(std::max<std::size_t>(1u << 18, gz.size()), kPiece);
        out.resize(old_size + chunk);
        zs.next_out = reinterpret_cast<Bytef*>(out.data() + old_size);
        zs.avail_out = static_cast<uInt>(chunk);
        const int ret = inflate(&zs, Z_NO_FLUSH);
        out.resize(old_size + chunk - zs.avail_out);
        if (ret == Z_STREAM_END) {
            at_member_end = true;
        } else if (ret == Z_MEM_ERROR) {
            return fail(Kind::OutOfMemory);
        } else if (ret == Z_DATA_ERROR) {
            return fail(Kind::Corrupt);
        } else if (ret == Z_NEED_DICT || ret == Z_STREAM_ERROR) {
            return fail(Kind::Refused);
        } else if (zs.avail_in == 0 && in_pos == gz.size() && zs.avail_out != 0) {
            // inflate wanted more input and there is none.
            return fail(Kind::Truncated);
        }
    }
    return true;
}

}  // namespace fdmsurf::detail
