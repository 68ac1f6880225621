// Internals of the structure-input stage, shared by its source files (not installed).
#pragma once

#include <cctype>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"

namespace gemmi {
struct Atom;
struct Chain;
struct Residue;
struct Selection;
}  // namespace gemmi

namespace fdmsurf::detail {

// --- text_input.cpp: bytes in, checked text out ---

// The whole file; gzip data (by its magic bytes, whatever the name) is decompressed.
// Throws Error(Io) when the file cannot be read, Error(Format) for a broken gzip stream.
std::string load_file(const std::string& path);

// A structure file's text. A regular file that is not gzip data is mapped, not copied: on the VM
// of docs/performance.md a fresh page costs more than reading it, and a copy of the shell's 71 MB
// cost more than the parse. (Should another program cut the file short while it is mapped, the
// pages past its new end raise SIGBUS, as for any mapped file.) Any other file is read, and
// decompressed, as load_file does, with its errors.
class FileText {
public:
    explicit FileText(const std::string& path);
    ~FileText();
    FileText(const FileText&) = delete;
    FileText& operator=(const FileText&) = delete;
    std::string_view text() const { return text_; }

private:
    std::string owned_;
    void* map_ = nullptr;
    std::size_t map_size_ = 0;
    std::string_view text_;
};

// The bytes themselves, or their decompression when they are gzip data; `name` for messages.
std::string decompress(std::string bytes, const std::string& name);

// Rejects empty input and binary data, naming `name`. Throws Error(Format).
void check_text(std::string_view data, const std::string& name);

// Extension first (".gz" stripped), then the content; throws Error(Format) when neither tells.
StructureFormat detect_format(std::string_view text, const std::string& name);

// Splits text into lines without their "\n" or "\r\n", numbered from 1.
class LineReader {
public:
    explicit LineReader(std::string_view text) : rest_(text) {}
    bool next(std::string_view& line);
    std::size_t number() const { return number_; }

private:
    std::string_view rest_;
    std::size_t number_ = 0;
    bool done_ = false;
};

// Whitespace-separated fields of a line.
std::vector<std::string_view> split_fields(std::string_view line);
// The same into `fields` (cleared first), whose storage is reused from line to line.
void split_fields(std::string_view line, std::vector<std::string_view>& fields);
// The same a byte at a time: split_fields' reference, and its route for long or non-ASCII lines.
void split_fields_plain(std::string_view line, std::vector<std::string_view>& fields);
std::string_view trim(std::string_view s);
// std::isspace of the byte (split_fields' and trim's white space), without its call for ASCII:
// the C locale's six, which glibc's locales keep for bytes below 0x80; others as the locale says.
inline bool is_space(char c) {
    const auto b = static_cast<unsigned char>(c);
    return b < 0x80 ? b == ' ' || (b >= '\t' && b <= '\r') : std::isspace(b) != 0;
}
bool iequals(std::string_view a, std::string_view b);

enum class NumberStatus { Ok, NotNumber, NotFinite, OutOfRange };
// The whole of `s` must be one decimal number (a leading '+' allowed, no spaces). OutOfRange:
// beyond what a float holds (Atoms stores floats).
NumberStatus parse_number(std::string_view s, double& value);
// "non-numeric x coordinate 'abc'", "NaN or infinite radius 'nan'", ...: for a status not Ok.
std::string number_problem(NumberStatus status, const std::string& what, std::string_view field);

[[noreturn]] void fail_format(const std::string& message);
// " at line N", the tail of messages about one line.
std::string at_line(std::size_t line);

// --- pdb_text.cpp: PDB text as gemmi can read it ---

// An ATOM or HETATM record (gemmi matches record names case-insensitively on their first four
// letters).
bool is_atom_record(std::string_view line);
// END (not ENDMDL), which ends gemmi's reading, so fdmsurf's checks stop there too.
bool is_end_record(std::string_view line);

// Checks every ATOM/HETATM record's coordinates (Error(Format) naming the line and columns) and
// returns the text rewritten where gemmi would refuse or misread it: records whose fields
// overflow their columns, unreadable charges, repeated MODEL numbers or a missing ENDMDL
// (models renumbered in file order), short LINK/SSBOND records; "" when nothing needs it.
// A warning per kind of change goes to `warnings`.
std::string prepare_pdb_text(std::string_view text, const std::string& name,
                             std::vector<std::string>& warnings);

// --- radii.cpp ---

// Upper-case symbol of a known element ("C", "FE"), or "" when `symbol` names none.
std::string known_element(std::string_view symbol);

// --- selection.cpp: ReadOptions::chains and ReadOptions::select ---

// A parsed gemmi selection. gemmi::Selection stays inside selection.cpp: its header pulls in
// stb_sprintf, which Debian's gemmi-dev leaves out and which only that file works around.
class Selection {
public:
    // Throws Error(InvalidArgument) for bad syntax; `context` starts the message (the file
    // name, or "selection").
    Selection(const std::string& expr, const std::string& context);
    ~Selection();
    Selection(Selection&&) noexcept;
    Selection& operator=(Selection&&) noexcept;

    bool matches_model(int model) const;  // model: 1-based
    bool matches(const gemmi::Chain& chain) const;
    bool matches(const gemmi::Residue& residue) const;
    bool matches(const gemmi::Atom& atom) const;

private:
    std::unique_ptr<gemmi::Selection> sel_;
};
// 1 per atom that `expr` matches, the atoms taken as model `model`; atoms.meta has one entry
// per atom. Entity types (;polymer, ;solvent) come from gemmi's heuristic on the residues.
std::vector<std::uint8_t> selection_mask(const Atoms& atoms, const std::string& expr, int model,
                                         const std::string& context);
// "A, B, (blank)": chain names for messages.
std::string chain_list(const std::vector<std::string>& chains);
// Throws Error(InvalidArgument) "NAME: chain(s) X is/are not in WHERE; chains present: ..."
// when some of `requested` are not in `present`.
void check_chains_present(const std::vector<std::string>& requested,
                          const std::vector<std::string>& present, const std::string& name,
                          const std::string& where);
// Applies options.chains, then options.select, to atoms read line by line (PQR, XYZRN, XYZR):
// throws Error(InvalidArgument) when the input lacks what they need (chain ids, metadata), and
// Error(EmptySelection) when nothing is left.
void filter_read_atoms(Structure& s, const ReadOptions& options, const std::string& name);

// --- read_gemmi.cpp and read_plain.cpp: one reader per format; `text` passed check_text ---

// Every model (options.model == kAllModels) or options.model alone; the model number and the
// assembly option were checked to be >= 0.
std::vector<Structure> read_pdb_or_mmcif(std::string_view text, const std::string& name,
                                         StructureFormat format, const ReadOptions& options);
Structure read_pqr(std::string_view text, const std::string& name);
Structure read_xyzr(std::string_view text, const std::string& name);
Structure read_xyzrn(std::string_view text, const std::string& name);
// Those read pieces of about 1 MiB of whole lines on all threads, each written in place
// (read_*_pieces); read_*_plain, one pass on one thread, is their reference, with the same atoms,
// warnings and first error (the tests cut small texts into many pieces).
Structure read_pqr_plain(std::string_view text, const std::string& name);
Structure read_xyzr_plain(std::string_view text, const std::string& name);
Structure read_xyzrn_plain(std::string_view text, const std::string& name);
Structure read_pqr_pieces(std::string_view text, const std::string& name, std::size_t piece);
Structure read_xyzr_pieces(std::string_view text, const std::string& name, std::size_t piece);
Structure read_xyzrn_pieces(std::string_view text, const std::string& name, std::size_t piece);

}  // namespace fdmsurf::detail
