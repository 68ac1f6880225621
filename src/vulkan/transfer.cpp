// Uploads and read-backs: direct through mapped memory on unified-memory devices (lavapipe),
// staged copies on discrete GPUs.
#include "vulkan/transfer.hpp"

#include <cstring>
#include <string>

#include "fdmsurf/error.hpp"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {

Buffer upload_buffer(Context& ctx, Commands& cmds, StagingArena& arena, const void* data,
                     std::size_t bytes, const char* name) {
    Buffer dst(ctx, bytes, MemoryUse::Device, name);
    write_pieces(ctx, cmds, arena, dst, {{data, bytes}}, name);
    return dst;
}

void write_pieces(Context& ctx, Commands& cmds, StagingArena& arena, const Buffer& dst,
                  std::initializer_list<UploadPiece> pieces, const char* name) {
    std::size_t bytes = 0;
    for (const UploadPiece& p : pieces) bytes += p.bytes;
    if (bytes == 0) return;
    if (bytes > dst.size())
        throw Error(ErrorCode::Internal, std::string("write_pieces: ") + name + " too small");
    const Buffer* write = &dst;
    if (!dst.host_visible()) {
        arena.buffers.emplace_back(ctx, bytes, MemoryUse::Upload, name);
        write = &arena.buffers.back();
    }
    auto* out = static_cast<unsigned char*>(write->mapped());
    for (const UploadPiece& p : pieces) {
        if (p.bytes > 0) std::memcpy(out, p.data, p.bytes);
        out += p.bytes;
    }
    write->flush();
    if (write != &dst) cmds.copy(*write, dst, bytes);
}

const Buffer& readback_buffer(Context& ctx, Commands& cmds, StagingArena& arena, const Buffer& src,
                              std::size_t bytes, const char* name) {
    if (src.host_visible()) return src;
    arena.buffers.emplace_back(ctx, bytes, MemoryUse::Readback, name);
    cmds.copy(src, arena.buffers.back(), bytes);
    return arena.buffers.back();
}

}  // namespace fdmsurf::detail
