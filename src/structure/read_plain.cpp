// PQR, XYZR and XYZRN readers: whitespace-separated lines that carry their own radii.
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <exception>
#include <functional>
#include <initializer_list>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <iterator>
#include <limits>

#include "base/decimal.hpp"
#include "base/fresh_pages.hpp"
#include "base/parallel.hpp"
#include "base/pipeline.hpp"
#include "base/trace.hpp"
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

// A radius as the atoms keep it: one that rounds to 0 as a float (1e-70) is 0, so that it is
// left out with the radius-0 atoms rather than kept as a ball of no size. Only the general
// route below can read one: the plain decimals' fast path gives 0 or at least 1e-22, within
// float's range (parse_decimal_fast's own bounds).
double stored_radius(double r) { return static_cast<float>(r) == 0.0f ? 0.0 : r; }

// x, y, z and the radius of one line (four fields); a negative radius is refused.
void sphere(std::initializer_list<std::string_view> xyzr, const std::string& name,
            std::size_t line, float xyz[3], double& r) {
    const std::string_view* f = xyzr.begin();
    for (int i = 0; i < 3; ++i)
        xyz[i] = static_cast<float>(number_field(f[i], kCoordinate[i], name, line));
    r = number_field(f[3], "radius", name, line);
    if (r < 0.0)
        fail_format(name + ": radius " + std::string(f[3]) + " is not > 0" + at_line(line));
    r = stored_radius(r);
}

// The pieces' size for the threads: a text below it is read on one thread (the counts first, so
// that the arrays are allocated once).
constexpr std::size_t kPiece = std::size_t{1} << 20;

// A text cut into pieces of about `piece` bytes of whole lines, to be read on all threads (every
// piece but the last ends in a newline).
std::vector<std::string_view> text_pieces(std::string_view text, std::size_t piece) {
    std::vector<std::string_view> pieces;
    for (std::size_t at = 0; at < text.size();) {
        std::size_t end = std::min(text.size(), at + piece);
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

// The records `is_record` takes in each piece and the lines before it, both as the counts before
// each piece (entry k) with the totals last: where each piece's atoms and line numbers start.
struct PieceStarts {
    std::vector<std::size_t> slot, line;
};
template <class IsRecord>
PieceStarts count_records(const std::vector<std::string_view>& pieces, IsRecord is_record) {
    PieceStarts starts{std::vector<std::size_t>(pieces.size() + 1, 0),
                       std::vector<std::size_t>(pieces.size() + 1, 0)};
    parallel_chunks(pieces.size(), thread_count(), [&](std::size_t k) {
        LineReader lines(pieces[k]);
        std::string_view line;
        while (lines.next(line)) starts.slot[k + 1] += is_record(line);
        starts.line[k + 1] = lines.number();  // the newlines: the piece ends in one (or is last)
    });
    running_sums(starts.slot);
    running_sums(starts.line);
    trace("read: pieces counted");
    return starts;
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
// sphere() reads from them; `rest`: where the fourth field ends. False for anything else (a comment, a blank line, a '+', bytes
// outside printable ASCII, what is an error), which sphere() and its messages then take.
bool xyzr_line_fast(std::string_view line, float xyz[3], double& r, std::size_t* rest = nullptr) {
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
    if (rest) *rest = std::size_t(p - line.data());
    return true;
}

// Radius-0 atoms are left out, with this warning, rather than refused: pdb2pqr gives some
// hydrogens radius 0, and such an atom has no volume.
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
    // The first letter's element, looked up once for each byte.
    static const std::array<std::string, 256> kLetter = [] {
        std::array<std::string, 256> letter;
        for (int c = 0; c < 256; ++c) {
            const char byte = static_cast<char>(c);
            const std::string element = known_element(std::string_view(&byte, 1));
            letter[std::size_t(c)] = element.empty() ? "X" : element;
        }
        return letter;
    }();
    if (atom_name.empty()) {
        std::string element = known_element(atom_name);
        return element.empty() ? "X" : element;
    }
    return kLetter[static_cast<unsigned char>(atom_name[0])];
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
    std::string_view parts[6];  // split at '_'; a seventh part: not MSMS's form
    std::size_t count = 0;
    for (std::size_t start = 0;;) {
        const std::size_t end = field.find('_', start);
        if (count == 6) return m;
        parts[count++] = field.substr(start, end == std::string_view::npos ? end : end - start);
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
    std::int32_t number = 0;
    if (count < 5 || !parse_int(parts[1], number) || parts[3].empty() || parts[4].empty())
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
// --- One line of each format, for both ways of reading below ---

// x, y, z and the radius of an XYZR line (line `number` of the file), with `f` for its fields;
// false for a comment or a blank line.
bool xyzr_line(std::string_view line, std::size_t number, const std::string& name,
               std::vector<std::string_view>& f, float xyz[3], double& r) {
    if (xyzr_line_fast(line, xyz, r)) return true;
    const std::string_view t = trim(line);
    if (t.empty() || t[0] == '#') return false;
    split_fields(t, f);
    if (f.size() < 4)
        fail_format(name + ": too few fields for an XYZR atom" + at_line(number) + " (" +
                    std::to_string(f.size()) + "; expected: x y z radius)");
    sphere({f[0], f[1], f[2], f[3]}, name, number, xyz, r);
    return true;
}

// Whether `line` is one of XYZRN's sphere lines (neither blank nor a comment): the lines that
// MSMS numbers.
bool is_xyzrn_sphere(std::string_view line) {
    const std::string_view t = trim(line);
    return !t.empty() && t[0] != '#';
}

// The last field of the rest of an XYZRN line after its four numbers, as split_fields would
// give it ("" for none), into `field`; false where the rest is not plain ASCII (split_fields'
// white space there is the locale's), which the general route then takes.
bool xyzrn_name_fast(std::string_view rest, std::string_view& field) {
    for (char c : rest)
        if (!(c == ' ' || c == '\t' || (c > ' ' && c < 0x7f))) return false;
    std::size_t end = rest.size();
    while (end > 0 && (rest[end - 1] == ' ' || rest[end - 1] == '\t')) --end;
    std::size_t start = end;
    while (start > 0 && rest[start - 1] != ' ' && rest[start - 1] != '\t') --start;
    field = rest.substr(start, end - start);
    return true;
}

// x, y, z and the radius of an XYZRN line and its name field (the last of five or more; ""
// for four), with `f` for its fields; false for a comment or a blank line.
bool xyzrn_line(std::string_view line, std::size_t number, const std::string& name,
                std::vector<std::string_view>& f, float xyz[3], double& r,
                std::string_view& atom_name) {
    std::size_t rest = 0;
    if (xyzr_line_fast(line, xyz, r, &rest) && xyzrn_name_fast(line.substr(rest), atom_name))
        return true;
    if (!is_xyzrn_sphere(line)) return false;
    split_fields(trim(line), f);
    if (f.size() < 4)
        fail_format(name + ": too few fields for an XYZRN atom" + at_line(number) + " (" +
                    std::to_string(f.size()) + "; expected: x y z radius n name)");
    sphere({f[0], f[1], f[2], f[3]}, name, number, xyz, r);
    atom_name = f.size() >= 5 ? f.back() : std::string_view();
    return true;
}

// An XYZRN atom's metadata and element from its name field; `serial`: its sphere line's number.
AtomMeta xyzrn_atom(std::string_view atom_name, std::int32_t serial, std::string& element) {
    AtomMeta m = xyzrn_meta(atom_name, element);
    m.serial = serial;
    return m;
}

// A PQR record (line `number` of the file; is_pqr_atom_record): its metadata into `m` (as
// constructed), its centre and radius, its fields in `f` (PDB's fixed columns where white space
// does not give them; `in_columns` says so).
void pqr_record(std::string_view line, std::size_t number, const std::string& name,
                std::vector<std::string_view>& f, AtomMeta& m, float xyz[3], double& r,
                bool& in_columns) {
    split_fields(line, f);
    // x y z charge radius as plain decimals (base/decimal.hpp): read once, here, with the values
    // that numbers(), number_field() and sphere() would give.
    double v[5] = {};
    bool fast = f.size() >= 10;
    for (std::size_t i = 0; fast && i < 5; ++i) fast = parse_decimal_fast(f[f.size() - 5 + i], v[i]);
    fast = fast && v[4] >= 0.0;
    in_columns = false;
    if (!fast && (f.size() < 10 || !numbers(f, f.size() - 5))) {
        std::vector<std::string_view> columns = pqr_columns(line);
        if (!columns.empty()) {
            f = std::move(columns);
            in_columns = true;
        }
    }
    if (f.size() < 10)
        fail_format(name + ": too few fields for a PQR atom" + at_line(number) + " (" +
                    std::to_string(f.size()) +
                    "; expected: record serial name resName [chain] resSeq x y z charge radius)");
    const std::size_t n = f.size();
    m.charge = static_cast<float>(fast ? v[3] : number_field(f[n - 2], "charge", name, number));
    m.has_charge = true;
    if (!parse_int(f[1], m.serial)) m.serial = 0;  // serials are informative only
    m.name = std::string(f[2]);
    m.residue_name = std::string(f[3]);
    m.hetero = iequals(f[0], "HETATM");
    pqr_residue(f, m, name, number);
    r = v[4];
    if (fast)
        for (int i = 0; i < 3; ++i) xyz[i] = static_cast<float>(v[i]);
    else
        sphere({f[n - 5], f[n - 4], f[n - 3], f[n - 1]}, name, number, xyz, r);
}

// The warning for a PQR's records read in fixed columns.
void note_columns(Structure& s, std::size_t in_columns, std::size_t first_line,
                  const std::string& name) {
    if (in_columns)
        s.info.warnings.push_back(name + ": " + std::to_string(in_columns) +
                                  " record(s) read in PDB's fixed columns (fields run together "
                                  "or missing; the first at line " +
                                  std::to_string(first_line) + ")");
}

// --- Pieces on all threads: a text cut at line ends, each piece written in place ---

// What reading one piece leaves for the whole: its atoms (written from its first slot on), its
// radius-0 atoms and the first line of them, and the error that stopped it.
struct Part {
    std::size_t atoms = 0, zero = 0, first_zero = 0;
    std::exception_ptr error;
};

// The atoms' arrays as pieces write them while the arrays grow (see grow_atoms).
struct AtomSlots {
    float* xyz;
    float* radius;
    std::string* element;
    AtomMeta* meta;
};

// Room for `n` atoms in the arrays (`with_meta`: the metadata too), reserved, not yet filled,
// its pages provided on all threads.
AtomSlots reserve_atoms(Atoms& a, std::size_t n, bool with_meta) {
    a.xyz.reserve(3 * n);
    a.radius.reserve(n);
    a.element.reserve(n);
    if (with_meta) a.meta.reserve(n);
    populate_pages({{a.xyz.data(), 3 * n * sizeof(float)},
                    {a.radius.data(), n * sizeof(float)},
                    {a.element.data(), n * sizeof(std::string)},
                    {a.meta.data(), with_meta ? n * sizeof(AtomMeta) : 0}});
    trace("read: room for the atoms");
    return {a.xyz.data(), a.radius.data(), a.element.data(), a.meta.data()};
}

// The arrays grown to `n` atoms, within their room: std::vector constructs its elements on one
// thread, so that thread grows them piece by piece while the others read the pieces already
// grown (parallel_prepared).
void grow_atoms(Atoms& a, std::size_t n, bool with_meta) {
    a.xyz.resize(3 * n);
    a.radius.resize(n);
    a.element.resize(n);
    if (with_meta) a.meta.resize(n);
}

// Reads the pieces (`read(k)`) on all threads, each as soon as the arrays have grown to the
// slots before the next piece (`first_slot[k + 1]`).
void read_pieces(Atoms& a, const std::vector<std::size_t>& first_slot, bool with_meta,
                 const std::function<void(std::size_t)>& read) {
    parallel_prepared(
        first_slot.size() - 1, thread_count(),
        [&](std::size_t k) { grow_atoms(a, first_slot[k + 1], with_meta); }, read);
    trace("read: pieces read");
}

// The pieces' atoms one after another, the gaps that comments, radius-0 atoms and other lines
// left closed (moved towards the front), the arrays cut to them; the first error in file order
// rethrown. `zero` and `first_zero`: the radius-0 atoms of the whole.
template <class P>
void join_parts(Atoms& a, const std::vector<std::size_t>& first_slot, const std::vector<P>& parts,
                std::size_t& zero, std::size_t& first_zero) {
    std::size_t atoms = 0;
    zero = first_zero = 0;
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const Part& part = parts[k];
        if (part.error) std::rethrow_exception(part.error);
        if (atoms != first_slot[k]) {
            const auto from = std::ptrdiff_t(first_slot[k]), to = std::ptrdiff_t(atoms);
            const auto n = std::ptrdiff_t(part.atoms);
            std::copy(a.xyz.begin() + 3 * from, a.xyz.begin() + 3 * (from + n),
                      a.xyz.begin() + 3 * to);
            std::copy(a.radius.begin() + from, a.radius.begin() + from + n, a.radius.begin() + to);
            if (!a.meta.empty()) {  // XYZR's elements are all empty
                std::move(a.meta.begin() + from, a.meta.begin() + from + n, a.meta.begin() + to);
                std::move(a.element.begin() + from, a.element.begin() + from + n,
                          a.element.begin() + to);
            }
        }
        atoms += part.atoms;
        if (part.zero > 0 && zero == 0) first_zero = part.first_zero;
        zero += part.zero;
    }
    a.xyz.resize(3 * atoms);
    a.radius.resize(atoms);
    a.element.resize(atoms);
    if (!a.meta.empty()) a.meta.resize(atoms);
}

// XYZR lines of `text`, the first of which is line `first_line` + 1 of the file, into the atoms'
// arrays from slot `slot` on (room for an atom per line).
void read_xyzr_part(std::string_view text, std::size_t first_line, const std::string& name,
                    const AtomSlots& atoms, std::size_t slot, Part& part) {
    try {
        float* const xyz = atoms.xyz + 3 * slot;
        float* const radius = atoms.radius + slot;
        LineReader lines(text);
        std::string_view line;
        std::vector<std::string_view> f;
        float p[3];
        double r = 0.0;
        while (lines.next(line)) {
            const std::size_t number = first_line + lines.number();
            if (!xyzr_line(line, number, name, f, p, r)) continue;
            // Radius 0: left out (note_zero_radii says why).
            if (r == 0.0) {
                if (part.zero++ == 0) part.first_zero = number;
                continue;
            }
            std::copy(p, p + 3, xyz + 3 * part.atoms);
            radius[part.atoms++] = static_cast<float>(r);
        }
    } catch (...) {
        part.error = std::current_exception();
    }
}

// XYZRN lines of `text` as read_xyzr_part; `first_sphere`: the sphere lines before it.
void read_xyzrn_part(std::string_view text, std::size_t first_line, std::size_t first_sphere,
                     const std::string& name, const AtomSlots& atoms, std::size_t slot,
                     Part& part) {
    try {
        LineReader lines(text);
        std::string_view line;
        std::vector<std::string_view> f;
        std::size_t sphere = first_sphere;
        float p[3];
        double r = 0.0;
        std::string_view atom_name;
        while (lines.next(line)) {
            const std::size_t number = first_line + lines.number();
            if (!xyzrn_line(line, number, name, f, p, r, atom_name)) continue;
            ++sphere;
            if (r == 0.0) {
                if (part.zero++ == 0) part.first_zero = number;
                continue;
            }
            const std::size_t at = slot + part.atoms++;
            std::copy(p, p + 3, atoms.xyz + 3 * at);
            atoms.radius[at] = static_cast<float>(r);
            const auto serial = std::int32_t(
                std::min<std::size_t>(sphere, std::numeric_limits<std::int32_t>::max()));
            atoms.meta[at] = xyzrn_atom(atom_name, serial, atoms.element[at]);
        }
    } catch (...) {
        part.error = std::current_exception();
    }
}

// A PQR piece's part: besides Part's, the count and first line of its records read in columns,
// and its radius-0 atoms while it has no atom with a radius.
struct PqrPart : Part {
    std::size_t in_columns = 0, first_in_columns = 0;
    std::vector<Unsized> unsized;
};

// The ATOM/HETATM records of `text` as read_xyzr_part (room for each record).
void read_pqr_part(std::string_view text, std::size_t first_line, const std::string& name,
                   const AtomSlots& atoms, std::size_t slot, PqrPart& part) {
    try {
        LineReader lines(text);
        std::string_view line;
        std::vector<std::string_view> f;
        while (lines.next(line)) {
            if (!is_pqr_atom_record(line)) continue;
            const std::size_t number = first_line + lines.number();
            // The record's own slot (one per record), as constructed: read into it in place.
            const std::size_t at = slot + part.atoms;
            AtomMeta& m = atoms.meta[at];
            float xyz[3];
            double r = 0.0;
            bool in_columns = false;
            pqr_record(line, number, name, f, m, xyz, r, in_columns);
            if (in_columns && part.in_columns++ == 0) part.first_in_columns = number;
            if (r > 0.0) {
                ++part.atoms;
                std::copy(xyz, xyz + 3, atoms.xyz + 3 * at);
                atoms.radius[at] = static_cast<float>(r);
                atoms.element[at] = pqr_element(f[2], f[3]);
                part.unsized.clear();
            } else {
                if (part.zero++ == 0) part.first_zero = number;
                if (part.atoms == 0) {
                    Unsized atom;
                    std::copy(xyz, xyz + 3, atom.xyz);
                    atom.meta = std::move(m);
                    atom.element = pqr_element(f[2], f[3]);
                    part.unsized.push_back(std::move(atom));
                }
                m = AtomMeta();  // the slot is the next record's
            }
        }
    } catch (...) {
        part.error = std::current_exception();
    }
}

}  // namespace

// --- PQR: ATOM/HETATM serial name resName [chainID] resSeq x y z charge radius. The chain is
// optional and fields are not in fixed columns, so x y z and radius are counted from the end;
// where white space does not give the fields, PDB's fixed columns are tried. Radius-0 atoms are
// left out (pdb2pqr gives some hydrogens radius 0), unless no atom has a radius: then the
// elements' radii are used. ---

Structure read_pqr_plain(std::string_view text, const std::string& name) {
    Structure s;
    std::size_t zero = 0, first_zero = 0, in_columns = 0, first_in_columns = 0;
    std::vector<Unsized> unsized;  // while no atom has a radius
    LineReader lines(text);
    std::string_view line;
    std::vector<std::string_view> f;
    while (lines.next(line)) {
        if (!is_pqr_atom_record(line)) continue;
        AtomMeta m;
        Unsized atom;
        double r = 0.0;
        bool columns = false;
        pqr_record(line, lines.number(), name, f, m, atom.xyz, r, columns);
        if (columns && in_columns++ == 0) first_in_columns = lines.number();
        if (r > 0.0) {
            s.atoms.xyz.insert(s.atoms.xyz.end(), atom.xyz, atom.xyz + 3);
            s.atoms.radius.push_back(static_cast<float>(r));
            s.atoms.element.push_back(pqr_element(f[2], f[3]));
            s.atoms.meta.push_back(std::move(m));
            unsized.clear();
        } else {
            if (zero++ == 0) first_zero = lines.number();
            if (s.atoms.empty()) {
                atom.meta = std::move(m);
                atom.element = pqr_element(f[2], f[3]);
                unsized.push_back(std::move(atom));
            }
        }
    }
    note_columns(s, in_columns, first_in_columns, name);
    if (s.atoms.empty() && zero > 0) {
        radii_from_elements(s, unsized, name);
        zero = first_zero = 0;
    }
    note_zero_radii(s, zero, first_zero, name);
    return finish(std::move(s), StructureFormat::Pqr, name, "ATOM/HETATM");
}

// Each piece's records counted first, so that each writes its atoms (metadata too) in place.
Structure read_pqr_pieces(std::string_view text, const std::string& name, std::size_t piece) {
    const std::vector<std::string_view> pieces = text_pieces(text, piece);
    const std::size_t count = pieces.size();
    const PieceStarts starts = count_records(pieces, is_pqr_atom_record);
    const std::vector<std::size_t>& first_slot = starts.slot;
    const std::vector<std::size_t>& first_line = starts.line;
    Structure s;
    const AtomSlots slots = reserve_atoms(s.atoms, first_slot.back(), true);
    std::vector<PqrPart> parts(count);
    read_pieces(s.atoms, first_slot, true, [&](std::size_t k) {
        read_pqr_part(pieces[k], first_line[k], name, slots, first_slot[k], parts[k]);
    });
    std::size_t zero = 0, first_zero = 0, in_columns = 0, first_in_columns = 0;
    join_parts(s.atoms, first_slot, parts, zero, first_zero);
    for (const PqrPart& part : parts) {
        if (part.in_columns > 0 && in_columns == 0) first_in_columns = part.first_in_columns;
        in_columns += part.in_columns;
    }
    note_columns(s, in_columns, first_in_columns, name);
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

Structure read_pqr(std::string_view text, const std::string& name) {
    return read_pqr_pieces(text, name, kPiece);
}

// --- XYZR (MSMS): "x y z r" and optionally more fields, which are ignored. ---

Structure read_xyzr_plain(std::string_view text, const std::string& name) {
    Structure s;
    std::size_t zero = 0, first_zero = 0;
    LineReader lines(text);
    std::string_view line;
    std::vector<std::string_view> f;
    float xyz[3];
    double r = 0.0;
    while (lines.next(line)) {
        if (!xyzr_line(line, lines.number(), name, f, xyz, r)) continue;
        if (r == 0.0) {  // left out (note_zero_radii says why)
            if (zero++ == 0) first_zero = lines.number();
            continue;
        }
        s.atoms.xyz.insert(s.atoms.xyz.end(), xyz, xyz + 3);
        s.atoms.radius.push_back(static_cast<float>(r));
    }
    s.atoms.element.resize(s.atoms.size());  // XYZR has no element; kept parallel to radius
    note_zero_radii(s, zero, first_zero, name);
    return finish(std::move(s), StructureFormat::Xyzr, name, "'x y z r'");
}

// Each piece written at its first line's slot (an atom per line at most).
Structure read_xyzr_pieces(std::string_view text, const std::string& name, std::size_t piece) {
    const std::vector<std::string_view> pieces = text_pieces(text, piece);
    // The lines before each piece.
    std::vector<std::size_t> first_line(pieces.size() + 1, 0);
    parallel_chunks(pieces.size(), thread_count(), [&](std::size_t k) {
        first_line[k + 1] = std::size_t(std::count(pieces[k].begin(), pieces[k].end(), '\n'));
    });
    running_sums(first_line);
    trace("read: pieces counted");
    // A slot per line; the last line may have no newline.
    std::vector<std::size_t> first_slot = first_line;
    first_slot.back() += 1;
    Structure s;
    const AtomSlots slots = reserve_atoms(s.atoms, first_slot.back(), false);
    std::vector<Part> parts(pieces.size());
    read_pieces(s.atoms, first_slot, false, [&](std::size_t k) {
        read_xyzr_part(pieces[k], first_line[k], name, slots, first_slot[k], parts[k]);
    });
    std::size_t zero = 0, first_zero = 0;
    join_parts(s.atoms, first_slot, parts, zero, first_zero);
    note_zero_radii(s, zero, first_zero, name);
    return finish(std::move(s), StructureFormat::Xyzr, name, "'x y z r'");
}

Structure read_xyzr(std::string_view text, const std::string& name) {
    return read_xyzr_pieces(text, name, kPiece);
}

// --- XYZRN (MSMS's pdb_to_xyzrn): "x y z r n name"; with five or more fields the last is the
// name, so "x y z r name" reads too, and plain "x y z r" lines give an empty name. ---

Structure read_xyzrn_plain(std::string_view text, const std::string& name) {
    Structure s;
    std::size_t zero = 0, first_zero = 0;
    std::int32_t sphere = 0;  // the serial: the sphere's number in the file, as MSMS's
    LineReader lines(text);
    std::string_view line;
    std::vector<std::string_view> f;
    float xyz[3];
    double r = 0.0;
    std::string_view atom_name;
    while (lines.next(line)) {
        if (!xyzrn_line(line, lines.number(), name, f, xyz, r, atom_name)) continue;
        if (sphere < std::numeric_limits<std::int32_t>::max()) ++sphere;
        if (r == 0.0) {  // left out (note_zero_radii says why)
            if (zero++ == 0) first_zero = lines.number();
            continue;
        }
        s.atoms.xyz.insert(s.atoms.xyz.end(), xyz, xyz + 3);
        s.atoms.radius.push_back(static_cast<float>(r));
        std::string element;
        s.atoms.meta.push_back(xyzrn_atom(atom_name, sphere, element));
        s.atoms.element.push_back(std::move(element));
    }
    note_zero_radii(s, zero, first_zero, name);
    return finish(std::move(s), StructureFormat::Xyzrn, name, "'x y z r n name'");
}

// Each piece's sphere lines counted first (they number the atoms and give their slots).
Structure read_xyzrn_pieces(std::string_view text, const std::string& name, std::size_t piece) {
    const std::vector<std::string_view> pieces = text_pieces(text, piece);
    const std::size_t count = pieces.size();
    const PieceStarts starts = count_records(pieces, is_xyzrn_sphere);
    const std::vector<std::size_t>& first_slot = starts.slot;
    const std::vector<std::size_t>& first_line = starts.line;
    Structure s;
    const AtomSlots slots = reserve_atoms(s.atoms, first_slot.back(), true);
    std::vector<Part> parts(count);
    read_pieces(s.atoms, first_slot, true, [&](std::size_t k) {
        read_xyzrn_part(pieces[k], first_line[k], first_slot[k], name, slots, first_slot[k],
                        parts[k]);
    });
    std::size_t zero = 0, first_zero = 0;
    join_parts(s.atoms, first_slot, parts, zero, first_zero);
    note_zero_radii(s, zero, first_zero, name);
    return finish(std::move(s), StructureFormat::Xyzrn, name, "'x y z r n name'");
}

Structure read_xyzrn(std::string_view text, const std::string& name) {
    return read_xyzrn_pieces(text, name, kPiece);
}

}  // namespace fdmsurf::detail
