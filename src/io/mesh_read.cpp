// read_mesh: loads a file and hands its bytes to the parser of its format.
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "io/formats.hpp"
#include "io/mesh_io.hpp"

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

std::optional<Mesh> parse_mesh_data(std::string_view data, const std::string& path,
                                    const std::string& extension) {
    // PLY and GLB announce themselves; OBJ and STL have no magic.
    if (starts_with_ply_magic(data)) return parse_ply(data, path);
    if (is_glb(data)) return parse_glb(data, path);
    if (extension == ".obj") return parse_obj(data, path);
    if (extension == ".stl") return parse_stl(data, path);
    if (extension == ".off") return parse_off(data, path);
    if (extension == ".glb") return parse_glb(data, path);
    // Under another name: OFF by its first word, STL by its size or its text.
    const std::size_t start = data.find_first_not_of(" \t\r\n");
    if (start != std::string_view::npos) {
        const std::string_view head =
            data.substr(start, data.find_first_of(" \t\r\n", start) - start);
        if (head.find("OFF") != std::string_view::npos) return parse_off(data, path);
    }
    if (is_binary_stl(data) || is_ascii_stl(data)) return parse_stl(data, path);
    return std::nullopt;
}

}  // namespace detail

Mesh read_mesh(const std::string& path) {
    const std::string data = detail::read_file(path);
    if (auto mesh = detail::parse_mesh_data(data, path, detail::lowercase_extension(path))) {
        return std::move(*mesh);
    }
    throw Error(ErrorCode::Format,
                path + ": not a mesh file read_mesh reads (PLY, OBJ, GLB, STL or OFF)");
}

}  // namespace fdmsurf
