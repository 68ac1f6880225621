// On-disk cache of VkFFT plans (their compiled SPIR-V), keyed by grid size, device, driver and
// versions, so that a later run skips VkFFT's run-time GLSL compilation.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace fdmsurf::detail {

class PlanCache {
public:
    // `directory`: where entries live; empty disables the cache. The default directory is
    // $FDMSURF_CACHE_DIR, else $XDG_CACHE_HOME/fdmsurf, else $HOME/.cache/fdmsurf; setting
    // FDMSURF_CACHE_DIR to "off" disables it.
    explicit PlanCache(std::string directory);
    static std::string default_directory();

    // The payload stored under `key`, or nothing when absent, unreadable, truncated, of another
    // key (a hash collision), or failing its checksum: a bad entry is treated as a miss.
    std::optional<std::vector<std::uint32_t>> load(const std::string& key) const;
    // Stores atomically (temporary file and rename); true when the entry is in place. A failure
    // is never a reason to fail the run (the cache is an optimisation); `fdmsurf prepare` says so.
    bool store(const std::string& key, const void* data, std::size_t bytes) const;

    const std::string& directory() const { return directory_; }
    std::string path_for(const std::string& key) const;

private:
    std::string directory_;
};

std::uint64_t fnv1a64(const void* data, std::size_t bytes, std::uint64_t seed = 1469598103934665603ull);

}  // namespace fdmsurf::detail
