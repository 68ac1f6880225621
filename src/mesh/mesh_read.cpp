// read_mesh: loads a file and hands its bytes to the PLY or OBJ parser.
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_io.hpp"

namespace fdmsurf {
namespace detail {
namespace {

std::string read_file(const std::string& path) {
    auto fail = [&path](int error_number) {
        return Error(ErrorCode::Io, "cannot read " + path + ": " + std::strerror(error_number));
    };
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                         &std::fclose);
    if (!file) throw fail(errno);
    std::string data;
    std::error_code size_error;
    const auto size = std::filesystem::file_size(path, size_error);
    if (!size_error) data.reserve(size);
    errno = 0;
    char chunk[1 << 16];
    std::size_t n;
    while ((n = std::fread(chunk, 1, sizeof chunk, file.get())) > 0) data.append(chunk, n);
    if (std::ferror(file.get())) throw fail(errno != 0 ? errno : EIO);
    return data;
}

bool starts_with_ply_magic(std::string_view data) {
    return data.starts_with("ply\n") || data.starts_with("ply\r\n");
}

}  // namespace

std::string lowercase_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace detail

Mesh read_mesh(const std::string& path) {
    const std::string data = detail::read_file(path);
    // PLY announces itself; OBJ has no magic, so it is recognised by its extension.
    if (detail::starts_with_ply_magic(data)) return detail::parse_ply(data, path);
    if (detail::lowercase_extension(path) == ".obj") return detail::parse_obj(data, path);
    throw Error(ErrorCode::Format, path + ": not a PLY file, nor named .obj");
}

}  // namespace fdmsurf
