// Areas files: one CSV table (a row per atom, residue, buried group and the total) or one JSON
// object, written atomically (layouts: docs/areas.md).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

#include "base/json_text.hpp"
#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "io/atomic_file.hpp"

namespace fdmsurf {

namespace {

using detail::csv_field;

std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

std::string number(double value, int decimals = 4) {
    if (!std::isfinite(value)) return "";
    char text[64];
    // Beyond 1e15 (a radius of 1e30 Å reads), fixed notation would pass the buffer: exponent.
    if (std::fabs(value) >= 1e15) {
        std::snprintf(text, sizeof text, "%.*e", decimals + 6, value);
        return text;
    }
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    // "-0.0000" reads oddly
    if (std::string_view(text).find_first_not_of("-0.") == std::string_view::npos)
        std::snprintf(text, sizeof text, "%.*f", decimals, 0.0);
    return text;
}

std::string icode(char c) { return c == ' ' ? std::string() : std::string(1, c); }

const char* surface_name(SurfaceKind kind) {
    return kind == SurfaceKind::Ses ? "ses" : kind == SurfaceKind::Vdw ? "vdw" : "sas";
}

// The group (1 or 2, 0 none) of atom i of the report's atoms, and its area alone.
struct BuriedView {
    const BuriedAreas* b;
    int group(std::size_t i) const { return b ? b->group[b->complex_atoms[i]] : 0; }
    std::string name(std::size_t i) const {
        const int g = group(i);
        return g == 0 ? std::string() : b->names[g - 1];
    }
};

void check(const AreasReport& r) {
    if (r.atoms == nullptr || r.areas == nullptr)
        throw Error(ErrorCode::InvalidArgument, "write_areas: no atoms or areas");
    const std::size_t n = r.atoms->size();
    if (r.areas->area.size() != n ||
        (!r.areas->mesh_area.empty() && r.areas->mesh_area.size() != n))
        throw Error(ErrorCode::InvalidArgument, "write_areas: one area per atom needed");
    if (r.buried && (r.buried->complex.size() != n || r.buried->alone.area.size() != n))
        throw Error(ErrorCode::InvalidArgument,
                    "write_areas: the buried areas are not of the report's atoms");
}

void write_csv(const AreasReport& r, detail::AtomicFile& out) {
    const Atoms& atoms = *r.atoms;
    const AtomAreas& a = *r.areas;
    const bool mesh = !a.mesh_area.empty();
    const bool meta = atoms.meta.size() == atoms.size();
    const BuriedView bv{r.buried};
    out.write(
        "record,atom,serial,chain,residue_number,insertion_code,residue_name,atom_name,element,"
        "x,y,z,radius,group,area,mesh_area,relative_area,area_alone,buried_area\n");
    std::string line;
    auto buried_cells = [&](double alone, double in_complex) {
        return r.buried ? number(alone) + "," + number(alone - in_complex) : std::string(",");
    };
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        line = "atom," + std::to_string(i) + ",";
        if (meta) {
            const AtomMeta& m = atoms.meta[i];
            line += std::to_string(m.serial) + ",";
            if (!m.in_residue)  // an XYZRN name of another form than MSMS's
                line += ",,,,";
            else
                line += csv_field(m.chain) + "," + std::to_string(m.residue_number) + "," +
                        csv_field(icode(m.insertion_code)) + "," + csv_field(m.residue_name) + ",";
            line += csv_field(m.name) + ",";
        } else {
            line += ",,,,,,";
        }
        line += (atoms.element.size() == atoms.size() ? csv_field(atoms.element[i]) : "") + ",";
        for (int q = 0; q < 3; ++q) line += number(atoms.xyz[3 * i + q], 3) + ",";
        line += number(atoms.radius[i], 3) + "," + csv_field(bv.name(i)) + ",";
        line += number(a.area[i]) + "," + (mesh ? number(a.mesh_area[i]) : "") + ",,";
        line += buried_cells(r.buried ? r.buried->alone.area[i] : 0.0, a.area[i]) + "\n";
        out.write(line);
    }
    if (r.residues) {
        for (const ResidueArea& res : *r.residues) {
            double alone = 0.0;
            if (r.buried)
                for (std::uint32_t i : res.atoms) alone += r.buried->alone.area[i];
            line = "residue,,," + csv_field(res.chain) + "," + std::to_string(res.number) + "," +
                   csv_field(icode(res.insertion_code)) + "," + csv_field(res.name) + ",,,,,,," +
                   csv_field(res.atoms.empty() ? std::string() : bv.name(res.atoms.front())) + "," +
                   number(res.area) + "," + (mesh ? number(res.mesh_area) : "") + "," +
                   (res.relative >= 0.0 ? number(res.relative) : "") + "," +
                   buried_cells(alone, res.area) + "\n";
            out.write(line);
        }
    }
    double total = 0.0, mesh_total = 0.0;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        total += a.area[i];
        if (mesh) mesh_total += a.mesh_area[i];
    }
    if (r.buried) {
        const BuriedAreas& b = *r.buried;
        for (int g = 0; g < 2; ++g) {
            line = "group,,,,,,,,,,,,," + csv_field(b.names[g]) + "," +
                   number(b.area_in_complex[g]) + "," +
                   (mesh ? number(b.mesh_area_in_complex[g]) : "") + ",," +
                   buried_cells(b.area_alone[g], b.area_in_complex[g]) + "\n";
            out.write(line);
        }
    }
    line = "total,,,,,,,,,,,,,," + number(total) + "," + (mesh ? number(mesh_total) : "") + ",," +
           (r.buried ? buried_cells(r.buried->area_alone[0] + r.buried->area_alone[1], total)
                     : std::string(",")) +
           "\n";
    out.write(line);
}

// A number for the JSON file: null where the CSV leaves the field empty (not finite).
std::string json_number(double value, int decimals = 4) {
    const std::string text = number(value, decimals);
    return text.empty() ? "null" : text;
}

// The JSON file's settings and totals, from its opening brace.
std::string json_header(const AreasReport& r) {
    const Atoms& atoms = *r.atoms;
    const AtomAreas& a = *r.areas;
    const bool mesh = !a.mesh_area.empty();
    const SurfaceOptions& s = r.surface;
    double total = 0.0, mesh_total = 0.0;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        total += a.area[i];
        if (mesh) mesh_total += a.mesh_area[i];
    }
    std::string j = "{\n";
    j += "  \"fdmsurf\": " + detail::json_quote(version()) + ",\n";
    j += "  \"input\": " + detail::json_quote(r.input) + ",\n";
    j += "  \"mesh\": " + (r.has_mesh ? detail::json_quote(r.output) : std::string("null")) + ",\n";
    j += "  \"surface\": \"" + std::string(surface_name(s.surface)) + "\",\n";
    j += "  \"method\": " +
         (s.surface == SurfaceKind::Ses
              ? std::string(s.method == SesMethod::Edt ? "\"edt\"" : "\"fdm\"")
              : std::string("null")) +
         ",\n";
    j += "  \"probe\": " + json_number(s.probe, 4) + ",\n";
    j += "  \"spacing\": " + (r.has_mesh ? json_number(s.spacing, 4) : std::string("null")) + ",\n";
    j += "  \"area_method\": \"" +
         std::string(a.exact ? "exact sphere patches" : "mesh by vertex atom") + "\",\n";
    j += "  \"mesh_split\": " +
         std::string(!mesh     ? "null"
                     : a.exact ? "\"sphere patches, else vertex atoms\""
                               : "\"vertex atoms\"") +
         ",\n";
    j += "  \"relative_table\": " +
         (r.relative == RelativeTable::None ? std::string("null")
                                            : detail::json_quote(to_string(r.relative))) +
         ",\n";
    j += "  \"total\": {\"area\": " + json_number(total) +
         ", \"mesh_area\": " + (mesh ? json_number(mesh_total) : "null") +
         ", \"mesh_area_on_patches\": " + (mesh && a.exact ? json_number(a.mesh_on_patches) : "null") +
         ", \"atoms\": " + std::to_string(atoms.size()) +
         ", \"residues\": " + std::to_string(r.residues ? r.residues->size() : 0) + "},\n";
    return j;
}

// The JSON file's "buried" member (null without groups), with its line's end.
std::string json_buried(const AreasReport& r) {
    const bool mesh = !r.areas->mesh_area.empty();
    std::string j;
    if (r.buried) {
        const BuriedAreas& b = *r.buried;
        j += "  \"buried\": {\"groups\": [";
        for (int g = 0; g < 2; ++g) {
            j += std::string(g ? ", " : "") + "{\"name\": " + detail::json_quote(b.names[g]) +
                 ", \"atoms\": " + std::to_string(b.atom_count[g]) +
                 ", \"area_alone\": " + json_number(b.area_alone[g]) +
                 ", \"area_in_complex\": " + json_number(b.area_in_complex[g]) +
                 ", \"buried_area\": " + json_number(b.area_alone[g] - b.area_in_complex[g]) +
                 ", \"mesh_area_alone\": " + (mesh ? json_number(b.mesh_area_alone[g]) : "null") +
                 ", \"mesh_area_in_complex\": " +
                 (mesh ? json_number(b.mesh_area_in_complex[g]) : "null") + "}";
        }
        j += "], \"buried_area\": " + json_number(b.buried()) +
             ", \"mesh_buried_area\": " + (mesh ? json_number(b.mesh_buried()) : "null") + "},\n";
    } else {
        j += "  \"buried\": null,\n";
    }
    return j;
}

// The JSON file's residues, one a line, into `out` (nothing without residues).
void write_json_residues(const AreasReport& r, detail::AtomicFile& out) {
    const bool mesh = !r.areas->mesh_area.empty();
    const BuriedView bv{r.buried};
    std::string j;
    if (r.residues) {
        bool first = true;
        for (const ResidueArea& res : *r.residues) {
            j = first ? "\n    " : ",\n    ";
            first = false;
            j += "{\"chain\": " + detail::json_quote(res.chain) +
                 ", \"number\": " + std::to_string(res.number) +
                 ", \"insertion_code\": " + detail::json_quote(icode(res.insertion_code)) +
                 ", \"name\": " + detail::json_quote(res.name) +
                 ", \"atoms\": " + std::to_string(res.atoms.size()) +
                 ", \"area\": " + json_number(res.area) +
                 ", \"mesh_area\": " + (mesh ? json_number(res.mesh_area) : "null") +
                 ", \"max_area\": " + (res.max_area > 0 ? json_number(res.max_area, 1) : "null") +
                 ", \"relative_area\": " + (res.relative >= 0 ? json_number(res.relative) : "null");
            if (r.buried) {
                double alone = 0.0;
                for (std::uint32_t i : res.atoms) alone += r.buried->alone.area[i];
                j += ", \"group\": " +
                     detail::json_quote(res.atoms.empty() ? std::string()
                                                          : bv.name(res.atoms.front())) +
                     ", \"area_alone\": " + json_number(alone) +
                     ", \"buried_area\": " + json_number(alone - res.area);
            }
            j += "}";
            out.write(j);
        }
        if (!first) out.write("\n  ");
    }
}

// The JSON file's atoms, one a line, into `out`.
void write_json_atoms(const AreasReport& r, detail::AtomicFile& out) {
    const Atoms& atoms = *r.atoms;
    const AtomAreas& a = *r.areas;
    const bool mesh = !a.mesh_area.empty();
    const bool meta = atoms.meta.size() == atoms.size();
    const BuriedView bv{r.buried};
    std::string j;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        j = i ? ",\n    " : "\n    ";
        j += "{\"index\": " + std::to_string(i);
        if (meta) {
            const AtomMeta& m = atoms.meta[i];
            j += ", \"serial\": " + std::to_string(m.serial) +
                 ", \"name\": " + detail::json_quote(m.name);
            if (m.in_residue)  // else an XYZRN name of another form than MSMS's
                j += ", \"chain\": " + detail::json_quote(m.chain) +
                     ", \"residue_number\": " + std::to_string(m.residue_number) +
                     ", \"insertion_code\": " + detail::json_quote(icode(m.insertion_code)) +
                     ", \"residue_name\": " + detail::json_quote(m.residue_name);
        }
        if (atoms.element.size() == atoms.size())
            j += ", \"element\": " + detail::json_quote(atoms.element[i]);
        j += ", \"xyz\": [" + json_number(atoms.xyz[3 * i], 3) + ", " + json_number(atoms.xyz[3 * i + 1], 3) +
             ", " + json_number(atoms.xyz[3 * i + 2], 3) + "]";
        j += ", \"radius\": " + json_number(atoms.radius[i], 3) + ", \"area\": " + json_number(a.area[i]) +
             ", \"mesh_area\": " + (mesh ? json_number(a.mesh_area[i]) : "null");
        if (r.buried) {
            const double alone = r.buried->alone.area[i];
            j += ", \"group\": " + detail::json_quote(bv.name(i)) +
                 ", \"area_alone\": " + json_number(alone) +
                 ", \"buried_area\": " + json_number(alone - a.area[i]);
        }
        j += "}";
        out.write(j);
    }
}

void write_json(const AreasReport& r, detail::AtomicFile& out) {
    out.write(json_header(r) + json_buried(r));
    out.write("  \"residues\": [");
    write_json_residues(r, out);
    out.write("],\n  \"atoms\": [");
    write_json_atoms(r, out);
    out.write(r.atoms->empty() ? "]\n}\n" : "\n  ]\n}\n");
}

}  // namespace

AreasFormat areas_format_for_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".csv") return AreasFormat::Csv;
    if (ext == ".json") return AreasFormat::Json;
    throw Error(ErrorCode::InvalidArgument, "areas file '" + path + "': " +
                                                (ext.empty() ? std::string("no extension")
                                                             : "unknown extension '" + ext + "'") +
                                                "; give FILE.csv or FILE.json");
}

void write_areas(const AreasReport& report, const std::string& path) {
    const AreasFormat format = areas_format_for_path(path);
    check(report);
    detail::AtomicFile out(path);
    if (format == AreasFormat::Csv)
        write_csv(report, out);
    else
        write_json(report, out);
    out.commit();
}

}  // namespace fdmsurf
