// Getting structure text: file reading, gunzip, sanity checks, format detection, line helpers.
#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>

#if __has_include(<sys/mman.h>)
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#define FDMSURF_MAP_FILES 1
#endif

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "base/decimal.hpp"
#include "io/gzip_input.hpp"
#include "structure/detail.hpp"

namespace fdmsurf::detail {

namespace {

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

bool ends_with(std::string_view s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

bool istarts_with(std::string_view s, std::string_view prefix) {
    return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

std::string read_bytes(const std::string& path) {
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (std::filesystem::is_directory(status))
        throw Error(ErrorCode::Io, path + ": cannot open (it is a directory)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorCode::Io, path + ": cannot open (" + std::strerror(errno) + ")");
    std::string bytes;
    // A regular file's size up front: one allocation, no copies as the string grows (a pipe
    // or a special file has no size and grows as before).
    const std::uintmax_t size =
        std::filesystem::is_regular_file(status) ? std::filesystem::file_size(path, ec) : 0;
    if (!ec && size > 0) bytes.reserve(static_cast<std::size_t>(size));
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0)
        bytes.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (in.bad()) throw Error(ErrorCode::Io, path + ": read error");
    return bytes;
}

// Own inflate loop (io/gzip_input) rather than gemmi's MaybeGzipped: gzread treats a stream that
// ends early as a short file, and we want "truncated" to be an error, not a silently shorter
// structure.
std::string gunzip_or_fail(std::string_view gz, const std::string& name) {
    std::string out;
    GzipProblem problem;
    if (gunzip(gz, out, problem)) return out;
    switch (problem.kind) {
        case GzipProblem::Kind::Setup:
            throw Error(ErrorCode::Internal, name + ": zlib inflateInit2 failed");
        case GzipProblem::Kind::OutOfMemory:
            throw std::bad_alloc();
        case GzipProblem::Kind::Truncated:
            fail_format(name + ": truncated gzip stream (the compressed data ends early)");
        default:  // Corrupt, Refused
            break;
    }
    fail_format(name + ": corrupt gzip data (" +
                (problem.zlib_message.empty() ? "inflate failed" : problem.zlib_message) + ")");
}

bool is_text_byte(unsigned char c) {
    return c >= 0x20 ? c != 0x7f && c < 0x80
                     : (c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f');
}

StructureFormat format_from_name(const std::string& name) {
    std::string n = lower(name);
    if (ends_with(n, ".gz")) n.resize(n.size() - 3);
    if (ends_with(n, ".pdb") || ends_with(n, ".ent")) return StructureFormat::Pdb;
    if (ends_with(n, ".cif") || ends_with(n, ".mmcif")) return StructureFormat::Mmcif;
    if (ends_with(n, ".pqr")) return StructureFormat::Pqr;
    if (ends_with(n, ".xyzr")) return StructureFormat::Xyzr;
    if (ends_with(n, ".xyzrn")) return StructureFormat::Xyzrn;
    return StructureFormat::Auto;
}

// XYZRN: four numbers, then fields of which the last is not a number (the atom name). No PDB,
// mmCIF or PQR line starts with four numbers.
bool is_xyzrn_line(std::string_view line) {
    std::vector<std::string_view> f = split_fields(line);
    if (f.size() < 5) return false;
    double value = 0.0;
    for (std::size_t i = 0; i < 4; ++i)
        if (parse_number(f[i], value) != NumberStatus::Ok) return false;
    return parse_number(f.back(), value) == NumberStatus::NotNumber;
}

// XYZR: exactly four numbers.
bool is_xyzr_line(std::string_view line) {
    std::vector<std::string_view> f = split_fields(line);
    if (f.size() != 4) return false;
    double value = 0.0;
    for (std::string_view field : f)
        if (parse_number(field, value) != NumberStatus::Ok) return false;
    return true;
}

// An ATOM/HETATM line of PQR rather than PDB. PDB's fixed columns end in occupancy (55-60) and
// B-factor (61-66) as %6.2f, often followed by the element; PQR's whitespace-separated fields
// end in charge and radius, both numbers, written with other widths (pdb2pqr: %7.4f %6.4f).
bool is_pqr_atom_line(std::string_view line) {
    std::vector<std::string_view> f = split_fields(line);
    double value = 0.0;
    if (f.size() < 10 || parse_number(f.back(), value) != NumberStatus::Ok ||
        parse_number(f[f.size() - 2], value) != NumberStatus::Ok)
        return false;  // the last field is an element or a charge like "1+": PDB
    auto pdb_number = [&](std::size_t start) {  // %6.2f at columns start+1 .. start+6
        return line.size() >= start + 6 && line[start + 3] == '.' &&
               parse_number(trim(line.substr(start, 6)), value) == NumberStatus::Ok;
    };
    const bool pdb_columns = pdb_number(54) && (line.size() < 66 || pdb_number(60));
    return !pdb_columns;
}

StructureFormat format_from_content(std::string_view text) {
    LineReader lines(text);
    std::string_view line;
    bool first = true;
    while (lines.next(line)) {
        std::string_view t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        // mmCIF: the first real line opens a data block.
        if (first && istarts_with(t, "data_")) return StructureFormat::Mmcif;
        if (first && is_xyzrn_line(t)) return StructureFormat::Xyzrn;
        if (first && is_xyzr_line(t)) return StructureFormat::Xyzr;
        first = false;
        if (line.starts_with("ATOM") || line.starts_with("HETATM"))
            return is_pqr_atom_line(line) ? StructureFormat::Pqr : StructureFormat::Pdb;
        if (line.starts_with("HEADER")) return StructureFormat::Pdb;
    }
    return StructureFormat::Auto;
}

}  // namespace

void fail_format(const std::string& message) { throw Error(ErrorCode::Format, message); }

std::string at_line(std::size_t line) { return " at line " + std::to_string(line); }

std::string load_file(const std::string& path) { return decompress(read_bytes(path), path); }

FileText::FileText(const std::string& path) {
#ifdef FDMSURF_MAP_FILES
    // Only a regular file is opened here: opening a named pipe would wait for its writer, and
    // closing it again would cut that writer off.
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd >= 0 && ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
            int flags = MAP_PRIVATE;
#ifdef MAP_POPULATE
            flags |= MAP_POPULATE;  // the page cache's pages mapped in one call, not a fault each
#endif
            void* map = ::mmap(nullptr, std::size_t(st.st_size), PROT_READ, flags, fd, 0);
            if (map != MAP_FAILED) {
                map_ = map;
                map_size_ = std::size_t(st.st_size);
                text_ = std::string_view(static_cast<const char*>(map), map_size_);
            }
        }
        if (fd >= 0) ::close(fd);
    }
    if (map_ && !is_gzip(text_)) return;
    if (map_) {
        owned_ = decompress(std::string(text_), path);
        ::munmap(map_, map_size_);
        map_ = nullptr;
        text_ = owned_;
        return;
    }
#endif
    // Not mapped (not a regular file, empty, or an error that load_file reports).
    owned_ = load_file(path);
    text_ = owned_;
}

FileText::~FileText() {
#ifdef FDMSURF_MAP_FILES
    if (map_) ::munmap(map_, map_size_);
#endif
}

std::string decompress(std::string bytes, const std::string& name) {
    return is_gzip(bytes) ? gunzip_or_fail(bytes, name) : bytes;
}

void check_text(std::string_view data, const std::string& name) {
    if (data.empty()) fail_format(name + ": empty file");
    if (is_gzip(data))
        fail_format(name +
                    " is not a text structure file (gzip-compressed data; read the file "
                    "with read_structure, which decompresses it)");
    // A NUL anywhere would also cut C-string based parsing short, so it is rejected outright.
    bool binary = std::memchr(data.data(), '\0', data.size()) != nullptr;
    std::string_view head = data.substr(0, 4096);
    auto non_text = std::count_if(head.begin(), head.end(), [](char c) {
        return !is_text_byte(static_cast<unsigned char>(c));
    });
    // Bytes >= 0x80 count as non-text, so the threshold leaves room for UTF-8 in a header.
    if (binary || non_text * 10 > static_cast<long>(head.size()))
        fail_format(name + " is not a text structure file (binary data)");
    if (trim(data).empty()) fail_format(name + ": empty file (only white space)");
}

StructureFormat detect_format(std::string_view text, const std::string& name) {
    StructureFormat format = format_from_name(name);
    if (format == StructureFormat::Auto) format = format_from_content(text);
    if (format == StructureFormat::Auto)
        fail_format(name + ": unknown format (expected .pdb, .cif, .pqr, .xyzr or .xyzrn)");
    return format;
}

bool LineReader::next(std::string_view& line) {
    if (done_ || rest_.empty()) return false;
    std::size_t end = rest_.find('\n');
    if (end == std::string_view::npos) {
        line = rest_;
        rest_ = {};
        done_ = true;
    } else {
        line = rest_.substr(0, end);
        rest_.remove_prefix(end + 1);
    }
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++number_;
    return true;
}

std::vector<std::string_view> split_fields(std::string_view line) {
    std::vector<std::string_view> fields;
    split_fields(line, fields);
    return fields;
}

void split_fields_plain(std::string_view line, std::vector<std::string_view>& fields) {
    fields.clear();
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        std::size_t start = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (i > start) fields.push_back(line.substr(start, i - start));
    }
}

namespace {

#if defined(__SSE2__)
// split_fields of an ASCII line shorter than 128 bytes, 16 bytes a step: a bit mask of its white
// space, whose edges are the fields' starts and ends (a branch per field, not two per byte: the
// PQR and XYZRN readers' hot loop). False, `fields` untouched, for any other line.
bool split_ascii_fields(std::string_view line, std::vector<std::string_view>& fields) {
    constexpr std::size_t kBytes = 128;
    if (line.size() >= kBytes) return false;
    alignas(16) char padded[kBytes];
    std::memset(padded, ' ', kBytes);  // past the line: white space, which ends its last field
    if (!line.empty()) std::memcpy(padded, line.data(), line.size());  // data() may be null
    std::uint64_t space[2] = {0, 0};
    unsigned high = 0;
    for (std::size_t b = 0; b < kBytes / 16; ++b) {
        const __m128i v = _mm_load_si128(reinterpret_cast<const __m128i*>(padded + 16 * b));
        // ' ', or '\t' to '\r' (c - 9 <= 4 unsigned, as a signed compare after adding 128 - 9)
        const __m128i blank = _mm_cmpeq_epi8(v, _mm_set1_epi8(' '));
        const __m128i control = _mm_cmplt_epi8(_mm_add_epi8(v, _mm_set1_epi8(char(128 - 9))),
                                               _mm_set1_epi8(char(-128 + 5)));
        const auto mask = std::uint64_t(unsigned(_mm_movemask_epi8(_mm_or_si128(blank, control))));
        space[b / 4] |= mask << (16 * (b % 4));
        high |= unsigned(_mm_movemask_epi8(v));
    }
    if (high != 0) return false;  // bytes from 0x80: white space as the locale says
    std::size_t start[kBytes / 2], end[kBytes / 2], starts = 0, ends = 0;
    std::uint64_t carry = 0;  // whether the previous word's last byte is in a field
    for (std::size_t w = 0; w < 2; ++w) {
        const std::uint64_t word = ~space[w];
        const std::uint64_t before = (word << 1) | carry;
        for (std::uint64_t s = word & ~before; s != 0; s &= s - 1)
            start[starts++] = 64 * w + std::size_t(std::countr_zero(s));
        for (std::uint64_t e = ~word & before; e != 0; e &= e - 1)
            end[ends++] = 64 * w + std::size_t(std::countr_zero(e));
        carry = word >> 63;
    }
    fields.clear();
    for (std::size_t k = 0; k < starts; ++k)
        fields.push_back(line.substr(start[k], end[k] - start[k]));
    return true;
}
#else
bool split_ascii_fields(std::string_view, std::vector<std::string_view>&) { return false; }
#endif

}  // namespace

void split_fields(std::string_view line, std::vector<std::string_view>& fields) {
    if (!split_ascii_fields(line, fields)) split_fields_plain(line, fields);
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const auto x = static_cast<unsigned char>(a[i]), y = static_cast<unsigned char>(b[i]);
        if (x == y) continue;
        // ASCII letters fold as the C locale folds them, without std::tolower's call; other
        // bytes as the locale says.
        if (x < 0x80 && y < 0x80) {
            if ((x | 0x20) != (y | 0x20) || (x | 0x20) < 'a' || (x | 0x20) > 'z') return false;
        } else if (std::tolower(x) != std::tolower(y)) {
            return false;
        }
    }
    return true;
}

NumberStatus parse_number(std::string_view s, double& value) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
    if (s.empty()) return NumberStatus::NotNumber;
    // Always finite, and within float's range: |m x 10^e| < 2^53 x 10^22.
    if (parse_decimal_fast(s, value)) return NumberStatus::Ok;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (end != s.data() + s.size()) return NumberStatus::NotNumber;
    if (ec == std::errc::result_out_of_range) return NumberStatus::OutOfRange;
    if (ec != std::errc()) return NumberStatus::NotNumber;
    // from_chars accepts "nan" and "inf": numbers, but not usable ones.
    if (!std::isfinite(value)) return NumberStatus::NotFinite;
    return std::isfinite(static_cast<float>(value)) ? NumberStatus::Ok : NumberStatus::OutOfRange;
}

std::string number_problem(NumberStatus status, const std::string& what, std::string_view field) {
    std::string quoted = " '" + std::string(field) + "'";
    switch (status) {
        case NumberStatus::NotNumber:
            return "non-numeric " + what + quoted;
        case NumberStatus::NotFinite:
            return "NaN or infinite " + what + quoted;
        case NumberStatus::OutOfRange:
            return what + quoted + " out of range";
        case NumberStatus::Ok:
            break;
    }
    return what + quoted;
}

}  // namespace fdmsurf::detail
