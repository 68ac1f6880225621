// PQR, XYZR and XYZRN readers: whitespace-separated lines that carry their own radii.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <exception>
#include <initializer_list>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>

#include "base/decimal.hpp"
#include "base/parallel.hpp"
#include "structure/detail.hpp"

namespace fdmsurf::detail {

namespace {

// One numeric field; `what` names it in the message ("x coordinate", "radius"), which is only
// put together for a field that fails.
double number_field(std::string_view field, const char* what, const std::string& name,
                    std::size_t line) {
    double value = 0.0;
    NumberStatus status = parse_number(field, value);
    if (status != NumberStatus::Ok)
        fail_format(name + ": " + number_problem(status, what, field) + at_line(line));
    return value;
}

const char* const kCoordinate[] = {"x coordinate", "y coordinate", "z coordinate"};

// x, y, z and the radius of one line (four fields); a negative radius is refused.
void sphere(std::initializer_list<std::string_view> xyzr, const std::string& name,
            std::size_t line, float xyz[3], double& r) {
    const std::string_view* f = xyzr.begin();
    for (int i = 0; i < 3; ++i)
        xyz[i] = static_cast<float>(number_field(f[i], kCoordinate[i], name, line));
    r = number_field(f[3], "radius", name, line);
    if (r < 0.0)
        fail_format(name + ": radius " + std::string(f[3]) + " is not > 0" + at_line(line));
}

// Appends the atom's x y z and radius, or returns false for radius 0: pdb2pqr gives some
// hydrogens radius 0, and such an atom has no volume, so it is left out (with a warning)
// rather than refused.
bool add_atom(std::vector<float>& xyz_out, std::vector<float>& radius_out,
              std::initializer_list<std::string_view> xyzr, const std::string& name,
              std::size_t line) {
    float xyz[3];
    double r = 0.0;
    sphere(xyzr, name, line, xyz, r);
    if (r == 0.0) return false;
    xyz_out.insert(xyz_out.end(), xyz, xyz + 3);
    radius_out.push_back(static_cast<float>(r));
    return true;
}

bool add_atom(Atoms& atoms, std::initializer_list<std::string_view> xyzr,
              const std::string& name, std::size_t line) {
    return add_atom(atoms.xyz, atoms.radius, xyzr, name, line);
}

// A text cut into pieces of about 1 MiB of whole lines, to be read on all threads (every piece
// but the last ends in a newline).
std::vector<std::string_view> text_pieces(std::string_view text) {
    constexpr std::size_t kPiece = std::size_t{1} << 20;
    std::vector<std::string_view> pieces;
    for (std::size_t at = 0; at < text.size();) {
        std::size_t end = std::min(text.size(), at + kPiece);
        if (end < text.size()) {
            const std::size_t nl = text.find('\n', end);
            end = nl == std::string_view::npos ? text.size() : nl + 1;
        }
        pieces.push_back(text.substr(at, end - at));
        at = end;
    }
    return pieces;
}

// Running sums in place: counts per piece at [1..n] become the counts before each piece.
void running_sums(std::vector<std::size_t>& v) {
    for (std::size_t k = 1; k < v.size(); ++k) v[k] += v[k - 1];
}

// Whether the first field of `line` (as split_fields gives it) is ATOM or HETATM in any case.
bool is_pqr_atom_record(std::string_view line) {
    std::size_t i = 0;
    while (i < line.size() && is_space(line[i])) ++i;
    std::size_t end = i;
    while (end < line.size() && !is_space(line[end])) ++end;
    const std::string_view first = line.substr(i, end - i);
    return iequals(first, "ATOM") || iequals(first, "HETATM");
}

// x, y, z and the radius of an XYZR line whose first four fields are plain decimals (see
// base/decimal.hpp), separated by spaces or tabs, the radius not negative: the values that
// sphere() reads from them. False for anything else (a comment, a blank line, a '+', bytes
// outside printable ASCII, what is an error), which sphere() and its messages then take.
bool xyzr_line_fast(std::string_view line, float xyz[3], double& r) {
    const char* p = line.data();
    const char* const end = p + line.size();
    double v[4];
    for (double& value : v) {
        while (p != end && (*p == ' ' || *p == '\t')) ++p;
        const char* const start = p;
        while (p != end && *p > ' ' && *p < 0x7f) ++p;
        // The field must end where split_fields ends it: at white space or the line's end.
        if (p != end && !(*p == ' ' || (*p >= '\t' && *p <= '\r'))) return false;
        if (!parse_decimal_fast(std::string_view(start, std::size_t(p - start)), value))
            return false;
    }
    if (v[3] < 0.0) return false;
    for (int i = 0; i < 3; ++i) xyz[i] = static_cast<float>(v[i]);
    r = v[3];
    return true;
}

// One piece of an XYZR text (whole lines), read on a thread of its own into the atoms' arrays
// from `xyz` and `radius` on: its atom count, its radius-0 atoms, and the error that stopped it.
struct XyzrPart {
    std::size_t atoms = 0, zero = 0, first_zero = 0;
    std::exception_ptr error;
};

// XYZR lines of `text`, the first of which is line `first_line` + 1 of the file; room for an
// atom per line at `xyz` and `radius`.
void read_xyzr_part(std::string_view text, std::size_t first_line, const std::string& name,
                    float* xyz, float* radius, XyzrPart& part) {
    try {
        LineReader lines(text);
        std::string_view line;
        std::vector<std::string_view> f;
        while (lines.next(line)) {
            float p[3];
            double r = 0.0;
            if (!xyzr_line_fast(line, p, r)) {
                std::string_view t = trim(line);
                if (t.empty() || t[0] == '#') continue;
                split_fields(t, f);
                if (f.size() < 4)
                    fail_format(name + ": too few fields for an XYZR atom" +
                                at_line(first_line + lines.number()) + " (" +
                                std::to_string(f.size()) + "; expected: x y z radius)");
                sphere({f[0], f[1], f[2], f[3]}, name, first_line + lines.number(), p, r);
            }
            // Radius 0: left out (add_atom says why).
            if (r == 0.0) {
                if (part.zero++ == 0) part.first_zero = first_line + lines.number();
                continue;
            }
            std::copy(p, p + 3, xyz + 3 * part.atoms);
            radius[part.atoms++] = static_cast<float>(r);
        }
    } catch (...) {
        part.error = std::current_exception();
    }
}

void note_zero_radii(Structure& s, std::size_t zero, std::size_t first_line,
                     const std::string& name) {
    s.info.zero_radius_skipped = zero;
    s.info.first_zero_radius_line = first_line;
    if (zero == 0) return;
    if (s.atoms.empty())
        throw Error(ErrorCode::EmptySelection,
                    name + ": all " + std::to_string(zero) + " atoms have radius 0");
    s.info.warnings.push_back(
        name + ": " + std::to_string(zero) + " atom(s) with radius 0 left out (the first at line " +
        std::to_string(first_line) +
        "); atom numbers (the mesh's atom index, the areas files) count the atoms kept");
}

// PQR has no element column. Atom names start with the element, except ions, whose residue
// name is their element ("ZN ZN", "CL CL"): only there a two-letter symbol is taken.
std::string pqr_element(std::string_view atom_name, std::string_view residue_name) {
    while (!atom_name.empty() && std::isdigit(static_cast<unsigned char>(atom_name[0])))
        atom_name.remove_prefix(1);
    if (atom_name.size() <= 2 && iequals(atom_name, residue_name)) {
        std::string ion = known_element(atom_name);
        if (!ion.empty()) return ion;
    }
    std::string element = known_element(atom_name.substr(0, 1));
    return element.empty() ? "X" : element;
}

// A whole field as an int, or false.
bool parse_int(std::string_view field, std::int32_t& value) {
    if (field.size() > 1 && field[0] == '+') field.remove_prefix(1);
    auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
    return ec == std::errc() && end == field.data() + field.size();
}

bool is_alpha(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }

// A PQR residue number, "52" or with its insertion code "52A"; `m` changes only on success.
bool parse_residue_number(std::string_view field, AtomMeta& m) {
    char icode = ' ';
    if (field.size() > 1 && is_alpha(field.back())) {
        icode = field.back();
        field.remove_suffix(1);
    }
    std::int32_t number = 0;
    if (!parse_int(field, number)) return false;
    m.residue_number = number;
    m.insertion_code = icode;
    return true;
}

// The fields between resName and x: "[chain] resSeq". Writers with fixed columns glue a
// one-letter chain to a residue number of four digits ("A1000"); that is split here.
void pqr_residue(const std::vector<std::string_view>& f, AtomMeta& m, const std::string& name,
                 std::size_t line) {
    const std::size_t middle = f.size() - 9;  // fields 4 .. n-6
    std::string_view number = f[4];
    if (middle >= 2) {
        m.chain = std::string(f[4]);
        number = f[5];
    }
    if (parse_residue_number(number, m)) return;
    if (middle == 1 && number.size() > 1 && is_alpha(number[0]) &&
        parse_residue_number(number.substr(1), m)) {
        m.chain = std::string(number.substr(0, 1));
        return;
    }
    fail_format(name + ": non-numeric residue number '" + std::string(number) + "'" +
                at_line(line));
}

// The metadata of an XYZRN name field. MSMS-style names "A_23_x_LYS_NZ_Blue"
// (chain_resnum_icode_resname_atomname[_colour], as MaSIF's and similar pdb-to-xyzrn scripts
// write them; 'x' for no insertion code) give chain, residue and atom name, and the element
// from the atom name as for PQR. Other names are kept whole as the atom name, without element.
AtomMeta xyzrn_meta(std::string_view field, std::string& element) {
    AtomMeta m;
    m.xyzrn_name = std::string(field);
    m.name = m.xyzrn_name;
    m.in_residue = false;  // unless the name is MSMS's form
    element.clear();
    std::vector<std::string_view> parts;
    for (std::size_t start = 0;;) {
        std::size_t end = field.find('_', start);
        parts.push_back(field.substr(start, end == std::string_view::npos ? end : end - start));
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
    std::int32_t number = 0;
    if ((parts.size() != 5 && parts.size() != 6) || !parse_int(parts[1], number) ||
        parts[3].empty() || parts[4].empty())
        return m;
    m.in_residue = true;
    m.chain = std::string(parts[0]);
    m.residue_number = number;
    m.insertion_code = parts[2].size() == 1 && parts[2] != "x" ? parts[2][0] : ' ';
    m.residue_name = std::string(parts[3]);
    m.name = std::string(parts[4]);
    element = pqr_element(parts[4], parts[3]);
    return m;
}

Structure finish(Structure s, StructureFormat format, const std::string& name, const char* what) {
    if (s.atoms.empty()) fail_format(name + ": no atoms (no " + what + " lines)");
    s.info.format = format;
    s.info.atoms_in_file = s.atoms.size() + s.info.zero_radius_skipped;
    s.info.models_in_file = 1;
    return s;
}

bool numbers(const std::vector<std::string_view>& f, std::size_t from) {
    double value = 0.0;
    for (std::size_t i = from; i < f.size(); ++i)
        if (parse_number(f[i], value) != NumberStatus::Ok) return false;
    return true;
}

// The fields of a PQR record in PDB's fixed columns, for lines that white space does not split
// into them: coordinates that run together ("1999.3232998.770-900.490", as PyMOL and some
// converters write them) or a blank chain. record 1-6, serial 7-11, name 13-16, resName 18-20,
// chain 22, resSeq and insertion code 23-27, x y z 31-54, then charge and radius, the only two
// fields after column 54. Empty when the columns do not hold numbers where they should.
std::vector<std::string_view> pqr_columns(std::string_view line) {
    if (line.size() < 56) return {};
    auto column = [&](std::size_t from, std::size_t width) {
        return trim(line.substr(from, width));
    };
    std::vector<std::string_view> f = {column(0, 6), column(6, 5), column(12, 4), column(17, 3)};
    if (!column(21, 1).empty()) f.push_back(column(21, 1));
    f.push_back(column(22, 5));
    for (std::size_t i = 0; i < 3; ++i) f.push_back(column(30 + 8 * i, 8));
    std::vector<std::string_view> rest = split_fields(line.substr(54));
    if (rest.size() != 2) return {};  // more fields: which are charge and radius is a guess
    f.push_back(rest[0]);
    f.push_back(rest[1]);
    for (std::string_view field : f)
        if (field.empty()) return {};
    return numbers(f, f.size() - 5) ? f : std::vector<std::string_view>{};
}

// One atom whose radius is 0, kept while no atom of the file has a radius.
struct Unsized {
    float xyz[3];
    AtomMeta meta;
    std::string element;
};

// A PQR whose radius column is all zeros (written by viewers that export charges only): the
// element radii used for PDB input instead.
void radii_from_elements(Structure& s, std::vector<Unsized>& unsized, const std::string& name) {
    std::size_t unknown = 0;
    for (Unsized& u : unsized) {
        float r = vdw_radius(u.element);
        if (!(r > 0.0f)) r = kUnknownElementRadius, ++unknown;
        s.atoms.xyz.insert(s.atoms.xyz.end(), u.xyz, u.xyz + 3);
        s.atoms.radius.push_back(r);
        s.atoms.element.push_back(std::move(u.element));
        s.atoms.meta.push_back(std::move(u.meta));
    }
    char fallback[16];
    std::snprintf(fallback, sizeof fallback, "%.2f", static_cast<double>(kUnknownElementRadius));
    s.info.warnings.push_back(
        name + ": all " + std::to_string(unsized.size()) +
        " atoms have radius 0 (a PQR written without radii?); the element radii of PDB input "
        "used instead" +
        (unknown ? " (" + std::to_string(unknown) + " of unknown element: " + fallback + " A)"
                 : std::string()) +
        "; a PQR's own radii are kept as soon as one atom has a radius above 0");
}

// A PQR's pieces, each read on a thread of its own into the atoms' arrays from its first
// atom's slot on: the counts and first lines of its radius-0 atoms and of its records read in
// columns, its radius-0 atoms while it has no atom with a radius, and the error that stopped it.
struct PqrPart {
    std::size_t atoms = 0, zero = 0, first_zero = 0, in_columns = 0, first_in_columns = 0;
    std::vector<Unsized> unsized;
    std::exception_ptr error;
};

// The ATOM/HETATM records of `text` (whole lines, the first of which is line `first_line` + 1
// of the file) into `atoms` from atom `slot` on, which has room for each of them.
void read_pqr_part(std::string_view text, std::size_t first_line, const std::string& name,
                   Atoms& atoms, std::size_t slot, PqrPart& part) {
    try {
        LineReader lines(text);
        std::string_view line;
        std::vector<std::string_view> f;
        while (lines.next(line)) {
            if (!is_pqr_atom_record(line)) continue;
            const std::size_t number = first_line + lines.number();
            split_fields(line, f);
            // x y z charge radius as plain decimals (base/decimal.hpp): read once, here, with
            // the values that numbers(), number_field() and sphere() would give.
            double v[5] = {};
            bool fast = f.size() >= 10;
            for (std::size_t i = 0; fast && i < 5; ++i)
                fast = parse_decimal_fast(f[f.size() - 5 + i], v[i]);
            fast = fast && v[4] >= 0.0;
            if (!fast && (f.size() < 10 || !numbers(f, f.size() - 5))) {
                std::vector<std::string_view> columns = pqr_columns(line);
                if (!columns.empty()) {
                    f = std::move(columns);
                    if (part.in_columns++ == 0) part.first_in_columns = number;
                }
            }
            if (f.size() < 10)
                fail_format(name + ": too few fields for a PQR atom" + at_line(number) + " (" +
                            std::to_string(f.size()) +
                            "; expected: record serial name resName [chain] resSeq x y z charge "
                            "radius)");
            std::size_t n = f.size();
            AtomMeta m;
            m.charge = static_cast<float>(fast ? v[3]
                                               : number_field(f[n - 2], "charge", name, number));
            m.has_charge = true;
            if (!parse_int(f[1], m.serial)) m.serial = 0;  // serials are informative only
            m.name = std::string(f[2]);
            m.residue_name = std::string(f[3]);
            m.hetero = iequals(f[0], "HETATM");
            pqr_residue(f, m, name, number);
            Unsized atom;
            double r = v[4];
            if (fast)
                for (int i = 0; i < 3; ++i) atom.xyz[i] = static_cast<float>(v[i]);
            else
                sphere({f[n - 5], f[n - 4], f[n - 3], f[n - 1]}, name, number, atom.xyz, r);
            if (r > 0.0) {
                const std::size_t at = slot + part.atoms++;
                std::copy(atom.xyz, atom.xyz + 3, atoms.xyz.begin() + std::ptrdiff_t(3 * at));
                atoms.radius[at] = static_cast<float>(r);
                atoms.element[at] = pqr_element(f[2], f[3]);
                atoms.meta[at] = std::move(m);
                part.unsized.clear();
            } else {
                if (part.zero++ == 0) part.first_zero = number;
                if (part.atoms == 0) {
                    atom.meta = std::move(m);
                    atom.element = pqr_element(f[2], f[3]);
                    part.unsized.push_back(std::move(atom));
                }
            }
        }
    } catch (...) {
        part.error = std::current_exception();
    }
}

}  // namespace

// PQR: ATOM/HETATM serial name resName [chainID] resSeq x y z charge radius. The chain is
// optional and fields are not in fixed columns, so x y z and radius are counted from the end;
// where white space does not give the fields, PDB's fixed columns are tried. Pieces of about
// 1 MiB on all threads, each written in place from its first record's slot (its records
// counted first), the gaps that radius-0 atoms leave closed after: the same atoms, warnings
// and first error as one pass from the top.
Structure read_pqr(std::string_view text, const std::string& name) {
    const std::vector<std::string_view> pieces = text_pieces(text);
    const std::size_t count = pieces.size();
    // The records and the lines before each piece.
    std::vector<std::size_t> first_slot(count + 1, 0), first_line(count + 1, 0);
    parallel_chunks(count, thread_count(), [&](std::size_t k) {
        LineReader lines(pieces[k]);
        std::string_view line;
        while (lines.next(line)) first_slot[k + 1] += is_pqr_atom_record(line);
        first_line[k + 1] = lines.number();  // the newlines: the piece ends in one (or is last)
    });
    running_sums(first_slot);
    running_sums(first_line);
    Structure s;
    const std::size_t slots = first_slot.back();
    s.atoms.xyz.resize(3 * slots);
    s.atoms.radius.resize(slots);
    s.atoms.element.resize(slots);
    s.atoms.meta.resize(slots);
    std::vector<PqrPart> parts(count);
    parallel_chunks(count, thread_count(), [&](std::size_t k) {
        read_pqr_part(pieces[k], first_line[k], name, s.atoms, first_slot[k],
                      parts[k]);
    });
    std::size_t atoms = 0, zero = 0, first_zero = 0, in_columns = 0, first_in_columns = 0;
    for (std::size_t k = 0; k < count; ++k) {
        PqrPart& part = parts[k];
        if (part.error) std::rethrow_exception(part.error);
        if (atoms != first_slot[k]) {  // close the gap before this piece (moves towards the front)
            Atoms& a = s.atoms;
            const auto from = std::ptrdiff_t(first_slot[k]), to = std::ptrdiff_t(atoms);
            const auto n = std::ptrdiff_t(part.atoms);
            std::copy(a.xyz.begin() + 3 * from, a.xyz.begin() + 3 * (from + n),
                      a.xyz.begin() + 3 * to);
            std::copy(a.radius.begin() + from, a.radius.begin() + from + n, a.radius.begin() + to);
            std::move(a.element.begin() + from, a.element.begin() + from + n,
                      a.element.begin() + to);
            std::move(a.meta.begin() + from, a.meta.begin() + from + n, a.meta.begin() + to);
        }
        atoms += part.atoms;
        if (part.zero > 0 && zero == 0) first_zero = part.first_zero;
        zero += part.zero;
        if (part.in_columns > 0 && in_columns == 0) first_in_columns = part.first_in_columns;
        in_columns += part.in_columns;
    }
    s.atoms.xyz.resize(3 * atoms);
    s.atoms.radius.resize(atoms);
    s.atoms.element.resize(atoms);
    s.atoms.meta.resize(atoms);
    if (in_columns)
        s.info.warnings.push_back(name + ": " + std::to_string(in_columns) +
                                  " record(s) read in PDB's fixed columns (fields run together "
                                  "or missing; the first at line " +
                                  std::to_string(first_in_columns) + ")");
    if (s.atoms.empty() && zero > 0) {
        // No atom has a radius: every piece kept all its radius-0 atoms.
        std::vector<Unsized> unsized;
        unsized.reserve(zero);
        for (PqrPart& part : parts)
            std::move(part.unsized.begin(), part.unsized.end(), std::back_inserter(unsized));
        radii_from_elements(s, unsized, name);
        zero = first_zero = 0;
    }
    note_zero_radii(s, zero, first_zero, name);
    return finish(std::move(s), StructureFormat::Pqr, name, "ATOM/HETATM");
}

// XYZR (MSMS): "x y z r" and optionally more fields, which are ignored. Pieces of about 1 MiB
// (whole lines) on all threads, each written in place at its first line's slot of the atoms'
// arrays (an atom per line at most), the gaps that comments and radius-0 lines leave closed
// after: the same atoms, and the same first error, as one pass from the top.
Structure read_xyzr(std::string_view text, const std::string& name) {
    const std::vector<std::string_view> pieces = text_pieces(text);
    // The lines before each piece.
    std::vector<std::size_t> first_line(pieces.size() + 1, 0);
    parallel_chunks(pieces.size(), thread_count(), [&](std::size_t k) {
        first_line[k + 1] = std::size_t(std::count(pieces[k].begin(), pieces[k].end(), '\n'));
    });
    running_sums(first_line);
    Structure s;
    // A slot per line; the last line may have no newline.
    const std::size_t slots = first_line.back() + 1;
    s.atoms.xyz.resize(3 * slots);
    s.atoms.radius.resize(slots);
    std::vector<XyzrPart> parts(pieces.size());
    parallel_chunks(pieces.size(), thread_count(), [&](std::size_t k) {
        read_xyzr_part(pieces[k], first_line[k], name, s.atoms.xyz.data() + 3 * first_line[k],
                       s.atoms.radius.data() + first_line[k], parts[k]);
    });
    std::size_t zero = 0, first_zero = 0, atoms = 0;
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const XyzrPart& part = parts[k];
        if (part.error) std::rethrow_exception(part.error);
        if (atoms != first_line[k]) {  // close the gap before this piece (moves towards the front)
            const float* xyz = s.atoms.xyz.data() + 3 * first_line[k];
            const float* radius = s.atoms.radius.data() + first_line[k];
            std::copy(xyz, xyz + 3 * part.atoms, s.atoms.xyz.data() + 3 * atoms);
            std::copy(radius, radius + part.atoms, s.atoms.radius.data() + atoms);
        }
        atoms += part.atoms;
        if (part.zero > 0 && zero == 0) first_zero = part.first_zero;
        zero += part.zero;
    }
    s.atoms.xyz.resize(3 * atoms);
    s.atoms.radius.resize(atoms);
    s.atoms.element.resize(atoms);  // XYZR has no element; kept parallel to radius
    note_zero_radii(s, zero, first_zero, name);
    return finish(std::move(s), StructureFormat::Xyzr, name, "'x y z r'");
}

// XYZRN (MSMS's pdb_to_xyzrn): "x y z r n name"; with five or more fields the last is the
// name, so "x y z r name" reads too, and plain "x y z r" lines give an empty name.
Structure read_xyzrn(std::string_view text, const std::string& name) {
    Structure s;
    std::size_t zero = 0, first_zero = 0;
    std::int32_t sphere = 0;  // the serial: the sphere's number in the file, as MSMS's
    LineReader lines(text);
    std::string_view line;
    while (lines.next(line)) {
        std::string_view t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        std::vector<std::string_view> f = split_fields(t);
        if (sphere < std::numeric_limits<std::int32_t>::max()) ++sphere;
        if (f.size() < 4)
            fail_format(name + ": too few fields for an XYZRN atom" + at_line(lines.number()) +
                        " (" + std::to_string(f.size()) + "; expected: x y z radius n name)");
        if (add_atom(s.atoms, {f[0], f[1], f[2], f[3]}, name, lines.number())) {
            std::string element;
            s.atoms.meta.push_back(
                xyzrn_meta(f.size() >= 5 ? f.back() : std::string_view(), element));
            s.atoms.meta.back().serial = sphere;
            s.atoms.element.push_back(std::move(element));
        } else {
            if (zero++ == 0) first_zero = lines.number();
        }
    }
    note_zero_radii(s, zero, first_zero, name);
    return finish(std::move(s), StructureFormat::Xyzrn, name, "'x y z r n name'");
}

}  // namespace fdmsurf::detail
