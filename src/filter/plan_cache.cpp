// VkFFT plan cache: entries are "FDMPLAN1", key length, key, payload length, payload, FNV-1a
// checksum of key and payload; anything else is a miss and gets rewritten.
#include "filter/plan_cache.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

namespace fdmsurf::detail {
namespace {
constexpr char kMagic[8] = {'F', 'D', 'M', 'P', 'L', 'A', 'N', '1'};
constexpr std::uint64_t kMaxPayload = 256ull << 20;
}  // namespace

std::uint64_t fnv1a64(const void* data, std::size_t bytes, std::uint64_t h) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

PlanCache::PlanCache(std::string directory) : directory_(std::move(directory)) {}

std::string PlanCache::default_directory() {
    if (const char* d = std::getenv("FDMSURF_CACHE_DIR"); d && *d)
        return std::string(d) == "off" ? std::string() : std::string(d);
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/fdmsurf";
    if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/fdmsurf";
    return {};
}

std::string PlanCache::path_for(const std::string& key) const {
    char name[64];
    std::snprintf(name, sizeof name, "vkfft-%016llx.bin",
                  static_cast<unsigned long long>(fnv1a64(key.data(), key.size())));
    return directory_ + "/" + name;
}

std::optional<std::vector<std::uint32_t>> PlanCache::load(const std::string& key) const {
    if (directory_.empty()) return std::nullopt;
    std::ifstream in(path_for(key), std::ios::binary);
    if (!in) return std::nullopt;
    char magic[8];
    std::uint64_t key_size = 0, payload_size = 0, checksum = 0;
    if (!in.read(magic, 8) || std::memcmp(magic, kMagic, 8) != 0) return std::nullopt;
    if (!in.read(reinterpret_cast<char*>(&key_size), 8) || key_size != key.size()) return std::nullopt;
    std::string stored(key_size, '\0');
    if (!in.read(stored.data(), static_cast<std::streamsize>(key_size)) || stored != key)
        return std::nullopt;
    if (!in.read(reinterpret_cast<char*>(&payload_size), 8) || payload_size == 0 ||
        payload_size > kMaxPayload || payload_size % 4 != 0)
        return std::nullopt;
    std::vector<std::uint32_t> payload(payload_size / 4);
    if (!in.read(reinterpret_cast<char*>(payload.data()), static_cast<std::streamsize>(payload_size)))
        return std::nullopt;
    if (!in.read(reinterpret_cast<char*>(&checksum), 8)) return std::nullopt;
    std::uint64_t h = fnv1a64(key.data(), key.size());
    h = fnv1a64(payload.data(), payload_size, h);
    if (h != checksum) return std::nullopt;
    return payload;
}

bool PlanCache::store(const std::string& key, const void* data, std::size_t bytes) const {
    if (directory_.empty() || bytes == 0 || bytes > kMaxPayload) return false;
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(directory_, ec);
    const std::string path = path_for(key);
    std::random_device rd;
    const std::string tmp = path + ".tmp" + std::to_string(rd());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return false;
        const std::uint64_t key_size = key.size(), payload_size = bytes;
        std::uint64_t h = fnv1a64(key.data(), key.size());
        h = fnv1a64(data, bytes, h);
        out.write(kMagic, 8);
        out.write(reinterpret_cast<const char*>(&key_size), 8);
        out.write(key.data(), static_cast<std::streamsize>(key.size()));
        out.write(reinterpret_cast<const char*>(&payload_size), 8);
        out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
        out.write(reinterpret_cast<const char*>(&h), 8);
        out.close();
        if (!out) {
            fs::remove(tmp, ec);
            return false;
        }
    }
    fs::rename(tmp, path, ec);
    if (!ec) return true;
    fs::remove(tmp, ec);
    return false;
}

}  // namespace fdmsurf::detail
