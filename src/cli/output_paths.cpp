#include "cli/output_paths.hpp"

#include <unistd.h>

#include <climits>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "io/atomic_file.hpp"

namespace fdmsurf::cli {

bool written_through(const std::string& path) {
    return path == "-" || path.starts_with("/dev/") || path.starts_with("/proc/");
}

std::string output_path_problem(const std::string& given) {
    namespace fs = std::filesystem;
    if (written_through(given)) return {};
    const std::string head = "cannot write '" + given + "': ";
    // Where the file will be written: through symbolic links, as AtomicFile follows them (a link
    // to a file not made yet included).
    int link_error = 0;
    const std::string path = detail::follow_links(given, link_error);
    if (link_error != 0) return head + std::strerror(link_error);
    if (path != given && written_through(path)) return {};
    std::error_code ec;
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty() && !fs::is_directory(parent, ec)) {
        return head + "'" + parent.string() +
               (fs::exists(parent, ec) ? "' is not a folder" : "' does not exist");
    }
    if (fs::is_directory(path, ec)) return head + "it is a folder";
    const std::string name = fs::path(path).filename().string();
    long limit = ::pathconf(parent.empty() ? "." : parent.c_str(), _PC_NAME_MAX);
    if (limit <= 0) limit = NAME_MAX;
    if (name.size() > static_cast<std::size_t>(limit)) {
        return head + "its name is " + std::to_string(name.size()) +
               " bytes long; the file system allows " + std::to_string(limit);
    }
    return {};
}

std::string output_identity(const std::string& given) {
    namespace fs = std::filesystem;
    int link_error = 0;
    const std::string path = detail::follow_links(given, link_error);
    std::error_code ec;
    const fs::path absolute = fs::absolute(path, ec);
    if (ec) return path;
    const fs::path resolved = fs::weakly_canonical(absolute, ec);
    return (ec ? absolute : resolved).lexically_normal().string();
}

}  // namespace fdmsurf::cli
