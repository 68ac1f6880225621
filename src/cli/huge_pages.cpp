// Transparent huge pages for the command-line program's memory (cli/huge_pages.hpp).
#include "cli/huge_pages.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#if defined(__linux__) && defined(__GLIBC__)
#include <gnu/libc-version.h>
#include <sys/auxv.h>
#include <unistd.h>
#endif

#include "base/trace.hpp"

namespace fdmsurf::cli {

namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kOwnAllocator = true;  // the sanitizer's allocator ignores glibc's tunables
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || \
    __has_feature(thread_sanitizer) || __has_feature(hwaddress_sanitizer)
constexpr bool kOwnAllocator = true;
#else
constexpr bool kOwnAllocator = false;
#endif
#else
constexpr bool kOwnAllocator = false;
#endif

constexpr const char* kTunable = "glibc.malloc.hugetlb";
// Set in the restarted program: it never restarts twice, whatever its loader did with
// GLIBC_TUNABLES (a secure-mode loader may drop it).
constexpr const char* kRestarted = "FDMSURF_HUGE_PAGES_RESTARTED";

// The kernel's mode, the bracketed word of transparent_hugepage/enabled ("always [madvise]
// never"), or "" when the file is absent.
std::string thp_mode() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string line;
    if (!std::getline(in, line)) return {};
    const auto open = line.find('['), close = line.find(']');
    if (open == std::string::npos || close == std::string::npos || close < open) return {};
    return line.substr(open + 1, close - open - 1);
}

}  // namespace

bool huge_pages_on_request() {
#if defined(__linux__) && defined(__GLIBC__)
    if (kOwnAllocator) return false;
    int major = 0, minor = 0;
    if (std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor) != 2 ||
        major * 100 + minor < 235)
        return false;  // no such tunable before glibc 2.35
    // "always": huge pages come without asking; "never" or no THP: asking gives nothing.
    return thp_mode() == "madvise";
#else
    return false;
#endif
}

void restart_with_huge_pages(char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
    if (!huge_pages_on_request()) return;
    if (std::getenv(kRestarted) != nullptr) return;
    if (const char* off = std::getenv("FDMSURF_HUGE_PAGES"); off && std::strcmp(off, "0") == 0)
        return;
    // setuid or file capabilities: the loader ignores GLIBC_TUNABLES there.
    if (getauxval(AT_SECURE) != 0) return;
    // Under valgrind /proc/self/exe is valgrind's own tool, and its malloc is not glibc's.
    if (const char* preload = std::getenv("LD_PRELOAD");
        preload && std::strstr(preload, "vgpreload") != nullptr)
        return;
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (tunables && std::strstr(tunables, kTunable)) return;  // set already: the user's choice
    const std::string before = tunables ? tunables : "";
    const std::string value = (before.empty() ? "" : before + ":") + kTunable + "=1";
    if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0 || setenv(kRestarted, "1", 1) != 0)
        return;
    detail::trace(("huge pages: restarting with GLIBC_TUNABLES=" + value).c_str());
    execv("/proc/self/exe", argv);
    // Not restarted (no /proc, or exec refused): go on as we are, the environment as it was.
    const int error = errno;
    if (tunables)
        setenv("GLIBC_TUNABLES", before.c_str(), 1);
    else
        unsetenv("GLIBC_TUNABLES");
    unsetenv(kRestarted);
    detail::trace((std::string("huge pages: restart failed: ") + std::strerror(error)).c_str());
#else
    (void)argv;
#endif
}

}  // namespace fdmsurf::cli
