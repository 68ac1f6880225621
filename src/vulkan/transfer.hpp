// Moving data between host and device buffers, with staging only where memory is not mappable.
#pragma once

#include <cstddef>
#include <memory>
#include <deque>
#include <initializer_list>

#include "vulkan/buffer.hpp"

namespace fdmsurf::detail {

class Commands;
class Context;

// Keeps staging buffers alive until the commands that use them have completed.
struct StagingArena {
    std::deque<Buffer> buffers;  // deque: references stay valid as it grows
    void clear() { buffers.clear(); }
};

// A device-local buffer holding `bytes` of `data`: written directly when the memory is
// host-visible, else through a staging buffer and a copy recorded into `cmds`.
Buffer upload_buffer(Context& ctx, Commands& cmds, StagingArena& arena, const void* data,
                     std::size_t bytes, const char* name);

// One piece of a gathered upload: `bytes` bytes from `data`.
struct UploadPiece {
    const void* data;
    std::size_t bytes;
};

// Writes `pieces` one after the other at the start of `dst` (a device buffer at least their
// size): directly when it is host-visible, else through a staging buffer and a recorded copy.
// No host copy of the whole.
void write_pieces(Context& ctx, Commands& cmds, StagingArena& arena, const Buffer& dst,
                  std::initializer_list<UploadPiece> pieces, const char* name);

// Records what is needed for reading `src` back after submission; returns the buffer to read
// (src itself when host-visible, else a readback copy kept in `arena`).
const Buffer& readback_buffer(Context& ctx, Commands& cmds, StagingArena& arena, const Buffer& src,
                              std::size_t bytes, const char* name);

}  // namespace fdmsurf::detail
