// PDB text made readable for gemmi: checked coordinates, overflowed fields, models in file order,
// unreadable charges and short connection records, each rewritten with a warning or refused.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <set>

#include "structure/detail.hpp"

namespace fdmsurf::detail {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_letter(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }

// gemmi matches record names case-insensitively on their first four letters.
bool record_is(std::string_view line, std::string_view four) {
    return line.size() >= 4 && iequals(line.substr(0, 4), four);
}


// Hybrid-36 (gemmi reads it): `width` digits, then upper-case base 36 from A000 (10000) or
// A0000 (100000) on; "" beyond its range.
std::string hybrid36(long value, int width) {
    long decimal_limit = width == 4 ? 10000 : 100000;
    if (value < decimal_limit) {
        char out[16];
        std::snprintf(out, sizeof out, "%*ld", width, value);
        return std::string(out).size() == static_cast<std::size_t>(width) ? out : "";
    }
    long first = width == 4 ? 10L * 36 * 36 * 36 : 10L * 36 * 36 * 36 * 36;  // "A000", "A0000"
    long n = value - decimal_limit + first;
    std::string out(static_cast<std::size_t>(width), '0');
    for (int i = width - 1; i >= 0; --i, n /= 36) {
        long d = n % 36;
        out[static_cast<std::size_t>(i)] = static_cast<char>(d < 10 ? '0' + d : 'A' + d - 10);
    }
    return n == 0 ? out : "";
}

// A coordinate as %8.3f writers give it: [-]digits.ddd; `pos` moves past it. Fields that run
// together ("-1000.000-1000.000", "1999.3232998.770") are told apart by the three decimals.
bool coordinate_token(std::string_view s, std::size_t& pos, double& value) {
    while (pos < s.size() && s[pos] == ' ') ++pos;
    std::size_t start = pos, i = pos;
    if (i < s.size() && s[i] == '-') ++i;
    std::size_t digits = i;
    while (i < s.size() && is_digit(s[i])) ++i;
    if (i == digits || i >= s.size() || s[i] != '.') return false;
    ++i;
    for (int k = 0; k < 3; ++k, ++i)
        if (i >= s.size() || !is_digit(s[i])) return false;
    if (parse_number(s.substr(start, i - start), value) != NumberStatus::Ok) return false;
    pos = i;
    return true;
}

// 8 columns for gemmi: %8.3f, or fewer decimals where the number needs the room.
std::string coordinate_field(double value) {
    char out[32];
    for (int decimals = 3; decimals >= 0; --decimals) {
        std::snprintf(out, sizeof out, "%8.*f", decimals, value);
        if (std::string_view(out).size() == 8) return out;
    }
    return "";
}

bool standard_coordinates(std::string_view line) {
    if (line.size() < 54) return false;
    for (int i = 0; i < 3; ++i) {
        double value = 0.0;
        if (parse_number(trim(line.substr(30 + 8 * i, 8)), value) != NumberStatus::Ok) return false;
    }
    return true;
}

// A record whose fields overflowed their columns, as MD programs write them: a serial past
// 99999 or a residue number past 9999 that shifts the rest of the line right, coordinates
// that need more than 8 columns and run into the next. Returns the record in the standard
// columns (hybrid-36 serial and residue number, coordinates in 8 columns), or "" when the
// fields do not have the record's shape: serial, then columns 12-22 as they stand, residue
// number and insertion code, three coordinates of three decimals, and white space or nothing
// after them.
std::string realign_record(std::string_view record) {
    if (record.size() < 27) return "";
    // Serial: digits from column 7; more than five push the line right.
    std::size_t i = 6;
    while (i < record.size() && record[i] == ' ') ++i;
    std::size_t serial_start = i;
    while (i < record.size() && is_digit(record[i])) ++i;
    if (record.size() > 11 && record[11] == ' ' && (i < 11 || record[i] != ' '))
        i = 11;  // a serial in its columns (hybrid-36 too)
    else if (i >= record.size() || record[i] != ' ')
        return "";
    std::string serial(record.substr(6, 5));
    if (i > 11) {
        if (i - serial_start > 9) return "";
        serial = hybrid36(std::stol(std::string(record.substr(serial_start, i - serial_start))), 5);
        if (serial.empty()) serial = "*****";  // informative only; gemmi reads it as 0
    }
    // The record with its serial in columns 7-11: columns 12-22 are where they belong.
    const std::string shifted =
        std::string(record.substr(0, 6)) + serial + std::string(record.substr(std::max<std::size_t>(i, 11)));
    std::string_view line = shifted;
    // Residue number from column 23, up to nine digits, then an insertion code or a space.
    std::string_view head = line.substr(0, 22);
    std::size_t j = 22;
    while (j < line.size() && j < 26 && line[j] == ' ') ++j;
    std::size_t number_start = j;
    if (j < line.size() && line[j] == '-') ++j;
    while (j < line.size() && is_digit(line[j])) ++j;
    if (j == number_start || j - number_start > 9 || j >= line.size()) return "";
    long number = std::stol(std::string(line.substr(number_start, j - number_start)));
    char icode = ' ';
    if (is_letter(line[j]))
        icode = line[j++];
    else if (line[j] != ' ')
        return "";
    std::string residue = number < 0 ? std::to_string(number) : hybrid36(number, 4);
    if (residue.empty() || residue.size() > 4) return "";
    if (residue.size() < 4) residue.insert(0, 4 - residue.size(), ' ');
    std::string out = std::string(head) + residue + icode + "   ";
    std::size_t pos = j;
    for (int k = 0; k < 3; ++k) {
        double value = 0.0;
        if (!coordinate_token(line, pos, value)) return "";
        std::string field = coordinate_field(value);
        if (field.empty()) return "";
        out += field;
    }
    if (pos < line.size() && !is_space(line[pos])) return "";
    out += line.substr(pos);
    return out;
}

bool is_integer(std::string_view s) {
    std::size_t i = !s.empty() && s[0] == '-' ? 1 : 0;
    if (i == s.size() || s.size() - i > 9) return false;
    for (; i < s.size(); ++i)
        if (!is_digit(s[i])) return false;
    return true;
}

bool is_decimal(std::string_view s, double& value) {
    return s.find('.') != std::string_view::npos &&
           parse_number(s, value) == NumberStatus::Ok;
}

bool is_word(std::string_view s, std::size_t most) {
    if (s.empty() || s.size() > most) return false;
    for (char c : s)
        if (!is_letter(c) && !is_digit(c) && c != '\'' && c != '*' && c != '+' && c != '-' &&
            c != '_')
            return false;
    return true;
}

// A record written in free format, its fields separated by spaces or tabs without regard to
// PDB's columns (APBS's examples, some converters): "ATOM serial name resName [chain]
// resSeq[icode] x y z [occupancy [B [element]]]", the coordinates three numbers with a decimal
// point and as many decimals each. Returns it in the standard columns, or "" when the fields do not have that shape.
std::string free_format_record(std::string_view line) {
    std::vector<std::string_view> f = split_fields(line);
    if (f.size() < 8 || (!iequals(f[0], "ATOM") && !iequals(f[0], "HETATM"))) return "";
    // The coordinates: the first three decimal numbers in a row after name, residue and number.
    std::size_t c = 0;
    double xyz[3] = {0, 0, 0};
    for (std::size_t k = 5; k + 2 < f.size() && c == 0; ++k)
        if (is_decimal(f[k], xyz[0]) && is_decimal(f[k + 1], xyz[1]) &&
            is_decimal(f[k + 2], xyz[2]))
            c = k;
    if (c == 0 || (c != 5 && c != 6) || !is_integer(f[1])) return "";
    // A writer gives the three coordinates the same number of decimals: a record with a blank
    // coordinate column would otherwise take its occupancy for z.
    auto decimals = [](std::string_view v) { return v.size() - v.find('.'); };
    if (decimals(f[c]) != decimals(f[c + 1]) || decimals(f[c]) != decimals(f[c + 2])) return "";
    std::string_view name = f[2], residue = f[3], chain = c == 6 ? f[4] : "";
    std::string_view number = f[c - 1];
    char icode = ' ';
    if (!number.empty() && is_letter(number.back())) icode = number.back(), number.remove_suffix(1);
    if (!is_word(name, 4) || !is_word(residue, 4) || chain.size() > 1 || !is_integer(number) ||
        std::stol(std::string(number)) > 9999 || std::stol(std::string(number)) < -999)
        return "";
    double occupancy = 1.0, b = 0.0;
    std::size_t k = c + 3;
    if (k < f.size() && is_decimal(f[k], occupancy)) ++k;
    if (k < f.size() && is_decimal(f[k], b)) ++k;
    std::string element = k < f.size() && is_word(f[k], 2) && is_letter(f[k][0])
                              ? std::string(f[k]) : "";
    std::string serial = hybrid36(std::stol(std::string(f[1])), 5);
    // Names shorter than four characters start in column 14, so that gemmi takes the element
    // from the name as it does for a standard file (" CA " carbon, "CA  " calcium).
    std::string name_field(name);
    if (name_field.size() < 4) name_field.insert(name_field.begin(), ' ');
    // The residue name right-aligned in columns 18-20 (a fourth character takes column 21).
    std::string residue_field(residue);
    if (residue_field.size() < 3) residue_field.insert(0, 3 - residue_field.size(), ' ');
    if (residue_field.size() < 4) residue_field += ' ';
    char out[128];
    std::snprintf(out, sizeof out, "%-6s%5s %-4s %4s%c%4s%c   ",
                  iequals(f[0], "ATOM") ? "ATOM" : "HETATM", serial.empty() ? "*****" : serial.c_str(),
                  name_field.c_str(), residue_field.c_str(), chain.empty() ? ' ' : chain[0],
                  std::string(number).c_str(), icode);
    std::string record = out;
    for (double v : xyz) {
        std::string field = coordinate_field(v);
        if (field.empty()) return "";
        record += field;
    }
    occupancy = std::clamp(occupancy, -99.99, 999.99), b = std::clamp(b, -99.99, 999.99);
    std::snprintf(out, sizeof out, "%6.2f%6.2f          %2s", occupancy, b, element.c_str());
    return record + out;
}

// Columns 23-27 all digits and a blank column 28: a five-digit residue number written over the
// insertion code, the rest of the line in its columns (VMD's way). gemmi would read residue 1000
// with insertion code '0'.
bool residue_over_insertion_code(std::string_view line) {
    if (line.size() < 31) return false;
    for (std::size_t k = 22; k < 27; ++k)
        if (!is_digit(line[k])) return false;
    return line[27] == ' ';
}

// gemmi 0.5.7 refuses a charge (columns 79-80) of a digit and anything but a sign or a space
// ("Wrong format for charge"): the segment ids and other text of old-format files.
bool unreadable_charge(std::string_view line) {
    char digit = line.size() > 78 ? line[78] : ' ', sign = line.size() > 79 ? line[79] : ' ';
    if (is_digit(sign)) std::swap(digit, sign);
    return is_digit(digit) && sign != '+' && sign != '-' && !is_space(sign);
}

// gemmi 0.5.7 reads a LINK or SSBOND record's distance or link id (columns 73-80) once the
// line, as it keeps it (with its "\n" or "\r\n", up to its first NUL byte), is longer than 73
// characters: past the end of a line shorter than 80 (found by fuzz_pdb twice: a heap-buffer
// overflow). Those lines are given to gemmi without NUL bytes (spaces instead) and padded with
// spaces to 80 columns (spaces read as no distance, as in a line that stops at column 72).
bool short_connection_record(std::string_view line) {
    return (record_is(line, "LINK") || record_is(line, "SSBO")) &&
           ((line.size() >= 72 && line.size() < 80) || line.find('\0') != std::string_view::npos);
}

// gemmi 0.5.7 keeps the first 120 characters of a line and skips the rest up to the newline,
// but its skipping stops at a byte >= 0x80 (its getc returns a signed char): it then reads what
// follows that byte as a line of its own, a record this pass never sees (found by fuzz_pdb: a
// LINK record of 73 columns hidden so, a third heap-buffer overflow). Such a line is cut at 120
// characters, which is all of it that gemmi means to read.
constexpr std::size_t kGemmiLineLength = 120;
bool gemmi_splits(std::string_view line) {
    if (line.size() <= kGemmiLineLength) return false;
    const std::string_view tail = line.substr(kGemmiLineLength);
    return std::any_of(tail.begin(), tail.end(),
                       [](char c) { return static_cast<unsigned char>(c) >= 0x80; });
}

// The model records as gemmi takes them: true when a MODEL number repeats or a MODEL follows a
// model with atoms and no ENDMDL, two things gemmi refuses.
bool models_need_order(std::string_view text) {
    std::set<std::string> numbers;
    bool open = false, atoms = false;
    LineReader lines(text);
    std::string_view line;
    while (lines.next(line)) {
        if (is_end_record(line)) break;
        if (record_is(line, "MODE")) {
            if (open && atoms) return true;
            if (!numbers.insert(std::string(trim(line.size() > 10 ? line.substr(10, 4) : ""))).second)
                return true;
            open = true, atoms = false;
        } else if (record_is(line, "ENDM")) {
            open = false;
        } else if (is_atom_record(line)) {
            if (!open) {
                // gemmi names a model without MODEL by its position: a later MODEL of that
                // number collides.
                numbers.insert(std::to_string(numbers.size() + 1));
                open = true;
            }
            atoms = true;
        }
    }
    return false;
}

// The first line and count of one kind of fix, for its warning.
struct Fixes {
    std::size_t count = 0, first_line = 0;
    std::string first;
    void add(std::size_t line, std::string what = "") {
        if (count++ == 0) first_line = line, first = std::move(what);
    }
    std::string more() const {
        return count > 1 ? " (and " + std::to_string(count - 1) + " more)" : "";
    }
};

[[noreturn]] void fail_coordinates(std::string_view line, std::size_t number,
                                   const std::string& name) {
    static const char* const kAxis[] = {"x", "y", "z"};
    std::string record = record_is(line, "ATOM") ? "ATOM" : "HETATM";
    if (line.size() < 54)
        fail_format(name + ": truncated " + record + " record" + at_line(number) + " (" +
                    std::to_string(line.size()) + " columns; x, y, z need columns 31-54)");
    for (int i = 0; i < 3; ++i) {
        std::string_view field = line.substr(30 + 8 * i, 8);
        double value = 0.0;
        NumberStatus status = parse_number(trim(field), value);
        if (status != NumberStatus::Ok)
            fail_format(name + ": " +
                        number_problem(status, std::string(kAxis[i]) + " coordinate", field) +
                        " (columns " + std::to_string(31 + 8 * i) + "-" +
                        std::to_string(38 + 8 * i) + ")" + at_line(number));
    }
    fail_format(name + ": unreadable " + record + " record" + at_line(number));
}

}  // namespace

bool is_atom_record(std::string_view line) {
    return record_is(line, "ATOM") || record_is(line, "HETA");
}

bool is_end_record(std::string_view line) {
    return line.size() >= 3 && iequals(line.substr(0, 3), "END") &&
           (line.size() == 3 || is_space(line[3]));
}

std::string prepare_pdb_text(std::string_view text, const std::string& name,
                             std::vector<std::string>& warnings) {
    const bool order_models = models_need_order(text);
    Fixes realigned, free_format, charges, repeated, unclosed;
    bool changed = false, ended = false, open = false, atoms = false;
    int ordinal = 0;
    std::set<std::string> numbers;
    // The rewritten text is built from the first line that changes on (or from the top when the
    // models are renumbered): most files need no change, and then no copy of them is made.
    std::string out;
    bool copying = order_models;
    auto start_copy = [&](const char* line_start) {
        out.reserve(text.size() + 1024);
        LineReader before(text.substr(0, std::size_t(line_start - text.data())));
        std::string_view l;
        while (before.next(l)) out.append(l).push_back('\n');
        copying = true;
    };
    if (copying) out.reserve(text.size() + 1024);
    LineReader lines(text);
    std::string_view line;
    while (lines.next(line)) {
        std::string fixed;
        const bool cut = !ended && gemmi_splits(line);
        if (cut) line = line.substr(0, kGemmiLineLength);
        if (ended) {
            // gemmi stops at END; what follows is passed on as it is.
        } else if (is_end_record(line)) {
            ended = true;
        } else if (is_atom_record(line)) {
            std::string_view record = line;
            if (!standard_coordinates(line)) {
                fixed = realign_record(line);
                if (!fixed.empty() && standard_coordinates(fixed)) {
                    realigned.add(lines.number());
                } else {
                    fixed = free_format_record(line);
                    if (fixed.empty() || !standard_coordinates(fixed))
                        fail_coordinates(line, lines.number(), name);
                    free_format.add(lines.number());
                }
                record = fixed;
            } else if (residue_over_insertion_code(line)) {
                fixed = realign_record(std::string(line.substr(0, 27)) + " " +
                                       std::string(line.substr(27)));
                if (fixed.empty()) fail_coordinates(line, lines.number(), name);
                realigned.add(lines.number());
                record = fixed;
            }
            if (unreadable_charge(record)) {
                if (fixed.empty()) fixed = std::string(line);
                charges.add(lines.number(), fixed.substr(78, 2));
                fixed.replace(78, std::min<std::size_t>(2, fixed.size() - 78), "  ");
            }
            if (order_models && !open) open = true, ++ordinal;
            atoms = true;
        } else if (order_models && record_is(line, "MODE")) {
            std::string number(trim(line.size() > 10 ? line.substr(10, 4) : ""));
            if (open && atoms) {
                unclosed.add(lines.number());
                out += "ENDMDL\n";
            }
            if (!numbers.insert(number).second) repeated.add(lines.number(), number);
            char record[32];
            std::snprintf(record, sizeof record, "MODEL     %4d", ++ordinal);
            fixed = record;
            open = true, atoms = false;
        } else if (order_models && record_is(line, "ENDM")) {
            open = false;
        } else if (short_connection_record(line)) {
            fixed = std::string(line);
            std::replace(fixed.begin(), fixed.end(), '\0', ' ');
            if (fixed.size() < 80) fixed.append(80 - fixed.size(), ' ');
        }
        if (fixed.empty() && cut) fixed = std::string(line);
        if (fixed.empty()) {
            if (copying) out.append(line).push_back('\n');
        } else {
            if (!copying) start_copy(line.data());
            out.append(fixed).push_back('\n');
            changed = true;
        }
    }
    if (realigned.count)
        warnings.push_back(name + ": " + std::to_string(realigned.count) +
                           " ATOM/HETATM record(s) with fields past their columns (residue "
                           "numbers past 9999, serials past 99999 or coordinates run together; "
                           "the first at line " +
                           std::to_string(realigned.first_line) + ") read field by field");
    if (free_format.count)
        warnings.push_back(name + ": " + std::to_string(free_format.count) +
                           " ATOM/HETATM record(s) in free format (fields separated by white "
                           "space, not in PDB's columns; the first at line " +
                           std::to_string(free_format.first_line) + ") read by their fields");
    if (charges.count)
        warnings.push_back(name + ": unreadable charge '" + charges.first + "' (columns 79-80)" +
                           at_line(charges.first_line) + charges.more() +
                           " ignored (old-format text in the charge columns)");
    if (repeated.count)
        warnings.push_back(name + ": MODEL " + repeated.first + at_line(repeated.first_line) +
                           " repeats a model number" + repeated.more() +
                           "; models are numbered in file order");
    if (unclosed.count)
        warnings.push_back(name + ": MODEL" + at_line(unclosed.first_line) +
                           " follows a model without ENDMDL" + unclosed.more() +
                           "; models are numbered in file order");
    return changed || order_models ? out : std::string();
}

}  // namespace fdmsurf::detail
