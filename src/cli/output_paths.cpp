#include "cli/output_paths.hpp"

#include <unistd.h>

#include <climits>
#include <filesystem>
#include <system_error>

namespace fdmsurf::cli {

std::string output_path_problem(const std::string& path) {
    namespace fs = std::filesystem;
    if (path == "-" || path.starts_with("/dev/") || path.starts_with("/proc/")) return {};
    std::error_code ec;
    const fs::path parent = fs::path(path).parent_path();
    const std::string head = "cannot write '" + path + "': ";
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

}  // namespace fdmsurf::cli
