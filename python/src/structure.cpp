// fdmsurf.Structure and the readers: atoms as numpy arrays, their metadata as numpy arrays of
// str, int and float (one entry per atom, in input order: the order SurfaceResult.atoms indexes).
#include <algorithm>
#include <cctype>
#include <cmath>

#include "objects.hpp"

namespace fdmsurf::python {

using namespace pybind11::literals;

std::string path_argument(py::handle path) {
    const py::bytes encoded = py::module_::import("os").attr("fsencode")(path);
    std::string bytes = encoded;
    if (bytes.find('\0') != std::string::npos) throw py::value_error("embedded null byte");
    return bytes;
}

std::string type_name(py::handle value) {
    return py::str(value.get_type().attr("__name__"));
}

py::str text(const std::string& value) {
    PyObject* decoded = PyUnicode_DecodeUTF8(value.data(), py::ssize_t(value.size()), "replace");
    if (decoded == nullptr) throw py::error_already_set();
    return py::reinterpret_steal<py::str>(decoded);
}

py::list text_list(const std::vector<std::string>& values) {
    py::list items(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) items[i] = text(values[i]);
    return items;
}

py::array string_array(const std::vector<std::string>& values) {
    return py::module_::import("numpy").attr("array")(text_list(values), "dtype"_a = "U");
}

namespace {

// An array of real numbers as float32, C order; wrong kinds are a TypeError naming `what`.
py::array_t<float, py::array::c_style | py::array::forcecast> floats(py::handle object,
                                                                     const char* what) {
    py::array array = py::array::ensure(object);
    if (!array) throw py::type_error(std::string(what) + " must be an array of numbers");
    const char kind = array.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw py::type_error(std::string(what) + " must hold real numbers, not dtype " +
                             std::string(py::str(array.dtype())));
    return py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
}

[[noreturn]] void invalid(const std::string& message) {
    throw Error(ErrorCode::InvalidArgument, message);
}

std::string shape_of(const py::array& a) {
    std::string text = "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
    return text + (a.ndim() == 1 ? ",)" : ")");
}

// Atoms from numpy: xyz (N, 3) and radii (N,) of any real dtype (stored as float32, Å),
// every coordinate finite, every radius positive; element: None or N symbols.
Atoms atoms_from_arrays(py::handle xyz_object, py::handle radii_object, py::handle element) {
    const auto xyz = floats(xyz_object, "xyz");
    const auto radii = floats(radii_object, "radii");
    if (xyz.ndim() != 2 || xyz.shape(1) != 3)
        invalid("xyz must have shape (N, 3), not " + shape_of(xyz));
    if (radii.ndim() != 1) invalid("radii must have shape (N,), not " + shape_of(radii));
    if (radii.shape(0) != xyz.shape(0))
        invalid("xyz has " + std::to_string(xyz.shape(0)) + " atoms but radii " +
                std::to_string(radii.shape(0)));
    const std::size_t n = std::size_t(radii.shape(0));
    Atoms atoms;
    atoms.xyz.assign(xyz.data(), xyz.data() + 3 * n);
    atoms.radius.assign(radii.data(), radii.data() + n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(atoms.xyz[3 * i + k]))
                invalid("xyz[" + std::to_string(i) + "] is not finite (" +
                        std::to_string(atoms.xyz[3 * i + k]) + "): every coordinate must be");
        if (!(atoms.radius[i] > 0.0f) || !std::isfinite(atoms.radius[i]))
            invalid("radii[" + std::to_string(i) + "] is " + std::to_string(atoms.radius[i]) +
                    ": radii must be positive and finite (Å)");
    }
    if (!element.is_none()) {
        if (py::isinstance<py::str>(element))
            throw py::type_error("element must be a sequence of element symbols, not a str");
        std::vector<std::string> symbols;
        for (py::handle item : element) {
            if (py::isinstance<py::bytes>(item))  // np.array([b"C"]) holds np.bytes_
                symbols.push_back(std::string(py::reinterpret_borrow<py::bytes>(item)));
            else if (py::isinstance<py::str>(item))
                symbols.push_back(item.cast<std::string>());
            else
                throw py::type_error("element must hold element symbols (str or bytes), not " +
                                     type_name(item));
        }
        if (symbols.size() != n)
            invalid("element has " + std::to_string(symbols.size()) + " entries for " +
                    std::to_string(n) + " atoms");
        for (std::string& s : symbols)
            for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
        atoms.element = std::move(symbols);
    }
    return atoms;
}

PyStructure wrap(Structure structure) {
    return PyStructure{std::make_shared<Structure>(std::move(structure)), py::dict()};
}

// `array` made read-only: the metadata is the file's, and the library reads its own copy (an
// edit would show in the array and change nothing).
py::object read_only(py::object array) {
    array.attr("setflags")("write"_a = false);
    return array;
}

// One per-atom field of the metadata as a numpy array; None when the atoms have none (XYZR,
// or atoms from arrays).
template <class T, class Get>
py::object meta_numbers(PyStructure& s, const char* key, Get get) {
    if (s.metadata.contains(key)) return s.metadata[key];
    const auto& meta = s.data->atoms.meta;
    py::object out = py::none();
    if (!meta.empty()) {
        py::array_t<T> array(py::ssize_t(meta.size()));
        T* p = array.mutable_data();
        for (std::size_t i = 0; i < meta.size(); ++i) p[i] = static_cast<T>(get(meta[i]));
        out = read_only(array);
    }
    s.metadata[key] = out;
    return out;
}

template <class Get>
py::object meta_strings(PyStructure& s, const char* key, Get get) {
    if (s.metadata.contains(key)) return s.metadata[key];
    const auto& meta = s.data->atoms.meta;
    py::object out = py::none();
    if (!meta.empty()) {
        std::vector<std::string> values(meta.size());
        for (std::size_t i = 0; i < meta.size(); ++i) values[i] = get(meta[i]);
        out = read_only(string_array(values));
    }
    s.metadata[key] = out;
    return out;
}

py::dict info_dict(const StructureInfo& info) {
    py::dict d;
    d["format"] = to_string(info.format);
    d["atoms_in_file"] = info.atoms_in_file;
    d["waters_skipped"] = info.waters_skipped;
    d["hydrogens_skipped"] = info.hydrogens_skipped;
    d["ligands_skipped"] = info.ligands_skipped;
    d["altlocs_skipped"] = info.altlocs_skipped;
    d["models_in_file"] = info.models_in_file;
    d["model"] = info.model;
    d["assemblies_in_file"] = info.assemblies_in_file;
    d["assembly"] = info.assembly;
    d["assembly_name"] = text(info.assembly_name);
    d["assembly_operators"] = info.assembly_operators;
    d["assembly_chains"] = info.assembly_chains;
    d["warnings"] = text_list(info.warnings);
    return d;
}

// The atoms whose mask entry is true, as a new Structure (its info kept).
PyStructure subset_of(const PyStructure& s, py::handle mask_object) {
    py::array mask = py::array::ensure(mask_object);
    if (!mask || mask.dtype().kind() != 'b')
        throw py::type_error("mask must be an array of bool, one per atom");
    const auto m = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(mask);
    if (m.ndim() != 1 || std::size_t(m.shape(0)) != s.data->atoms.size())
        invalid("mask must have shape (" + std::to_string(s.data->atoms.size()) + ",), not " +
                shape_of(m));
    std::vector<std::uint8_t> keep(m.data(), m.data() + m.shape(0));
    Structure out;
    out.atoms = subset(s.data->atoms, keep);
    out.info = s.data->info;
    return wrap(std::move(out));
}

PyStructure select_in(const PyStructure& s, const std::string& expr) {
    std::vector<std::uint8_t> keep;
    {
        py::gil_scoped_release release;
        keep = match_selection(s.data->atoms, expr, s.data->info.model);
    }
    Structure out;
    out.atoms = subset(s.data->atoms, keep);
    out.info = s.data->info;
    return wrap(std::move(out));
}

std::vector<std::string> chains_of(const PyStructure& s) {
    std::vector<std::string> chains;
    for (const AtomMeta& a : s.data->atoms.meta)
        if (chains.empty() || chains.back() != a.chain)
            if (std::find(chains.begin(), chains.end(), a.chain) == chains.end())
                chains.push_back(a.chain);
    return chains;
}

std::string repr(const PyStructure& s) {
    const Structure& d = *s.data;
    std::string text = "<fdmsurf.Structure: " + std::to_string(d.atoms.size()) + " atoms";
    if (!d.atoms.meta.empty()) text += ", " + std::to_string(chains_of(s).size()) + " chain(s)";
    if (d.info.format != StructureFormat::Auto)
        text +=
            ", " + std::string(to_string(d.info.format)) + " model " + std::to_string(d.info.model);
    return text + ">";
}

}  // namespace

void bind_structure(py::module_& m) {
    py::class_<PyStructure>(m, "Structure", R"(Atoms (centres and radii, Å) and their metadata.

Made by read_structure / read_models / parse_structure, or from numpy arrays:
``Structure(xyz, radii, element=None)`` with xyz of shape (N, 3) and radii of shape (N,), any
real dtype (kept as float32); element, when given, is one symbol per atom (for colouring by
element). xyz and radii are views of the structure's own memory: editing them in place moves
the atoms of the surfaces computed afterwards. Per-atom metadata (chain, residue_name, ...)
are numpy arrays in atom order, or None for atoms without metadata (XYZR input, arrays).)")
        .def(py::init([](py::handle xyz, py::handle radii, py::handle element) {
                 Structure s;
                 s.atoms = atoms_from_arrays(xyz, radii, element);
                 return wrap(std::move(s));
             }),
             py::arg("xyz"), py::arg("radii"), py::arg("element") = py::none())
        .def("__len__", [](const PyStructure& s) { return s.data->atoms.size(); })
        .def("__repr__", &repr)
        .def_property_readonly(
            "xyz",
            [](PyStructure& s) {
                auto& v = s.data->atoms.xyz;
                return share(s.data, v.data(), {py::ssize_t(v.size() / 3), 3});
            },
            "Atom centres, (N, 3) float32, Å (a view: edits change the structure).")
        .def_property_readonly(
            "radii",
            [](PyStructure& s) {
                auto& v = s.data->atoms.radius;
                return share(s.data, v.data(), {py::ssize_t(v.size())});
            },
            "Atom radii, (N,) float32, Å (a view: edits change the structure).")
        .def_property_readonly(
            "element",
            [](PyStructure& s) -> py::object {
                if (s.metadata.contains("element")) return s.metadata["element"];
                py::object out = py::none();
                const auto& element = s.data->atoms.element;
                if (std::any_of(element.begin(), element.end(),
                                [](const std::string& e) { return !e.empty(); }))
                    out = read_only(string_array(element));
                s.metadata["element"] = out;
                return out;
            },
            "Upper-case element symbols, (N,) str, or None (XYZR, or arrays without element=).")
        .def_property_readonly(
            "name",
            [](PyStructure& s) {
                return meta_strings(s, "name", [](const AtomMeta& a) { return a.name; });
            },
            "Atom names ('CA'), (N,) str, or None.")
        .def_property_readonly(
            "residue_name",
            [](PyStructure& s) {
                return meta_strings(s, "residue_name",
                                    [](const AtomMeta& a) { return a.residue_name; });
            },
            "Residue names ('LYS'), (N,) str, or None.")
        .def_property_readonly(
            "residue_number",
            [](PyStructure& s) {
                return meta_numbers<std::int32_t>(
                    s, "residue_number", [](const AtomMeta& a) { return a.residue_number; });
            },
            "Author residue numbers, (N,) int32, or None.")
        .def_property_readonly(
            "insertion_code",
            [](PyStructure& s) {
                return meta_strings(s, "insertion_code", [](const AtomMeta& a) {
                    return a.insertion_code == ' ' ? std::string()
                                                   : std::string(1, a.insertion_code);
                });
            },
            "Insertion codes ('' when none), (N,) str, or None.")
        .def_property_readonly(
            "chain",
            [](PyStructure& s) {
                return meta_strings(s, "chain", [](const AtomMeta& a) { return a.chain; });
            },
            "Author chain ids (in an assembly, the copies' names), (N,) str, or None.")
        .def_property_readonly(
            "serial",
            [](PyStructure& s) {
                return meta_numbers<std::int32_t>(s, "serial",
                                                  [](const AtomMeta& a) { return a.serial; });
            },
            "Atom serial numbers, (N,) int32, or None.")
        .def_property_readonly(
            "hetero",
            [](PyStructure& s) {
                return meta_numbers<bool>(s, "hetero", [](const AtomMeta& a) { return a.hetero; });
            },
            "True for HETATM records, (N,) bool, or None.")
        .def_property_readonly(
            "b_factor",
            [](PyStructure& s) {
                return meta_numbers<float>(s, "b_factor",
                                           [](const AtomMeta& a) { return a.b_factor; });
            },
            "B-factors, (N,) float32, Å², or None.")
        .def_property_readonly(
            "occupancy",
            [](PyStructure& s) {
                return meta_numbers<float>(s, "occupancy",
                                           [](const AtomMeta& a) { return a.occupancy; });
            },
            "Occupancies, (N,) float32, or None.")
        .def_property_readonly(
            "charge",
            [](PyStructure& s) {
                return meta_numbers<float>(s, "charge", [](const AtomMeta& a) { return a.charge; });
            },
            "Charges, (N,) float32, e (PQR: partial charges; PDB/mmCIF: formal), or None.")
        .def_property_readonly(
            "xyzrn_name",
            [](PyStructure& s) {
                return meta_strings(s, "xyzrn_name",
                                    [](const AtomMeta& a) { return a.xyzrn_name; });
            },
            "XYZRN input: the name field as read, (N,) str, or None.")
        .def_property_readonly(
            "chains", [](const PyStructure& s) { return text_list(chains_of(s)); },
            "Distinct chain ids in order of appearance (empty without metadata).")
        .def_property_readonly(
            "info", [](const PyStructure& s) { return info_dict(s.data->info); },
            "What the reader did: format, atoms_in_file, waters/hydrogens/ligands/altlocs_skipped, "
            "models_in_file, model, assemblies_in_file, assembly, assembly_name, "
            "assembly_operators, assembly_chains, warnings.")
        .def("subset", &subset_of, py::arg("mask"),
             "The atoms whose entry of the (N,) bool mask is true, in order, as a new Structure.")
        .def("select", &select_in, py::arg("expr"),
             "The atoms gemmi's selection `expr` matches ('A', 'A/10-50', '(HEM)', '[S]', "
             "';b>20'), as a new Structure. Raises InvalidArgumentError for bad syntax or atoms "
             "without metadata.");

    m.def(
        "_read_structure",
        [](py::handle path_object, const PyOptions& options) {
            const std::string path = path_argument(path_object);
            Structure s;
            {
                py::gil_scoped_release release;
                s = read_structure(path, options.read);
            }
            return wrap(std::move(s));
        },
        py::arg("path"), py::arg("options"));
    m.def(
        "_read_models",
        [](py::handle path_object, const PyOptions& options) {
            const std::string path = path_argument(path_object);
            std::vector<Structure> models;
            {
                py::gil_scoped_release release;
                models = read_models(path, options.read);
            }
            std::vector<PyStructure> out;
            for (Structure& s : models) out.push_back(wrap(std::move(s)));
            return out;
        },
        py::arg("path"), py::arg("options"));
    m.def(
        "_parse_structure",
        [](const std::string& text, const std::string& name, const PyOptions& options) {
            Structure s;
            {
                py::gil_scoped_release release;
                s = read_structure_from_memory(text, name, options.read);
            }
            return wrap(std::move(s));
        },
        py::arg("text"), py::arg("name"), py::arg("options"));
}

}  // namespace fdmsurf::python
